// visibility.raster, step 4: one 16x16 workgroup per screen tile tests its
// pixels against every triangle of the tile's bin (Laine & Karras 2011 §4.4
// fine raster, one pixel per thread): first the slot array, RTGI_VISIBILITY_TILE_BATCH
// records at a time loaded into shared memory by as many threads (independent
// loads), then the overflow list. The depth test is an atomic minimum, so the
// order of the triangles does not change the result.
#include "lib/raster.glsl"

layout(local_size_x = RTGI_VISIBILITY_TILE, local_size_y = RTGI_VISIBILITY_TILE) in;

layout(std430, binding = RTGI_VISIBILITY_SSBO_LARGE) readonly buffer Large { VisTriangle large[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_TILEHEADS) readonly buffer TileHeads { uint tileHead[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_NODES) readonly buffer Nodes { uvec2 nodes[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_TILESLOTS) readonly buffer TileSlots { uint tileSlot[]; };

shared VisTriangle sTri[RTGI_VISIBILITY_TILE_BATCH];

void main() {
    ivec2 tiles = (uSize + RTGI_VISIBILITY_TILE - 1) / RTGI_VISIBILITY_TILE;
    uint ti = gl_WorkGroupID.y * uint(tiles.x) + gl_WorkGroupID.x;
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    bool inTarget = all(lessThan(pixel, uSize));
    // The slots (the count is the same for the whole workgroup: the barriers are in uniform flow).
    uint inSlots = min(tileSlot[ti], uint(RTGI_VISIBILITY_TILE_SLOTS));
    uint slots = uint(tiles.x * tiles.y) + ti * uint(RTGI_VISIBILITY_TILE_SLOTS);
    for (uint b = 0u; b < inSlots; b += uint(RTGI_VISIBILITY_TILE_BATCH)) {
        uint m = min(uint(RTGI_VISIBILITY_TILE_BATCH), inSlots - b);
        if (gl_LocalInvocationIndex < m) sTri[gl_LocalInvocationIndex] = large[tileSlot[slots + b + gl_LocalInvocationIndex]];
        barrier();
        for (uint j = 0u; j < m && inTarget; ++j) {
            VisRasterTri t;
            if (!visUnpack(sTri[j], t)) continue;
            if (any(lessThan(pixel, t.box.xy)) || any(greaterThan(pixel, t.box.zw))) continue;
            visRasterPixel(t, pixel.x, pixel.y);
        }
        barrier();
    }
    uint node = tileHead[ti];
    // The list is a chain of dependent loads: the next node is fetched before this one's
    // triangle is tested, so its latency overlaps the test.
    uvec2 nd = node != RTGI_VISIBILITY_EMPTY ? nodes[node] : uvec2(0u, RTGI_VISIBILITY_EMPTY);
    while (node != RTGI_VISIBILITY_EMPTY) {
        uvec2 current = nd;
        node = current.y;
        if (node != RTGI_VISIBILITY_EMPTY) nd = nodes[node];
        if (!inTarget) continue;
        VisTriangle r = large[current.x];
        VisRasterTri t;
        if (!visUnpack(r, t)) continue;
        if (any(lessThan(pixel, t.box.xy)) || any(greaterThan(pixel, t.box.zw))) continue;
        visRasterPixel(t, pixel.x, pixel.y);
    }
}
