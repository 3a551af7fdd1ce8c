// ao.<variant>: one screen-space AO estimator per invocation, chosen by
// AO_VARIANT (RTGI_AO_* codes). Defines:
//   AO_VARIANT       1..7 (ssao-disk, ssao-sphere, ssao-hemisphere, vo, hbao, gtao, vbao)
//   AO_DIRECTIONAL   0 off, 1 bent normals (seed 000 eq. 17), 2 S3HO band 0-1 SH
//   AO_RADIUS        0 fixed, 1 dual radii, 2 dynamic (scale image from ao.radius)
//   AO_DEPTH_LIGHT   1: point tests against the sun's shadow map (seed 003 4.1)
//   AO_SECOND_LAYER  1: vbao adds the column of the surface in the second depth layer (ao.second_layer)
// A thin entry point: it binds the inputs, defines the scene accessors that
// lib/ao_estimators.glsl declares (depth along a ray, the point test, the
// sample sets) and calls the estimator; the estimators are pure functions there.
#include "lib/common.glsl"
#include "lib/depth.glsl"
#include "lib/ao_shared.h"
#include "lib/ao.glsl"
#include "lib/ao_estimators.glsl"
#include "lib/noise.glsl"
#include "lib/sh.glsl"

// Defaults (the pass always sets all four).
#ifndef AO_VARIANT
#define AO_VARIANT RTGI_AO_GTAO
#endif
#ifndef AO_DIRECTIONAL
#define AO_DIRECTIONAL 0
#endif
#ifndef AO_RADIUS
#define AO_RADIUS 0
#endif
#ifndef AO_DEPTH_LIGHT
#define AO_DEPTH_LIGHT 0
#endif
#ifndef AO_SLICE_BENT
#define AO_SLICE_BENT 0  // 1 (ao=gtao, ao.bent_normals=slices): the bent normal from GTAO's slices
#endif
#ifndef AO_SECOND_LAYER
#define AO_SECOND_LAYER 0  // 1: vbao reads gbuffer.linearDepth2 (visibility.layer2)
#endif

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, binding = RTGI_UBO_AO) uniform AoBlock { AoParams ao; };
layout(binding = RTGI_AO_TEX_DEPTH) uniform sampler2D uDepth;    // AO-resolution linear depth (0 = sky)
layout(binding = RTGI_AO_TEX_NORMAL) uniform sampler2D uNormal;   // AO-resolution view-space normals
layout(binding = RTGI_AO_ESTIMATE_TEX_NOISE) uniform sampler2DArray uNoise;
layout(binding = RTGI_AO_TEX_RADIUS_SCALE) uniform sampler2D uRadiusScale;
layout(binding = RTGI_AO_TEX_SHADOW_MAP) uniform sampler2D uShadowMap;
layout(binding = RTGI_AO_ESTIMATE_TEX_ALBEDO) uniform sampler2D uAlbedo;   // full resolution (gtao multi-bounce)
layout(binding = RTGI_AO_ESTIMATE_TEX_DEPTH2) uniform sampler2D uDepth2;  // full-resolution second layer (AO_SECOND_LAYER)
layout(r16f, binding = RTGI_AO_IMG_AO) uniform writeonly image2D uAo;
layout(rgba16f, binding = RTGI_AO_IMG_DIRECTIONAL) uniform writeonly image2D uDirectional;
layout(location = RTGI_AO_LOC_VIEW_TO_SHADOW) uniform mat4 uViewToShadow;  // shadowViewProj * invView
layout(location = RTGI_AO_LOC_SHADOW_TO_VIEW) uniform mat4 uShadowToView;  // its inverse

ivec2 aoSize() { return ao.size.xy; }
float tanHalfFov() { return ao.focal.z; }
float aspect() { return ao.focal.w; }

// Scene depth seen through uv (0 for sky or off-screen: both count as free).
float sceneDepth(vec2 uv) {
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return 0.0;
    return texelFetch(uDepth, ivec2(uv * vec2(aoSize())), 0).r;
}
vec3 viewPosAt(vec2 uv, float d) { return viewPositionFromDepth(uv, d, tanHalfFov(), aspect()); }
// Centre of the texel that holds uv: depth read there belongs to this uv.
vec2 snapUv(vec2 uv) { return (floor(uv * vec2(aoSize())) + 0.5) / vec2(aoSize()); }

