// lpv.inject_geometry: blocking potential B(w) = A_s s^-2 max(0, n.w) (seed
// eq. 11, [KD10]) projected with the cosine lobe, plus A_s * albedo (rgb) and
// A_s for the mean albedo the bounce reflects with (colour bleeding), accumulated with fp32 atomics on
// the corner lattice (offset by half a cell: corner g sits at origin + g*s),
// pre-reduced per workgroup in shared memory (lpv_reduce.glsl); the
// accumulation texture is zero on entry (the geometry pack zeroes it).
// Sources: RTGI_LPV_GV_RSM, the sun's RSM; RTGI_LPV_GV_GBUFFER, the camera G-buffer
// sampled at quarter resolution (every second pixel in x and y, seed 5.2.3), or with
// RTGI_LPV_GV_STRIDE = 4 (lpv.geometry_stride=4) every fourth, each sample's
// surfel standing for the stride^2 pixels (docs/lpv.md, "Geometry injection stride").
// With both, one dispatch of two workgroup layers: z = 0 reads the RSM, z = 1 the
// G-buffer (one launch and one barrier fewer per cascade; the sums are the same).
#extension GL_NV_shader_atomic_float : require  // float atomics (images, shared memory)
#if !defined(RTGI_LPV_GV_RSM) && !defined(RTGI_LPV_GV_GBUFFER)
#define RTGI_LPV_GV_RSM  // the sun's RSM is the source when none is named
#endif
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"
#include "lpv/gbuffer_surfel.glsl"
#include "lib/brdf.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_REDUCE, local_size_y = RTGI_LPV_LOCAL_REDUCE) in;

layout(r32f, binding = RTGI_LPV_INJECT_GEOMETRY_IMG_GEOMETRY_ACCUM) uniform image3D uGeometryAccum;

