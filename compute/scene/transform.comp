// scene.transform: the world-space positions and normals of the moving
// objects' vertices from their rest pose and one 4x3 matrix per object
// (GpuScene::setTransforms; docs/temporal.md, "Object motion"), written into
// the scene's vertex buffer, and (RTGI_SCENE_LOC_WRITE_PREVIOUS) the previous
// frame's positions into the previous-vertex buffer. Every later pass reads
// the vertex buffer as before.
// With RTGI_SCENE_COPY defined it is the copy that precedes the transform when
// the previous-vertex buffer needs the last rendered frame's whole geometry:
// uCount vertices, vertex buffer -> previous-vertex buffer. A shader copy, not
// glCopyNamedBufferSubData: the transform dispatch writes the buffer the copy
// reads, and on NVIDIA (driver 580) a buffer copy was not finished before a
// later dispatch's stores (the velocity of the hardware path read new
// positions as previous ones); between two dispatches a memory barrier orders it.
#include "lib/shared.h"
#include "lib/scene_shared.h"

layout(local_size_x = RTGI_SCENE_TRANSFORM_GROUP) in;

layout(std430, binding = RTGI_SCENE_SSBO_VERTICES) buffer SceneVertices { float vertexData[]; };
layout(std430, binding = RTGI_SCENE_SSBO_PREV_VERTICES) buffer ScenePrevVertices { float prevVertexData[]; };
layout(std430, binding = RTGI_SCENE_SSBO_MOVABLE) readonly buffer Movable { MovableVertex movable[]; };
layout(std430, binding = RTGI_SCENE_SSBO_TRANSFORMS) readonly buffer Transforms { ObjectTransform transforms[]; };
layout(location = RTGI_SCENE_LOC_COUNT) uniform uint uCount;
layout(location = RTGI_SCENE_LOC_WRITE_PREVIOUS) uniform int uWritePrevious;

vec3 apply(vec4 rows[3], vec4 p) { return vec3(dot(rows[0], p), dot(rows[1], p), dot(rows[2], p)); }

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uCount) return;
#ifdef RTGI_SCENE_COPY
    for (uint k = 0u; k < uint(RTGI_SCENE_VERTEX_FLOATS); ++k)
        prevVertexData[RTGI_SCENE_VERTEX_FLOATS * i + k] = vertexData[RTGI_SCENE_VERTEX_FLOATS * i + k];
#else
    MovableVertex mv = movable[i];
    uint v = floatBitsToUint(mv.positionVertex.w), o = floatBitsToUint(mv.normalObject.w);
    vec4 p = vec4(mv.positionVertex.xyz, 1.0);
    vec3 position = apply(transforms[o].current, p);
    vec3 n = apply(transforms[o].normal, vec4(mv.normalObject.xyz, 0.0));
    // A degenerate (zero-scale) transform keeps the rest normal, as the CPU does (transformVertices).
    float len = length(n);
    vec3 normal = len > 0.0 ? n / len : mv.normalObject.xyz;
    uint base = RTGI_SCENE_VERTEX_FLOATS * v;
    vertexData[base] = position.x;
    vertexData[base + 1] = position.y;
    vertexData[base + 2] = position.z;
    vertexData[base + 3] = normal.x;
    vertexData[base + 4] = normal.y;
    vertexData[base + 5] = normal.z;
    if (uWritePrevious != 0) {
        vec3 prev = apply(transforms[o].previous, p);
        prevVertexData[base] = prev.x;
        prevVertexData[base + 1] = prev.y;
        prevVertexData[base + 2] = prev.z;
    }
#endif
}
