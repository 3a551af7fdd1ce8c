// lpv.propagate with lpv.fuse = F > 1 (docs/lpv.md, "Fused propagation"): F iterations in one
// dispatch. A workgroup owns a tile of T^3 cells (T = RTGI_LPV_LOCAL_3D) and loads the previous
// step over the tile plus a halo of F cells into shared memory; each iteration j = 1..F computes
// lpvGather (lpv/propagate.glsl, unchanged) for the cells at least j cells inside that region
// (their sources are all in it) and writes it back (clamped by lpvStorable, read back rounded to
// RTGI_LPV_FORMAT as the unfused path's texture would be); the tile's cells add every step to
// `accum` in registers. Writes the last step and accum. Cells of the region outside the grid hold
// nothing and are never sources (lpvGather skips them, as in the unfused path). Band 1 only
// (lpv.sh_order=2 keeps one dispatch per iteration).
#define RTGI_LPV_FUSED
#include "lpv/propagate.glsl"
#include "lib/lpv_shared.h"

#ifndef RTGI_LPV_FUSE
#define RTGI_LPV_FUSE 2
#endif
#define LPV_T RTGI_LPV_LOCAL_3D
#define LPV_S (LPV_T + 2 * RTGI_LPV_FUSE)        // region side
#define LPV_REGION (LPV_S * LPV_S * LPV_S)
#define LPV_THREADS (LPV_T * LPV_T * LPV_T)
#define LPV_PER_THREAD ((LPV_REGION + LPV_THREADS - 1) / LPV_THREADS)
#define LPV_STEP_PER_THREAD (((LPV_S - 2) * (LPV_S - 2) * (LPV_S - 2) + LPV_THREADS - 1) / LPV_THREADS)

layout(local_size_x = LPV_T, local_size_y = LPV_T, local_size_z = LPV_T) in;

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

layout(location = RTGI_LPV_LOC_ITERATION) uniform int uIteration;   // the first iteration of this dispatch
layout(location = RTGI_LPV_LOC_FUSED_COUNT) uniform int uCount;      // iterations in this dispatch, 1..F

shared vec4 sR[LPV_REGION], sG[LPV_REGION], sB[LPV_REGION];

ivec3 gRegionOrigin;  // grid cell of region index 0

int lpvRegionIndex(ivec3 r) { return (r.z * LPV_S + r.y) * LPV_S + r.x; }
ivec3 lpvRegionCell(int i) { return ivec3(i % LPV_S, (i / LPV_S) % LPV_S, i / (LPV_S * LPV_S)); }

// What the unfused path's image store keeps of a value: rgba16f rounds to half (llvmpipe
// truncates, other drivers round to nearest as packHalf2x16 does: the paths may differ in the last
// half-precision bit there, docs/lpv.md), rgba32f keeps it.
vec4 lpvRounded(vec4 v) {
#ifdef RTGI_LPV_HALF
    return vec4(unpackHalf2x16(packHalf2x16(v.xy)), unpackHalf2x16(packHalf2x16(v.zw)));
#else
    return v;
#endif
}

// Shared memory holds each step as lpvStorable left it (the unfused path's registers); a source
// is read as the unfused path's texture holds it.
void lpvSharedSource(ivec3 p, out LpvSh sh[3]) {
    int i = lpvRegionIndex(p - gRegionOrigin);
    sh = LpvSh[3](lpvRounded(sR[i]), lpvRounded(sG[i]), lpvRounded(sB[i]));
}

void main() {
    ivec3 dims = lpv.grid.xyz;
    gRegionOrigin = ivec3(gl_WorkGroupID) * LPV_T - RTGI_LPV_FUSE;
    int t = int(gl_LocalInvocationIndex);
    for (int k = 0; k < LPV_PER_THREAD; ++k) {
        int i = t + k * LPV_THREADS;
        if (i >= LPV_REGION) break;
        ivec3 c = gRegionOrigin + lpvRegionCell(i);
        bool inside = lpvInside(c, dims);
        sR[i] = inside ? texelFetch(uSrcR, c, 0) : vec4(0.0);
        sG[i] = inside ? texelFetch(uSrcG, c, 0) : vec4(0.0);
        sB[i] = inside ? texelFetch(uSrcB, c, 0) : vec4(0.0);
    }
    barrier();
    ivec3 own = ivec3(gl_GlobalInvocationID);  // this invocation's tile cell
    bool ownInside = lpvInside(own, dims);
    int ownIndex = lpvRegionIndex(own - gRegionOrigin);
    vec4 accR = vec4(0.0), accG = vec4(0.0), accB = vec4(0.0);
    if (ownInside) {
        // The first iteration starts the sum from the injected volume (its source), as the unfused path.
        bool first = uIteration == 1;
        accR = first ? sR[ownIndex] : imageLoad(uAccumR, own);
        accG = first ? sG[ownIndex] : imageLoad(uAccumG, own);
        accB = first ? sB[ownIndex] : imageLoad(uAccumB, own);
    }
    for (int j = 1; j <= uCount; ++j) {
        // Step j for the cells at least j inside the region, [j, S - j) per axis: their 6
        // neighbours hold step j - 1.
        int m = LPV_S - 2 * j;
        LpvRgb next[LPV_STEP_PER_THREAD];
        for (int k = 0; k < LPV_STEP_PER_THREAD; ++k) {
            int i = t + k * LPV_THREADS;
            next[k] = LpvRgb(vec4(0.0), vec4(0.0), vec4(0.0));
            if (i >= m * m * m) break;
            ivec3 c = gRegionOrigin + j + ivec3(i % m, (i / m) % m, i / (m * m));
            if (!lpvInside(c, dims)) continue;
            next[k] = lpvGather(c, uIteration + j - 1, uSrcR, uSrcG, uSrcB, uGeometry, uGeometryAlbedo, uGeometryAxes);
        }
        barrier();  // every gather of step j has read step j - 1
        for (int k = 0; k < LPV_STEP_PER_THREAD; ++k) {
            int i = t + k * LPV_THREADS;
            if (i >= m * m * m) break;
            int r = lpvRegionIndex(j + ivec3(i % m, (i / m) % m, i / (m * m)));
            sR[r] = lpvStorable(next[k].r);
            sG[r] = lpvStorable(next[k].g);
            sB[r] = lpvStorable(next[k].b);
        }
        barrier();
        if (ownInside) {
            // As the unfused path: accum (as stored) + the step (as computed), stored.
            accR = lpvRounded(lpvStorable(accR + sR[ownIndex]));
            accG = lpvRounded(lpvStorable(accG + sG[ownIndex]));
            accB = lpvRounded(lpvStorable(accB + sB[ownIndex]));
        }
    }
    if (!ownInside) return;
    imageStore(uDstR, own, sR[ownIndex]);
    imageStore(uDstG, own, sG[ownIndex]);
    imageStore(uDstB, own, sB[ownIndex]);
    imageStore(uAccumR, own, accR);
    imageStore(uAccumG, own, accG);
    imageStore(uAccumB, own, accB);
}
