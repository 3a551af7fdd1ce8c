// Per-object transforms of a moving scene (issue 23; GpuScene::setTransforms,
// compute/scene/transform.comp; docs/temporal.md, "Object motion"), shared by
// C++ and GLSL. Include it after "lib/shared.h" (RTGI_STRUCT; C++: through
// src/render/gpu_types.h, which size-checks the structs).
#ifndef RTGI_SCENE_SHARED_H
#define RTGI_SCENE_SHARED_H

// ---- storage buffers of scene/transform.comp ----------------------------------
#define RTGI_SCENE_SSBO_VERTICES 3       // GpuVertex[] read and written as float[9] each
#define RTGI_SCENE_SSBO_PREV_VERTICES 4  // GpuVertex[] of the previous frame (positions written)
#define RTGI_SCENE_SSBO_MOVABLE 5        // MovableVertex[]: object-space vertices of the objects that move
#define RTGI_SCENE_SSBO_TRANSFORMS 6     // ObjectTransform[], one per moving object
// ---- uniform locations ------------------------------------------------------------
#define RTGI_SCENE_LOC_COUNT 0           // uint: MovableVertex count
#define RTGI_SCENE_LOC_WRITE_PREVIOUS 1  // int: 1 = also write the previous positions
#define RTGI_SCENE_TRANSFORM_GROUP 64
#define RTGI_SCENE_VERTEX_FLOATS 9       // sizeof(GpuVertex) / 4

#ifndef RTGI_GLSL
namespace rtgi::gpu {
#endif

// One vertex of a moving object in its rest pose (the object space of its
// transforms) and where it lives in the scene's vertex buffer (std430: 32 bytes).
RTGI_STRUCT(MovableVertex) {
    vec4 positionVertex;  // xyz rest position, w = vertex index (uint bits)
    vec4 normalObject;    // xyz rest normal, w = object index (uint bits)
};

// A moving object's rest -> world transforms as rows of 4x3 matrices
// (p' = (dot(r0, p1), dot(r1, p1), dot(r2, p1)) for p1 = (p, 1)); the normal
// matrix is the inverse transpose of the linear part (row xyz; w unused).
RTGI_STRUCT(ObjectTransform) {
    vec4 current[3];
    vec4 normal[3];
    vec4 previous[3];  // the transform the previous rendered frame used
};

#ifndef RTGI_GLSL
}  // namespace rtgi::gpu
#endif

#endif
