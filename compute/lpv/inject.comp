// lpv.inject (compute): one invocation per RSM texel adds Phi/pi * cosLobe(n)
// (seed eq. 9, SPEC 3.3) to its cell's 12 coefficients with fp32 image
// atomics, pre-reduced per workgroup in shared memory (lpv_reduce.glsl).
// Layout of each r32f accumulation texture: coefficient k of cell (x, y, z)
// at (4x + k, y, z). The textures are zero on entry (lpv.pack zeroes what it
// consumed). Texels outside the grid are counted. lpv.sh_order=2 (RTGI_LPV_SH2):
// the 9 coefficients of the band-2 lobe; 4-7 in injectHi (4X, Y, Z), 8 of colour c
// in injectLast at (3x + c, y, z) (lib/lpv_shared.h).
// RTGI_LPV_INJECT_FACES: many local-light RSM faces in one dispatch (docs/lpv.md "Injection"):
// the RSMs are layers of 2D arrays of one side, workgroup z injects face entry
// uFirstFace + z of the LpvRsmFace list (its layer and the inverse of the view it was drawn
// with); the volume's placement comes from the uniform block as for the sun's RSM.
// RTGI_LPV_INJECT_SKY (lpv.sky_bounce; docs/lpv.md, "Sky bounce"): instead of an RSM, the
// G-buffer at lpv.geometry_stride as surfels lit by the sky: each adds (rho E_sky A / pi)
// cosLobe(n) with E_sky = pi * sky * f, f the cosine-weighted sky visibility of the cells in
// front of it (the sky term's, lpv/apply.comp), read with the apply's side test and, with
// RTGI_LPV_LOOKUP_VISIBILITY, the cells' visibility moments.
#extension GL_NV_shader_atomic_float : require  // float atomics (images, shared memory)
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"

layout(local_size_x = RTGI_LPV_LOCAL_REDUCE, local_size_y = RTGI_LPV_LOCAL_REDUCE) in;