// Depth of the scene along the exact ray through uv: the fetched texel's
// surface (its depth and normal) extended as a plane to uv. Every variant
// reads the scene through this, so samples that fall between texel centres
// neither self-occlude on the staircase of a coarse depth buffer nor leave
// the slice/line they belong to (docs/ao.md, "Reconstruction").
float sceneDepthAlongRay(vec2 uv) {
    float z = sceneDepth(uv);
    if (isSky(z)) return z;
    vec2 c = snapUv(uv);
    vec3 Q = viewPosAt(c, z);
    vec3 nQ = aoSafeNormal(texelFetch(uNormal, ivec2(c * vec2(aoSize())), 0).xyz, Q);
    return aoPlaneDepthAlongRay(Q, nQ, uv, tanHalfFov(), aspect(), z);
}

// ---- the scene accessors of lib/ao_estimators.glsl ----
float aoSceneDepth(vec2 uv) { return sceneDepthAlongRay(uv); }
// The second layer's texel under uv (full resolution: with ao.resolution=half
// it may belong to another surface than the half-resolution sample; the
// library then falls back to the thickness, z2 <= zS).
float aoSceneDepth2(vec2 uv) {
#if AO_SECOND_LAYER
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return 0.0;
    return texelFetch(uDepth2, ivec2(uv * vec2(textureSize(uDepth2, 0))), 0).r;
#else
    return 0.0;
#endif
}
vec3 aoKernel(int i) { return ao.kernel[i].xyz; }
vec4 aoVoSample(int i) { return ao.voSamples[i]; }
AoCamera aoCamera() { return AoCamera(ao.focal.xy, tanHalfFov(), aspect(), vec2(aoSize())); }

// Point test of the sample-point variants: how much the sample point S is
// occluded (0 free .. 1 occluded, range-attenuated by the blocker distance).
float aoPointOcclusion(vec3 P, vec3 S, float R) {
#if AO_DEPTH_LIGHT
    vec4 c = uViewToShadow * vec4(S, 1.0);
    vec3 ndc = c.xyz / c.w;
    vec2 uvL = ndc.xy * 0.5 + 0.5;
    if (any(lessThan(uvL, vec2(0.0))) || any(greaterThanEqual(uvL, vec2(1.0)))) return 0.0;  // outside the light frustum
    // Raw depth: the pass binds a sampler object without compare mode to this unit.
    float stored = texture(uShadowMap, uvL).r;
    float z01 = ndc.z * 0.5 + 0.5;
    if (stored >= z01 - 1e-4) return 0.0;
    vec4 b = uShadowToView * vec4(ndc.xy, stored * 2.0 - 1.0, 1.0);
    return rangeAttenuation(R, distance(b.xyz / b.w, P));
#else
    return aoCameraPointOcclusion(aoCamera(), P, S, R);
#endif
}

// AO of the variant this program is compiled for (AO_VARIANT).
vec3 gSliceBent = vec3(0.0);  // gtao: its slices' bent normal (AO_SLICE_BENT)

