// visibility.raster, step 1: empty visibility buffer, empty tile bins (lists and slot counts), zero counters.
#include "lib/raster.glsl"

layout(local_size_x = 256) in;

layout(std430, binding = RTGI_VISIBILITY_SSBO_TILEHEADS) writeonly buffer TileHeads { uint tileHead[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_COUNTERS) writeonly buffer Counters { VisCounters counters; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_TILESLOTS) writeonly buffer TileSlots { uint tileSlot[]; };

void main() {
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (i < visPixelCount()) visClear(i);
    ivec2 tiles = (uSize + RTGI_VISIBILITY_TILE - 1) / RTGI_VISIBILITY_TILE;
    if (i < uint(tiles.x * tiles.y)) {
        tileHead[i] = RTGI_VISIBILITY_EMPTY;
        tileSlot[i] = 0u;  // the tile's entry count
    }
    if (i == 0u) counters = VisCounters(0u, 0u, 0u, 0u);
}