#ifdef RTGI_LPV_INJECT_SKY
#include "lpv/gbuffer_surfel.glsl"
#include "lib/lpv_lookup.glsl"
#include "lib/brdf.glsl"
layout(binding = RTGI_LPV_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
layout(binding = RTGI_LPV_TEX_VIEW_NORMAL) uniform sampler2D uViewNormal;
layout(binding = RTGI_LPV_TEX_ALBEDO) uniform sampler2D uAlbedo;
layout(binding = RTGI_LPV_TEX_MATERIAL) uniform sampler2D uMaterial;
layout(binding = RTGI_LPV_TEX_INJECT_SKY) uniform sampler3D uSkyVisibility;  // band-1 SH per cell
#ifdef RTGI_LPV_LOOKUP_VISIBILITY
layout(binding = RTGI_LPV_TEX_INJECT_MOMENTS) uniform sampler3D uVisibility;
#endif
#ifndef RTGI_LPV_GV_STRIDE
#define RTGI_LPV_GV_STRIDE 2
#endif
#elif defined(RTGI_LPV_INJECT_FACES)
layout(binding = RTGI_LPV_TEX_FLUX) uniform sampler2DArray uFlux;
layout(binding = RTGI_LPV_TEX_NORMAL) uniform sampler2DArray uNormal;
layout(binding = RTGI_LPV_TEX_DEPTH) uniform sampler2DArray uDepth;
layout(std430, binding = RTGI_SSBO_LPV_RSM_FACES) readonly buffer Faces { LpvRsmFace faces[]; };
layout(location = RTGI_LPV_INJECT_LOC_FIRST_FACE) uniform int uFirstFace;
layout(location = RTGI_LPV_INJECT_LOC_STATS_SLOT) uniform int uStatsSlot;
#else
layout(binding = RTGI_LPV_TEX_FLUX) uniform sampler2D uFlux;
layout(binding = RTGI_LPV_TEX_NORMAL) uniform sampler2D uNormal;
layout(binding = RTGI_LPV_TEX_DEPTH) uniform sampler2D uDepth;
#endif
layout(r32f, binding = RTGI_LPV_INJECT_IMG_INJECT_R) uniform image3D uInjectR;
layout(r32f, binding = RTGI_LPV_INJECT_IMG_INJECT_G) uniform image3D uInjectG;
layout(r32f, binding = RTGI_LPV_INJECT_IMG_INJECT_B) uniform image3D uInjectB;
layout(std430, binding = RTGI_SSBO_LPV_STATS) buffer Stats { uint droppedTexels[]; };

#ifdef RTGI_LPV_SH2
layout(r32f, binding = RTGI_LPV_INJECT_IMG_INJECT_HI_R) uniform image3D uInjectHiR;
layout(r32f, binding = RTGI_LPV_INJECT_IMG_INJECT_HI_G) uniform image3D uInjectHiG;
layout(r32f, binding = RTGI_LPV_INJECT_IMG_INJECT_HI_B) uniform image3D uInjectHiB;
layout(r32f, binding = RTGI_LPV_INJECT_IMG_INJECT_LAST) uniform image3D uInjectLast;
#define LPV_REDUCE_CHANNELS 27  // colour * 9 + SH coefficient
void lpvGlobalAdd(uint key, int channel, float value) {
    ivec3 c = lpvCellOfKey(key, lpv.grid.xyz);
    int colour = channel / 9, k = channel % 9;
    if (k == 8) {
        imageAtomicAdd(uInjectLast, ivec3(3 * c.x + colour, c.y, c.z), value);
        return;
    }
    ivec3 a = ivec3(4 * c.x + (k & 3), c.y, c.z);
    if (k < 4) {
        if (colour == 0) imageAtomicAdd(uInjectR, a, value);
        else if (colour == 1) imageAtomicAdd(uInjectG, a, value);
        else imageAtomicAdd(uInjectB, a, value);
    } else {
        if (colour == 0) imageAtomicAdd(uInjectHiR, a, value);
        else if (colour == 1) imageAtomicAdd(uInjectHiG, a, value);
        else imageAtomicAdd(uInjectHiB, a, value);
    }
}
#else
#define LPV_REDUCE_CHANNELS 12  // colour * 4 + SH coefficient
void lpvGlobalAdd(uint key, int channel, float value) {
    ivec3 c = lpvCellOfKey(key, lpv.grid.xyz);
    ivec3 a = ivec3(4 * c.x + (channel & 3), c.y, c.z);
    int colour = channel >> 2;
    if (colour == 0) imageAtomicAdd(uInjectR, a, value);
    else if (colour == 1) imageAtomicAdd(uInjectG, a, value);
    else imageAtomicAdd(uInjectB, a, value);
}
#endif
#include "lpv/lpv_reduce.glsl"

#ifdef RTGI_LPV_INJECT_SKY
// The cosine-weighted sky visibility f in [0, 1] of the cells in front of the surface point x
// (normal n), read at q = x + n s / 2 as lpv/apply.comp reads it for the receiver (with its view bias).
float lpvSkyVisibleAt(vec3 x, vec3 n) {
    vec3 q = lpvCellCoord(x + 0.5 * lpvCellSize() * n);
    float blocked[8];
#ifdef RTGI_LPV_LOOKUP_VISIBILITY
    lpvVisibilityBlockingFromView(uVisibility, q, normalize(frame.cameraPos.xyz - x), lpv.grid.xyz, blocked);
#else
    for (int k = 0; k < 8; ++k) blocked[k] = 0.0;
#endif
    float w[8];
    lpvGeometryWeights(q, lpvCellCoord(x), n, blocked, w);
    vec4 p = lpvStencilFetch(uSkyVisibility, lpvStencilBase(q), w, lpv.grid.xyz);
    return clamp(shCosineIntegral(p, n) * INV_PI, 0.0, 1.0);
}
#endif

// Adds flux Phi (rgb) leaving the surface point p with normal n as (Phi / pi) cosLobe(n) to the
// cell in front of it; false when that cell is outside the volume.
bool lpvInjectSurfel(vec3 p, vec3 n, vec3 flux) {
    ivec3 c;
    if (!lpvInjectionCell(p, n, c)) return false;
#ifdef RTGI_LPV_SH2
    mat3 lobe = shCosineLobe9(n) * INV_PI;
    float v[27];
    for (int k = 0; k < 9; ++k) {
        float l = lobe[k / 3][k % 3];
        v[k] = flux.r * l;
        v[9 + k] = flux.g * l;
        v[18 + k] = flux.b * l;
    }
#else
    vec4 lobe = shCosineLobe(n) * INV_PI;
    float v[12];
    for (int k = 0; k < 4; ++k) {
        v[k] = flux.r * lobe[k];
        v[4 + k] = flux.g * lobe[k];
        v[8 + k] = flux.b * lobe[k];
    }
#endif
    lpvReduceAdd(lpvKeyOfCell(c, lpv.grid.xyz), v);
    return true;
}

void main() {
    lpvReduceBegin();
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
#ifdef RTGI_LPV_INJECT_SKY
    ivec2 full = t * RTGI_LPV_GV_STRIDE;
    vec3 wp, n;
    float area;
    if (lpvGBufferSurfel(uLinearDepth, uViewNormal, full, RTGI_LPV_GV_STRIDE, lpv.rsm.w, wp, n, area)) {
        vec3 rho = diffuseAlbedo(texelFetch(uAlbedo, full, 0).rgb, texelFetch(uMaterial, full, 0).g);
        // Phi = rho A E_sky = rho A pi sky f (cells outside this cascade: the coarser one holds them).
        vec3 flux = rho * area * PI * frame.sky.rgb * lpvSkyVisibleAt(wp, n);
        if (any(greaterThan(flux, vec3(0.0)))) lpvInjectSurfel(wp, n, flux);
    }
#else
#ifdef RTGI_LPV_INJECT_FACES
    LpvRsmFace face = faces[uFirstFace + int(gl_WorkGroupID.z)];
    const int side = textureSize(uFlux, 0).x;
    const int statsSlot = uStatsSlot;
    ivec3 tex = ivec3(t, face.layer.x);
#define LPV_RSM_POSITION(depth) rsmWorldPosition(face.invViewProj, side, t, depth)
#else
    const int side = lpv.grid.w;
    const int statsSlot = 0;
    ivec2 tex = t;
#define LPV_RSM_POSITION(depth) rsmWorldPosition(t, depth)
#endif
    vec4 nrm = all(lessThan(t, ivec2(side))) ? texelFetch(uNormal, tex, 0) : vec4(0.0);
    if (nrm.w != 0.0) {  // a surface in this texel
        vec3 n = normalize(nrm.xyz);
        if (!lpvInjectSurfel(LPV_RSM_POSITION(texelFetch(uDepth, tex, 0).r), n, texelFetch(uFlux, tex, 0).rgb)) {
            if (lpv.cascade.z != 0) atomicAdd(droppedTexels[statsSlot], 1u);  // the coarsest cascade counts (finer ones hold less by design)
        }
    }
#endif
    lpvReduceEnd();
}