float estimate(ivec2 pixel, vec2 uv, vec3 P, vec3 n, float d, float R, vec4 bn) {
    AoCamera cam = aoCamera();
#if AO_VARIANT == RTGI_AO_SSAO_DISK
    return aoSsaoDisk(cam, P, d, R, tiledNoise4x4(uNoise, pixel), ao.counts.x, ao.flags.x != 0, AO_DEPTH_LIGHT != 0);
#elif AO_VARIANT == RTGI_AO_SSAO_SPHERE || AO_VARIANT == RTGI_AO_SSAO_HEMISPHERE
    return aoSsaoKernel(P, n, R, bn.xy, ao.counts.x, AO_VARIANT == RTGI_AO_SSAO_HEMISPHERE);
#elif AO_VARIANT == RTGI_AO_VO
    // Pairs p, -p: rotation over 180 degrees; blockers up to 2R in front (scaled with a second radius).
    return aoVo(cam, uv, d, R, PI * bn.x, int(ao.misc.z), ao.radius.z * (R / ao.radius.x));
#elif AO_VARIANT == RTGI_AO_HBAO
    // Rotation over 360/N_d and step jitter from the per-pixel noise (seed 003 5.3).
    return aoHbao(cam, uv, P, n, d, R, bn.xy, ao.counts.y, ao.counts.z, ao.radius.w, ao.flags.y != 0);
#elif AO_VARIANT == RTGI_AO_GTAO
#if AO_SLICE_BENT
    float vis = aoGtaoBent(cam, uv, P, n, d, R, bn.xy, ao.counts.y, ao.counts.z, gSliceBent);
#else
    float vis = aoGtao(cam, uv, P, n, d, R, bn.xy, ao.counts.y, ao.counts.z);  // no bent normal to keep
#endif
    if (ao.flags.z != 0) vis = gtaoMultiBounce(vis, luminance(texture(uAlbedo, uv).rgb));
    return vis;
#elif AO_VARIANT == RTGI_AO_VBAO
    // Sector jitter from the noise's third channel (unbiased quantization over frames).
    float vis = aoVbao(cam, uv, P, n, d, R, bn.xyz, ao.counts.y, ao.counts.z, ao.bitmask.x, ao.bitmask.y != 0.0,
                      AO_SECOND_LAYER != 0);
    if (ao.flags.z != 0) vis = gtaoMultiBounce(vis, luminance(texture(uAlbedo, uv).rgb));
    return vis;
#else
#error "AO_VARIANT must be one of the RTGI_AO_* codes"
#endif
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, aoSize()))) return;
    float d = texelFetch(uDepth, p, 0).r;
    if (isSky(d)) {
        imageStore(uAo, p, vec4(1.0));
#if AO_DIRECTIONAL
        imageStore(uDirectional, p, vec4(0.0, 0.0, 0.0, 1.0));
#endif
        return;
    }
    vec2 uv = (vec2(p) + 0.5) / vec2(aoSize());
    vec3 P = viewPosAt(uv, d);
    vec3 n = aoSafeNormal(texelFetch(uNormal, p, 0).xyz, P);
    vec4 bn = blueNoise(uNoise, p, frameIndex());
    float R = ao.radius.x;
#if AO_RADIUS == 2
    R *= texelFetch(uRadiusScale, p, 0).r;
#endif
    // Guard (issue 9, docs/STABILITY.md): a radius below 1e-4 of the view depth puts every sample
    // within ~1000 fp32 ulps of P, where the depth comparisons are decided by rounding (ssao-disk
    // counted a plane as fully occluded at R = 0, vo as 16 % occluded at 1e-6). Nothing can be
    // closer than R -> 0, so the exact AO is 1 and the directional terms are the unoccluded ones.
    if (!(R > 1e-4 * d)) {
        imageStore(uAo, p, vec4(1.0));
#if AO_DIRECTIONAL == 1
        imageStore(uDirectional, p, vec4(n, 1.0));
#elif AO_DIRECTIONAL == 2
        imageStore(uDirectional, p, shCosineLobe(n));
#endif
        return;
    }
    float a = estimate(p, uv, P, n, d, R, bn);
#if AO_RADIUS == 1
    float b = estimate(p, uv, P, n, d, ao.radius.y, bn);
    a = ao.misc.x != 0.0 ? min(a, b) : a * b;
#endif
    a = clamp(a, 0.0, 1.0);
    imageStore(uAo, p, vec4(a));
#if AO_DIRECTIONAL == 1 && AO_SLICE_BENT
    imageStore(uDirectional, p, vec4(gSliceBent, a));
#elif AO_DIRECTIONAL == 1
    imageStore(uDirectional, p, vec4(aoDirectional(P, n, R, bn, ao.counts.x, false).xyz, a));
#elif AO_DIRECTIONAL == 2
    imageStore(uDirectional, p, aoDirectional(P, n, R, bn, ao.counts.x, true));
#endif
}
