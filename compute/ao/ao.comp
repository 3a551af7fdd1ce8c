// ao.<variant>: one screen-space AO estimator per invocation, chosen by
// AO_VARIANT (RTGI_AO_* codes). Defines:
//   AO_VARIANT       1..6 (ssao-disk, ssao-sphere, ssao-hemisphere, vo, hbao, gtao)
//   AO_DIRECTIONAL   0 off, 1 bent normals (seed 000 eq. 17), 2 S3HO band 0-1 SH
//   AO_RADIUS        0 fixed, 1 dual radii, 2 dynamic (scale image from ao.radius)
//   AO_DEPTH_LIGHT   1: point tests against the sun's shadow map (seed 003 4.1)
// The math lives in lib/ao.glsl; this file binds inputs and loops samples.
#include "lib/common.glsl"
#include "lib/depth.glsl"
#include "lib/ao_shared.h"
#include "lib/ao.glsl"
#include "lib/sampling.glsl"
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

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, binding = RTGI_UBO_AO) uniform AoBlock { AoParams ao; };
layout(binding = RTGI_AO_TEX_DEPTH) uniform sampler2D uDepth;    // AO-resolution linear depth (0 = sky)
layout(binding = RTGI_AO_TEX_NORMAL) uniform sampler2D uNormal;   // AO-resolution view-space normals
layout(binding = RTGI_AO_ESTIMATE_TEX_NOISE) uniform sampler2DArray uNoise;
layout(binding = RTGI_AO_TEX_RADIUS_SCALE) uniform sampler2D uRadiusScale;
layout(binding = RTGI_AO_TEX_SHADOW_MAP) uniform sampler2D uShadowMap;
layout(binding = RTGI_AO_ESTIMATE_TEX_ALBEDO) uniform sampler2D uAlbedo;   // full resolution (gtao multi-bounce)
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

// Point test of the sample-point variants: how much the sample point S is
// occluded (0 free .. 1 occluded, range-attenuated by the blocker distance).
float pointOcclusion(vec3 P, vec3 S, float R) {
#if AO_DEPTH_LIGHT
    vec4 c = uViewToShadow * vec4(S, 1.0);
    vec3 ndc = c.xyz / c.w;
    vec2 uvL = ndc.xy * 0.5 + 0.5;
    if (any(lessThan(uvL, vec2(0.0))) || any(greaterThanEqual(uvL, vec2(1.0)))) return 0.0;  // outside the light frustum
    float stored = texture(uShadowMap, uvL).r;
    float z01 = ndc.z * 0.5 + 0.5;
    if (stored >= z01 - 1e-4) return 0.0;
    vec4 b = uShadowToView * vec4(ndc.xy, stored * 2.0 - 1.0, 1.0);
    return rangeAttenuation(R, distance(b.xyz / b.w, P));
#else
    vec3 uvS = uvFromViewPosition(S, tanHalfFov(), aspect());
    float zScene = sceneDepthAlongRay(uvS.xy);
    if (isSky(zScene) || zScene >= uvS.z - 0.02 * R) return 0.0;  // bias: 2 % of R against self-occlusion
    return rangeAttenuation(R, abs(-P.z - zScene));
#endif
}

#if AO_DIRECTIONAL
// Directional occlusion from cosine-distributed, normal-oriented samples
// (seed 000 4.3): xyz bent normal (eq. 17) or 4 SH coefficients of V(l)(n.l)+.
vec4 directional(vec3 P, vec3 n, float R, vec4 bn) {
    mat3 basis = aoBasis(n, vec3(cos(TWO_PI * bn.z), sin(TWO_PI * bn.z), 0.0));
    int count = ao.counts.x;
    vec3 bent = vec3(0.0);
    vec4 sh = vec4(0.0);
    for (int i = 0; i < count; ++i) {
        // Stratified in cos^2 (radial) and golden-ratio azimuth, rotated per pixel.
        vec2 u = vec2((float(i) + bn.w) / float(count), fract(float(i) * 0.6180339887 + bn.z));
        vec3 l = basis * cosineHemisphere(u);
        float r = R * length(ao.kernel[i % RTGI_AO_MAX_KERNEL].xyz);
        float v = 1.0 - pointOcclusion(P, P + l * max(r, 0.1 * R), R);
        bent += v * l;
        sh += v * shBasis(l);  // the LPV family's basis: lpv.apply consumes it
    }
#if AO_DIRECTIONAL == 1
    return vec4(dot(bent, bent) > 1e-12 ? normalize(bent) : n, 0.0);
#else
    return sh * (PI / float(count));  // cosine-weighted pdf cos/pi -> integral of V Y (n.l)+
#endif
}
#endif

