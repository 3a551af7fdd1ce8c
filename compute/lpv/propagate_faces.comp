// lpv.propagate with lpv.propagate_kernel=face (the default; docs/lpv.md, "Per-face propagation
// kernel"): one step, one invocation per (destination cell, neighbour face, colour) instead of one
// per cell. A small volume (2 x 16^3 cells) gives the per-cell kernel only 64 workgroups, and each
// invocation's 6 x 3 gathers run one after another: the dispatch costs the latency of that chain.
// Here a workgroup holds RTGI_LPV_FACE_CELLS cells x 6 faces x 3 colours; x runs over the cells, so a
// subgroup shares its face and colour (no divergence, the same geometry texels). Each invocation
// computes lpvFaceColour (lpv/propagate.glsl) of its face and colour, and the (face 0) invocation of
// each cell and colour sums the 6 terms in the per-cell kernel's order, stores the step and adds it
// to accum: the same arithmetic as lpvGather. Band 1, per cascade (not joint, not fused).
#include "lpv/propagate.glsl"
#include "lib/lpv_shared.h"

layout(local_size_x = RTGI_LPV_FACE_CELLS, local_size_y = 6, local_size_z = 3) in;

layout(binding = RTGI_LPV_TEX_SRC_R) uniform sampler3D uSrcR;
layout(binding = RTGI_LPV_TEX_SRC_G) uniform sampler3D uSrcG;
layout(binding = RTGI_LPV_TEX_SRC_B) uniform sampler3D uSrcB;
layout(binding = RTGI_LPV_TEX_GEOMETRY) uniform sampler3D uGeometry;
layout(binding = RTGI_LPV_TEX_GEOMETRY_ALBEDO) uniform sampler3D uGeometryAlbedo;
layout(binding = RTGI_LPV_TEX_GEOMETRY_AXES) uniform sampler3D uGeometryAxes;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_R) uniform writeonly image3D uDstR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_G) uniform writeonly image3D uDstG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_B) uniform writeonly image3D uDstB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_ACCUM_R) uniform image3D uAccumR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_ACCUM_G) uniform image3D uAccumG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_ACCUM_B) uniform image3D uAccumB;

layout(location = RTGI_LPV_LOC_ITERATION) uniform int uIteration;

shared vec4 sTerm[3][6][RTGI_LPV_FACE_CELLS];

// Colour ch of source cell p (ch is uniform in a subgroup: the branch does not diverge).
vec4 lpvSourceColour(int ch, ivec3 p) {
    if (ch == 0) return texelFetch(uSrcR, p, 0);
    if (ch == 1) return texelFetch(uSrcG, p, 0);
    return texelFetch(uSrcB, p, 0);
}

void main() {
    ivec3 dims = lpv.grid.xyz;
    int x = int(gl_LocalInvocationID.x), a = int(gl_LocalInvocationID.y), ch = int(gl_LocalInvocationID.z);
    int i = int(gl_WorkGroupID.x) * RTGI_LPV_FACE_CELLS + x;
    ivec3 c = ivec3(i % dims.x, (i / dims.x) % dims.y, i / (dims.x * dims.y));
    bool inside = i < dims.x * dims.y * dims.z;
    vec4 term = vec4(0.0);
    if (inside && lpvInside(c + LPV_AXES[a], dims)) {
        LpvFaceTerms f = lpvFaceTerms(c, a, lpvGeometryActive(uIteration), uGeometry, uGeometryAlbedo, uGeometryAxes);
        vec4 own = f.reflectedOwn[ch] > 0.0 ? lpvOwnSource(lpvSourceColour(ch, c)) : vec4(0.0);
        term = lpvFaceColour(lpvSourceColour(ch, c + LPV_AXES[a]), own, -vec3(LPV_AXES[a]), f, ch);
    }
    sTerm[ch][a][x] = term;
    barrier();
    if (a != 0 || !inside) return;
    vec4 v = vec4(0.0);
    for (int k = 0; k < 6; ++k) v += sTerm[ch][k][x];
    v = lpvStorable(v);
    // Each (cell, colour) has one storing invocation: the read-modify-write needs no atomics. The
    // first step starts the sum from the injected volume (its source), so lpv.pack writes only step[0].
    bool first = uIteration == 1;
    if (ch == 0) {
        imageStore(uDstR, c, v);
        imageStore(uAccumR, c, lpvStorable((first ? texelFetch(uSrcR, c, 0) : imageLoad(uAccumR, c)) + v));
    } else if (ch == 1) {
        imageStore(uDstG, c, v);
        imageStore(uAccumG, c, lpvStorable((first ? texelFetch(uSrcG, c, 0) : imageLoad(uAccumG, c)) + v));
    } else {
        imageStore(uDstB, c, v);
        imageStore(uAccumB, c, lpvStorable((first ? texelFetch(uSrcB, c, 0) : imageLoad(uAccumB, c)) + v));
    }
}
