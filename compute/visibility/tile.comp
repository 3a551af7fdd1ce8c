// visibility.raster, step 4: one 16x16 workgroup per screen tile walks the
// tile's bin list; each thread tests its pixel against every triangle
// (Laine & Karras 2011 §4.4 fine raster, one pixel per thread).
// The list is read in batches: one thread follows the links, one thread per
// triangle of the batch sets it up (visUnpack, double precision) into shared
// memory, and then every pixel tests the batch. Set-up is paid once per tile
// and triangle instead of once per pixel (docs/visibility.md, "Cost").
#include "lib/raster.glsl"

layout(local_size_x = RTGI_VISIBILITY_TILE, local_size_y = RTGI_VISIBILITY_TILE) in;

layout(std430, binding = RTGI_VISIBILITY_SSBO_LARGE) readonly buffer Large { VisTriangle large[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_TILEHEADS) readonly buffer TileHeads { uint tileHead[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_NODES) readonly buffer Nodes { uvec2 nodes[]; };

const uint kBatch = 64u;  // triangles set up per round (<= the 256 threads of a tile)
shared uint sTriangle[kBatch];
shared VisRasterTri sSetup[kBatch];
shared bool sValid[kBatch];
shared uint sCount, sNext;

void main() {
    ivec2 tiles = (uSize + RTGI_VISIBILITY_TILE - 1) / RTGI_VISIBILITY_TILE;
    uint lane = gl_LocalInvocationIndex;
    if (lane == 0u) sNext = tileHead[gl_WorkGroupID.y * uint(tiles.x) + gl_WorkGroupID.x];
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    bool inTarget = all(lessThan(pixel, uSize));
    for (;;) {
        barrier();  // the previous batch is rasterized before its slots are reused
        if (lane == 0u) {
            uint node = sNext, n = 0u;
            for (; node != RTGI_VISIBILITY_EMPTY && n < kBatch; ++n) {
                uvec2 nd = nodes[node];
                sTriangle[n] = nd.x;
                node = nd.y;
            }
            sCount = n;
            sNext = node;
        }
        barrier();
        uint n = sCount;
        if (n == 0u) break;  // uniform: every thread read the same count
        if (lane < n) {
            VisRasterTri t;
            sValid[lane] = visUnpack(large[sTriangle[lane]], t);
            sSetup[lane] = t;
        }
        barrier();
        for (uint i = 0u; inTarget && i < n; ++i) {
            if (!sValid[i]) continue;
            ivec4 box = sSetup[i].box;
            if (any(lessThan(pixel, box.xy)) || any(greaterThan(pixel, box.zw))) continue;
            visRasterPixel(sSetup[i], pixel.x, pixel.y);
        }
    }
}
