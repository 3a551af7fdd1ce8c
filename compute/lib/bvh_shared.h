// BVH and reference-renderer structs and bindings shared by C++ and GLSL
// (std430). C++ includes this through src/scene/bvh.h (size-checked there).
#ifndef RTGI_BVH_SHARED_H
#define RTGI_BVH_SHARED_H

#ifdef RTGI_GLSL
#define RTGI_BVH_STRUCT(name) struct name
#else
#define RTGI_BVH_STRUCT(name) struct alignas(16) name
namespace rtgi::gpu {
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uint = std::uint32_t;
#endif

// SSBO bindings of the reference passes (after the shared 1 = materials, 2 = lights).
#define RTGI_SSBO_BVH_NODES 3      // BvhNode[]
#define RTGI_SSBO_BVH_TRIS 4       // BvhTriangle[] in BVH leaf order
#define RTGI_SSBO_REF_VERTICES 5   // GpuScene vertex buffer (GpuVertex, 9 words each)
#define RTGI_SSBO_REF_INDICES 6    // GpuScene index buffer (3 per original triangle)
#define RTGI_SSBO_REF_RAYS 7       // test rays (trace_test.comp)
#define RTGI_SSBO_REF_COUNTER 8    // uint: rays traced by a dispatch (rays/s statistics)
#define RTGI_SSBO_REF_EMITTERS 9   // uint pairs: emissive triangle id, area CDF (float bits)
#define RTGI_BVH_STACK 48          // traversal stack depth (the builder caps the tree depth below it)
// Conservative slab test (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013):
// the exit distance of a box is multiplied by 1 + 2^-20 = 1 + 16u (u = 2^-24).
// Each slab distance (b - o)·(1/d) is off by at most 3u on the CPU and 7u
// in GLSL (1/d may be off by 2.5 ulp); without the margin a ray through a
// box's edge or corner, such as a ray through a mesh edge lying on the
// boundary between two leaves, could miss both boxes (tests/unit/test_bvh.cpp
// watertightness: ~100 of 97k rays did).
#define RTGI_BVH_BOX_EXIT_SCALE 1.00000095367431640625f
#define RTGI_REF_LOCAL 8           // workgroup edge of the per-pixel reference kernels

// A node of the flattened tree: interior nodes (count == 0) keep their left
// child at `index`, the right child directly after it; leaves keep `count`
// triangles starting at `index` in the BvhTriangle array.
RTGI_BVH_STRUCT(BvhNode) {
    vec3 lo;
    uint index;
    vec3 hi;
    uint count;
};

// Triangle in leaf order as its three vertices, not v0 and two edges: the
// watertight test (bvh.glsl bvhTriangle) needs a vertex shared by two
// triangles to be the same floats in both. v0.w holds the original triangle
// id (as uint bits), which indexes the GpuScene index buffer.
RTGI_BVH_STRUCT(BvhTriangle) {
    vec4 v0;
    vec4 v1;  // w unused
    vec4 v2;  // w unused
};

#ifndef RTGI_GLSL
}  // namespace rtgi::gpu
#endif

// ---- slots of compute/ref/ (docs/architecture.md, "Binding slots") ----
// RTGI_<FAMILY>[_<PASS>]_<TEX|IMG|LOC|SSBO>_<ROLE>; the pass appears only where the
// family's passes give the same role different slots.
// texture units (sampler bindings)
#define RTGI_REF_AO_TEX_LINEAR_DEPTH   0  // ref/ao.comp
#define RTGI_REF_AO_TEX_NORMAL         1  // ref/ao.comp
#define RTGI_REF_PATH_TEX_LINEAR_DEPTH 1  // ref/path.comp
#define RTGI_REF_PATH_TEX_NORMAL       2  // ref/path.comp
#define RTGI_REF_TEX_ALBEDO            3  // ref/path.comp
#define RTGI_REF_TEX_MATERIAL          4  // ref/path.comp
#define RTGI_REF_TEX_EMISSIVE          5  // ref/path.comp
// image units
#define RTGI_REF_IMG_ACCUM    0  // ref/ao.comp ref/path.comp ref/resolve.comp ref/moments_test.comp
#define RTGI_REF_IMG_ACCUM_SQ 1  // ref/ao.comp ref/path.comp ref/resolve.comp ref/moments_test.comp
#define RTGI_REF_IMG_MEAN     2  // ref/resolve.comp
#define RTGI_REF_IMG_STD_ERR  3  // ref/resolve.comp
#define RTGI_REF_IMG_LDR      4  // ref/resolve.comp
// uniform locations
#define RTGI_REF_LOC_SAMPLES 0  // ref/ao.comp ref/path.comp ref/moments_test.comp (first sample, count, edge)
#define RTGI_REF_LOC_RAY     1  // ref/ao.comp: maximum ray length
#define RTGI_REF_LOC_EMITTERS 2 // ref/path.comp: emitter count, total emissive area
#define RTGI_REF_LOC_COUNT   0  // ref/trace_test.comp
#endif