#ifdef RTGI_LPV_GV_GBUFFER
layout(binding = RTGI_LPV_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
layout(binding = RTGI_LPV_TEX_VIEW_NORMAL) uniform sampler2D uViewNormal;
layout(binding = RTGI_LPV_TEX_ALBEDO) uniform sampler2D uAlbedo;
layout(binding = RTGI_LPV_TEX_MATERIAL) uniform sampler2D uMaterial;
#ifndef RTGI_LPV_GV_STRIDE
#define RTGI_LPV_GV_STRIDE 2
#endif
const int kStride = RTGI_LPV_GV_STRIDE;
#endif
#ifdef RTGI_LPV_GV_RSM
layout(binding = RTGI_LPV_INJECT_GEOMETRY_TEX_RSM_FLUX) uniform sampler2D uFlux;
layout(binding = RTGI_LPV_INJECT_GEOMETRY_TEX_RSM_NORMAL) uniform sampler2D uNormal;
layout(binding = RTGI_LPV_INJECT_GEOMETRY_TEX_RSM_DEPTH) uniform sampler2D uDepth;
#endif

#define LPV_REDUCE_CHANNELS RTGI_LPV_GV_CHANNELS
void lpvGlobalAdd(uint key, int channel, float value) {
    ivec3 g = lpvCellOfKey(key, lpv.grid.xyz + 1);
    imageAtomicAdd(uGeometryAccum, ivec3(RTGI_LPV_GV_CHANNELS * g.x + channel, g.y, g.z), value);
}
#include "lpv/lpv_reduce.glsl"

// This invocation's run of samples in one cell (key LPV_NO_KEY: none yet).
uint gRunKey = LPV_NO_KEY;
float gRun[RTGI_LPV_GV_CHANNELS];
void flushRun() {
    if (gRunKey != LPV_NO_KEY) lpvReduceAdd(gRunKey, gRun);
    gRunKey = LPV_NO_KEY;
}

void addBlocker(vec3 p, vec3 n, float area, vec3 albedo) {
    ivec3 g = ivec3(floor(lpvCellCoord(p) + 0.5));
    if (!lpvInside(g, lpv.grid.xyz + 1) || !(area > 0.0)) return;
    vec4 b = shCosineLobe(n) * (area * lpv.rsm.y);
    float v[RTGI_LPV_GV_CHANNELS];
    for (int k = 0; k < 4; ++k) v[k] = b[k];
    for (int k = 0; k < 3; ++k) v[4 + k] = area * albedo[k];
    v[7] = area;
    // Two-sided axis blocking (docs/lpv.md, "Leaks"): the surface's area projected on the
    // three axis planes, per s^2, whichever side it was seen from.
#ifdef RTGI_LPV_TWO_SIDED
    for (int k = 0; k < 3; ++k) v[8 + k] = area * lpv.rsm.y * abs(n[k]);
#endif
    // Consecutive samples of one invocation in the same cell add up in registers first: one
    // contended shared-memory add per run instead of one per sample.
    uint key = lpvKeyOfCell(g, lpv.grid.xyz + 1);
    if (key != gRunKey) {
        flushRun();
        gRunKey = key;
        for (int k = 0; k < RTGI_LPV_GV_CHANNELS; ++k) gRun[k] = v[k];
    } else {
        for (int k = 0; k < RTGI_LPV_GV_CHANNELS; ++k) gRun[k] += v[k];
    }
}

// The contribution of sample / texel t, if any (no barriers inside). Each invocation takes a
// block of RTGI_LPV_GV_BLOCK x RTGI_LPV_GV_BLOCK of them.
#ifdef RTGI_LPV_GV_GBUFFER
void gbufferBlocker(ivec2 t) {
    ivec2 full = t * kStride;
    vec3 wp, n;
    float area;
    if (!lpvGBufferSurfel(uLinearDepth, uViewNormal, full, kStride, lpv.rsm.w, wp, n, area)) return;
    vec3 albedo = diffuseAlbedo(texelFetch(uAlbedo, full, 0).rgb, texelFetch(uMaterial, full, 0).g);
    addBlocker(wp, n, area, albedo);
}
#endif
#ifdef RTGI_LPV_GV_RSM
void rsmBlocker(ivec2 t) {
    if (any(greaterThanEqual(t, ivec2(lpv.grid.w)))) return;
    vec4 nrm = texelFetch(uNormal, t, 0);
    if (nrm.w == 0.0) return;
    vec3 n = normalize(nrm.xyz);
    // A_texel is the area perpendicular to the light; on the surface it is A_texel / cos.
    float area = lpv.rsm.x / max(dot(n, frame.sunDirection.xyz), lpv.rsm.w);
    // The RSM stores albedo * E_perp * A_texel; divide back for the albedo.
    vec3 e = frame.sunIrradiance.rgb * lpv.rsm.x;
    vec3 flux = texelFetch(uFlux, t, 0).rgb;
    vec3 albedo = vec3(e.r > 0.0 ? flux.r / e.r : 0.0, e.g > 0.0 ? flux.g / e.g : 0.0, e.b > 0.0 ? flux.b / e.b : 0.0);
    addBlocker(rsmWorldPosition(t, texelFetch(uDepth, t, 0).r), n, area, clamp(albedo, 0.0, 1.0));
}
#endif

void blocker() {
    for (int k = 0; k < RTGI_LPV_GV_CHANNELS; ++k) gRun[k] = 0.0;
    for (int j = 0; j < RTGI_LPV_GV_BLOCK * RTGI_LPV_GV_BLOCK; ++j) {
        ivec2 t = ivec2(gl_GlobalInvocationID.xy) * RTGI_LPV_GV_BLOCK + ivec2(j % RTGI_LPV_GV_BLOCK, j / RTGI_LPV_GV_BLOCK);
#if defined(RTGI_LPV_GV_RSM) && defined(RTGI_LPV_GV_GBUFFER)
        if (gl_WorkGroupID.z == 0u) rsmBlocker(t);
        else gbufferBlocker(t);
#elif defined(RTGI_LPV_GV_RSM)
        rsmBlocker(t);
#else
        gbufferBlocker(t);
#endif
    }
    flushRun();
}

void main() {
    lpvReduceBegin();
    blocker();
    lpvReduceEnd();
}
