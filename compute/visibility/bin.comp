// visibility.raster, step 3: bins the large triangles into screen tiles
// (Laine & Karras 2011 §4.2-4.3, one level of bins). Persistent workgroups
// stride over the triangles; the threads of a group share one triangle and
// stride over the tiles of its box, so no thread walks a large box alone.
// A tile gets the triangle when no edge function is negative at the tile's
// most-inside sample (exact for the box, conservative inside it). A tile's first
// RTGI_VISIBILITY_TILE_SLOTS entries go to its slot array, the rest to its list.
#include "lib/raster.glsl"

layout(local_size_x = RTGI_VISIBILITY_BIN_GROUP) in;

layout(std430, binding = RTGI_VISIBILITY_SSBO_LARGE) readonly buffer Large { VisTriangle large[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_TILEHEADS) buffer TileHeads { uint tileHead[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_NODES) writeonly buffer Nodes { uvec2 nodes[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_COUNTERS) buffer Counters { VisCounters counters; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_TILESLOTS) buffer TileSlots { uint tileSlot[]; };

void main() {
    uint count = min(counters.largeCount, uint(uCapacity.x));
    ivec2 tiles = (uSize + RTGI_VISIBILITY_TILE - 1) / RTGI_VISIBILITY_TILE;
    for (uint tri = gl_WorkGroupID.x; tri < count; tri += gl_NumWorkGroups.x) {
        VisTriangle r = large[tri];
        VisRasterTri t;
        if (!visUnpack(r, t)) continue;
        ivec2 t0 = t.box.xy / RTGI_VISIBILITY_TILE, t1 = t.box.zw / RTGI_VISIBILITY_TILE;
        int w = t1.x - t0.x + 1, n = w * (t1.y - t0.y + 1);
        for (int k = int(gl_LocalInvocationIndex); k < n; k += RTGI_VISIBILITY_BIN_GROUP) {
            ivec2 tile = t0 + ivec2(k % w, k / w);
            // The tile's pixel range clipped to the triangle's box.
            ivec2 lo = max(tile * RTGI_VISIBILITY_TILE, t.box.xy), hi = min(tile * RTGI_VISIBILITY_TILE + RTGI_VISIBILITY_TILE - 1, t.box.zw);
            i64vec2 slo = visSample(lo.x, lo.y), shi = visSample(hi.x, hi.y);
            bool reject = false;
            for (int e = 0; e < 3; ++e) {
                int64_t px = t.A[e] > 0L ? shi.x : slo.x, py = t.B[e] > 0L ? shi.y : slo.y;
                reject = reject || t.A[e] * px + t.B[e] * py + t.C[e] + t.rule[e] < 0L;
            }
            if (reject) continue;
            uint ti = uint(tile.y * tiles.x + tile.x);
            uint slot = atomicAdd(tileSlot[ti], 1u);
            if (slot < uint(RTGI_VISIBILITY_TILE_SLOTS)) {
                tileSlot[uint(tiles.x * tiles.y) + ti * uint(RTGI_VISIBILITY_TILE_SLOTS) + slot] = tri;
                continue;
            }
            uint node = atomicAdd(counters.nodeCount, 1u);
            if (node >= uint(uCapacity.y)) continue;  // overflow: reported by the pass
            nodes[node] = uvec2(tri, atomicExchange(tileHead[ti], node));
        }
    }
}
