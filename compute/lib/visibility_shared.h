// Bindings, uniform locations and limits of the compute rasterizer
// (compute/visibility/, src/render/visibility/; docs/visibility.md), shared by
// C++ and GLSL. GLSL includes it as "lib/visibility_shared.h".
#ifndef RTGI_VISIBILITY_SHARED_H
#define RTGI_VISIBILITY_SHARED_H

// ---- storage buffers (materials 1 and lights 2 stay free for the resolve) ----
#define RTGI_VISIBILITY_SSBO_VERTICES 3   // GpuVertex[] read as float[9] each
#define RTGI_VISIBILITY_SSBO_INDICES 4    // uint[] (3 per triangle)
#define RTGI_VISIBILITY_SSBO_VISBUF 5     // visibility buffer: uint64 depth|id, or uint depth[N] then uint id[N]
#define RTGI_VISIBILITY_SSBO_LARGE 6      // VisTriangle[]: set-up triangles too large for direct rasterization
#define RTGI_VISIBILITY_SSBO_TILEHEADS 7  // uint per screen tile: first node of its bin list (~0 = empty)
#define RTGI_VISIBILITY_SSBO_NODES 8      // uvec2 per bin entry: (large triangle, next node)
#define RTGI_VISIBILITY_SSBO_COUNTERS 9   // VisCounters
#define RTGI_VISIBILITY_SSBO_HITS 10      // uint per pixel: fragments written (tests only, RTGI_VISIBILITY_COUNT_HITS)
#define RTGI_VISIBILITY_SSBO_PREV_VERTICES 11  // GpuVertex[] of the previous frame (visibility/resolve.comp: object motion)
#define RTGI_VISIBILITY_SSBO_TILESLOTS 12  // uint per tile: its bin entries; then RTGI_VISIBILITY_TILE_SLOTS large-triangle ids per tile
// ---- images written by the resolves --------------------------------------------
#define RTGI_VISIBILITY_IMG_LINEAR_DEPTH 0
#define RTGI_VISIBILITY_IMG_NORMAL 1
#define RTGI_VISIBILITY_IMG_ALBEDO 2
#define RTGI_VISIBILITY_IMG_MATERIAL 3
#define RTGI_VISIBILITY_IMG_EMISSIVE 4
#define RTGI_VISIBILITY_IMG_VELOCITY 5
#define RTGI_VISIBILITY_IMG_RSM_FLUX 0
#define RTGI_VISIBILITY_IMG_RSM_NORMAL 1
// ---- images of the second depth layer (RTGI_VISIBILITY_LAYER2: setup.comp and tile.comp) ----
#define RTGI_VISIBILITY_IMG_LAYER1 0      // r32f gbuffer.linearDepth (read)
#define RTGI_VISIBILITY_IMG_LAYER2 1      // gbuffer.linearDepth2 (R32F) as r32ui: atomicMin on positive float bits
// ---- uniform locations ------------------------------------------------------------
#define RTGI_VISIBILITY_LOC_VIEW_PROJ 0     // mat4 (locations 0..3): world -> clip of the rasterized view
#define RTGI_VISIBILITY_LOC_SIZE 4         // ivec2 target size in pixels
#define RTGI_VISIBILITY_LOC_TRIANGLES 5    // int triangle count
#define RTGI_VISIBILITY_LOC_PHASE 6        // int: 32-bit path phase (0 depth, 1 id); 64-bit path: always 0
#define RTGI_VISIBILITY_LOC_FLAGS 7        // int: RTGI_VISIBILITY_FLAG_*
#define RTGI_VISIBILITY_LOC_CAPACITY 8     // ivec2 (large-triangle capacity, bin-node capacity)
#define RTGI_VISIBILITY_LOC_RSM_LIGHT 9    // visibility/rsm_resolve.comp (RTGI_RSM_LOCAL): vec4[4] GpuLight, locations 9-12
#define RTGI_VISIBILITY_LOC_RSM_FACE 13    // visibility/rsm_resolve.comp (RTGI_RSM_LOCAL): vec2 tan(half fov), RSM side
#define RTGI_VISIBILITY_LOC_LAYER2 14     // RTGI_VISIBILITY_LAYER2: vec4 (separation, 1 = x first-layer depth, P[2][2], P[3][2])
#define RTGI_VISIBILITY_FLAG_DEPTH_BIAS 1  // glPolygonOffset(1.5, 2) of the shadow map
#define RTGI_VISIBILITY_FLAG_CULL_BACK 2   // back-face culling (off for every view today: scenes may be open)

// ---- fixed limits ---------------------------------------------------------------------
#define RTGI_VISIBILITY_SUBPIXEL_BITS 8  // 1/256 pixel vertex snapping, as the hardware (and llvmpipe) does
#define RTGI_VISIBILITY_TILE 16          // screen tile side (one 16x16 workgroup rasterizes one tile)
#define RTGI_VISIBILITY_SMALL 8          // triangles whose pixel box is at most 8x8 are rasterized by their setup thread
#define RTGI_VISIBILITY_SETUP_GROUP 64
#define RTGI_VISIBILITY_BIN_GROUP 64
#define RTGI_VISIBILITY_BIN_GROUPS 2048  // persistent bin workgroups (grid-stride over the large triangles)
// A tile's first RTGI_VISIBILITY_TILE_SLOTS bin entries go to an array of its own (the rest to the linked
// list of nodes), which the tile workgroup reads RTGI_VISIBILITY_TILE_BATCH records at a time into shared
// memory: independent loads instead of a chain of dependent ones (docs/visibility.md, "Tile slots").
#define RTGI_VISIBILITY_TILE_SLOTS_DEFAULT 64
#define RTGI_VISIBILITY_TILE_BATCH 16
#if defined(RTGI_GLSL) && !defined(RTGI_VISIBILITY_TILE_SLOTS)
#define RTGI_VISIBILITY_TILE_SLOTS RTGI_VISIBILITY_TILE_SLOTS_DEFAULT  // the kernels get the target's count as a define
#endif
// Guard band in pixels: vertices are clipped to |x|,|y| <= this many pixels
// around the viewport so that 8-bit fixed point and the edge products fit
// (positions < 2^23 sub-pixel units, products < 2^47 in int64).
#define RTGI_VISIBILITY_GUARD_BAND 32768.0
#define RTGI_VISIBILITY_EMPTY 0xffffffffu

// Counters (std430), read back once for stats and overflow checks.
#ifdef RTGI_GLSL
struct VisCounters {
#else
struct VisCounters {
    using uint = std::uint32_t;
#endif
    uint largeCount;     // large triangles appended (may exceed the capacity: then overflow)
    uint nodeCount;      // bin entries appended
    uint smallCount;     // triangles rasterized directly by setup
    uint culledCount;    // triangles culled in setup (back-face, frustum, zero area, no sample)
};

#endif