float estimate(ivec2 pixel, vec2 uv, vec3 P, vec3 n, float d, float R, vec4 bn) {
    float R2 = R * R;
#if AO_VARIANT == RTGI_AO_SSAO_DISK
    // Kajalin / Crytek: full-sphere kernel reflected by the tiled 4x4 noise vector.
    vec3 noiseVec = tiledNoise4x4(uNoise, pixel);
    if (dot(noiseVec, noiseVec) < 1e-6) noiseVec = vec3(0, 0, 1);
    noiseVec = normalize(noiseVec);
    float sum = 0.0;
    for (int i = 0; i < ao.counts.x; ++i) {
        vec3 S = P + R * reflect(ao.kernel[i].xyz, noiseVec);
#if AO_DEPTH_LIGHT
        sum += 1.0 - pointOcclusion(P, S, R);
#else
        vec3 uvS = uvFromViewPosition(S, tanHalfFov(), aspect());
        float zScene = sceneDepthAlongRay(uvS.xy);
        sum += isSky(zScene) ? 1.0 : ssaoDiskSampleValue(d, uvS.z, zScene);
#endif
    }
    float v = sum / float(ao.counts.x);
    return ao.flags.x != 0 ? halfSpaceNormalize(v) : v;
#elif AO_VARIANT == RTGI_AO_SSAO_SPHERE || AO_VARIANT == RTGI_AO_SSAO_HEMISPHERE
    float a = TWO_PI * bn.x;
#if AO_VARIANT == RTGI_AO_SSAO_SPHERE
    mat3 basis = aoBasis(vec3(0, 0, 1), vec3(cos(a), sin(a), 0.0));  // rotation about the view axis
#else
    mat3 basis = aoBasis(n, vec3(cos(a), sin(a), 0.0));
#endif
    float radiusJitter = 0.75 + 0.5 * bn.y;  // noise on the radius too (seed 000 5.3 after [Jp16])
    float occ = 0.0;
    for (int i = 0; i < ao.counts.x; ++i) {
        vec3 o = ao.kernel[i].xyz;
#if AO_VARIANT == RTGI_AO_SSAO_HEMISPHERE
        o.z = abs(o.z);
#endif
        occ += pointOcclusion(P, P + R * radiusJitter * (basis * o), R);
    }
    float v = 1.0 - occ / float(ao.counts.x);
#if AO_VARIANT == RTGI_AO_SSAO_SPHERE
    return halfSpaceNormalize(v);
#else
    return v;
#endif
#elif AO_VARIANT == RTGI_AO_VO
    // Loos & Sloan line samples in pairs p, -p; rotation over 180 degrees.
    vec2 rUv = aoTextureRadius(R, d, ao.focal.xy);
    float a = PI * bn.x;
    mat2 rot = mat2(cos(a), sin(a), -sin(a), cos(a));
    float vis = 0.0;
    int pairs = int(ao.misc.z);
    for (int i = 0; i < pairs; ++i) {
        vec4 s = ao.voSamples[i];
        vec2 off = (rot * s.xy) * rUv;
        float frac[2];
        bool valid[2];
        for (int k = 0; k < 2; ++k) {
            float zScene = sceneDepthAlongRay(uv + (k == 0 ? off : -off));
            // Sky is infinitely far: the line is free. A scene point more than
            // the maximum occlusion distance 2R in front is invalid.
            valid[k] = isSky(zScene) || d - zScene < ao.radius.z * (R / ao.radius.x);
            frac[k] = isSky(zScene) ? 1.0 : voLineFree(s.z, (zScene - d) / R) / (2.0 * s.z);
        }
        if (!valid[0] && !valid[1]) frac[0] = frac[1] = 0.5;
        else if (!valid[0]) frac[0] = 1.0 - frac[1];
        else if (!valid[1]) frac[1] = 1.0 - frac[0];
        vis += s.w * 0.5 * (frac[0] + frac[1]);
    }
    return halfSpaceNormalize(vis);
#elif AO_VARIANT == RTGI_AO_HBAO
    vec2 rUv = aoTextureRadius(R, d, ao.focal.xy);
    if (rUv.x * float(aoSize().x) < 1.0) return 1.0;  // radius below one pixel: nothing to find
    int dirs = ao.counts.y, steps = ao.counts.z;
    float biasAngle = atan(ao.radius.w);
    float sumAo = 0.0;
    for (int k = 0; k < dirs; ++k) {
        // Rotation over 360/N_d and step jitter from the per-pixel noise (seed 003 5.3).
        float phi = TWO_PI * (float(k) + bn.x) / float(dirs);
        vec2 dir = vec2(cos(phi), sin(phi));
        float tanT;
        if (ao.flags.y != 0) {
            // Tangent of the slice: the line where the tangent plane meets the
            // plane through the eye that holds this screen direction. Every
            // in-plane sample of the march lies on it, so a plane gives
            // tanH == tanT exactly (the view-aligned -n.xy.dir/n.z differs
            // off-axis under perspective and needs the angle bias to hide it).
            vec3 T = hbaoSliceTangent(P, n, dir);
            tanT = T.z / max(length(T.xy), 1e-6);
        } else {
            vec2 uvT = uv + dir * rUv / (rUv.x * float(aoSize().x));  // one texel along the slice
            float dT = sceneDepthAlongRay(uvT);
            vec3 T = isSky(dT) ? vec3(dir, 0.0) : viewPosAt(uvT, dT) - P;
            tanT = T.z / max(length(T.xy), 1e-6);
        }
        float t = min(atan(tanT) + biasAngle, 1.5607);
        float tanHmax = tan(t), sinPrev = sin(t), a = 0.0;
        for (int j = 0; j < steps; ++j) {
            vec2 uvS = uv + dir * rUv * ((float(j) + bn.y) / float(steps));
            float zS = sceneDepthAlongRay(uvS);
            if (isSky(zS)) continue;
            vec3 D = viewPosAt(uvS, zS) - P;
            float r2 = dot(D, D), lxy = length(D.xy);
            if (r2 >= R2 || lxy < 1e-6) continue;
            float tanH = D.z / lxy;
            if (tanH > tanHmax) {
                float sinH = tanH * inversesqrt(1.0 + tanH * tanH);
                a += hbaoFalloff(r2, R2) * (sinH - sinPrev);
                sinPrev = sinH;
                tanHmax = tanH;
            }
        }
        sumAo += a;
    }
    return clamp(1.0 - sumAo / float(dirs), 0.0, 1.0);
#elif AO_VARIANT == RTGI_AO_GTAO
    vec2 rUv = aoTextureRadius(R, d, ao.focal.xy);
    vec3 V = normalize(-P);
    int slices = ao.counts.y, steps = ao.counts.z;
    float vis = 0.0, open = 0.0;
    for (int k = 0; k < slices; ++k) {
        float phi = PI * (float(k) + bn.x) / float(slices);
        vec3 dir = vec3(cos(phi), sin(phi), 0.0);
        vec3 ortho = dir - dot(dir, V) * V;
        vec3 axis = normalize(cross(ortho, V));
        vec3 projN = n - axis * dot(n, axis);
        float projLen = length(projN);
        if (projLen < 1e-4) continue;  // normal along the slice axis: the slice sees no hemisphere
        float cosN = clamp(dot(projN, V) / projLen, 0.0, 1.0);
        float nAngle = (dot(ortho, projN) >= 0.0 ? 1.0 : -1.0) * acos(cosN);
        float low0 = cos(nAngle + HALF_PI), low1 = cos(nAngle - HALF_PI);
        float hc0 = low0, hc1 = low1;
        for (int j = 0; j < steps; ++j) {
            float s = (float(j) + bn.y) / float(steps);
            vec2 off = dir.xy * rUv * s;
            for (int side = 0; side < 2; ++side) {
                vec2 uvS = side == 0 ? uv + off : uv - off;
                float zS = sceneDepthAlongRay(uvS);
                if (isSky(zS)) continue;
                vec3 D = viewPosAt(uvS, zS) - P;
                float dist = length(D);
                if (dist < 1e-6) continue;
                // Hard cut at R: the quantity is visibility up to distance R,
                // the reference's ray length. (The former linear falloff from
                // 0.6 R to R shortened the effective range: +0.02 bias on the
                // corner scene, docs/ao.md "Error against ray-traced AO".)
                if (dist >= R) continue;
                float shc = dot(D / dist, V);
                if (side == 0) hc0 = max(hc0, shc); else hc1 = max(hc1, shc);
            }
        }
        float h0 = nAngle + max(-acos(clamp(hc1, -1.0, 1.0)) - nAngle, -HALF_PI);
        float h1 = nAngle + min(acos(clamp(hc0, -1.0, 1.0)) - nAngle, HALF_PI);
        vis += gtaoSliceVisibility(h0, h1, nAngle, projLen);
        open += gtaoSliceVisibility(nAngle - HALF_PI, nAngle + HALF_PI, nAngle, projLen);
    }
    // Self-normalized slice quadrature: a few slices integrate the unoccluded
    // hemisphere only approximately (to 1 +- 0.05 for tilted normals); dividing
    // by the same quadrature of the open hemisphere makes a plane exactly 1
    // instead of clipping the excess at 1 pixel by pixel (a bias under the
    // filter chain). The ratio converges to the same integral (docs/ao.md).
    vis = open > 1e-6 ? clamp(vis / open, 0.0, 1.0) : 1.0;
    if (ao.flags.z != 0) {
        vec2 fullUv = uv;
        vis = gtaoMultiBounce(vis, luminance(texture(uAlbedo, fullUv).rgb));
    }
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
#if AO_DIRECTIONAL == 1
    imageStore(uDirectional, p, vec4(directional(P, n, R, bn).xyz, a));
#elif AO_DIRECTIONAL == 2
    imageStore(uDirectional, p, directional(P, n, R, bn));
#endif
}
