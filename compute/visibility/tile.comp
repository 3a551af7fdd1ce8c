// visibility.raster, step 4: one 16x16 workgroup per screen tile walks the
// tile's bin list; each thread tests its pixel against every triangle
// (Laine & Karras 2011 §4.4 fine raster, one pixel per thread).
#include "lib/raster.glsl"

layout(local_size_x = RTGI_VISIBILITY_TILE, local_size_y = RTGI_VISIBILITY_TILE) in;

layout(std430, binding = RTGI_VISIBILITY_SSBO_LARGE) readonly buffer Large { VisTriangle large[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_TILEHEADS) readonly buffer TileHeads { uint tileHead[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_NODES) readonly buffer Nodes { uvec2 nodes[]; };

void main() {
    ivec2 tiles = (uSize + RTGI_VISIBILITY_TILE - 1) / RTGI_VISIBILITY_TILE;
    uint node = tileHead[gl_WorkGroupID.y * uint(tiles.x) + gl_WorkGroupID.x];
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    bool inTarget = all(lessThan(pixel, uSize));
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
