// The six screen-space AO estimators and the directional (bent normal / S3HO)
// integral as pure functions (XeGTAO style): every input is a parameter, the
// library has no bindings, no uniform block and no #if on a variant.
//
// The scene is read through functions the including entry point defines
// (GLSL has no function pointers; the prototypes below are resolved at link
// time of the one compilation unit, so the .comp may define them before or
// after this include):
//   float aoSceneDepth(vec2 uv)               linear depth of the first surface
//                                             along the exact camera ray through
//                                             uv; 0 (isSky) where free or off-screen
//   float aoPointOcclusion(vec3 P, vec3 S, float R)
//                                             point test of the sample-point
//                                             variants: 0 free .. 1 occluded
//                                             (camera depth: aoCameraPointOcclusion;
//                                             light depth: the shadow map)
//   float aoSceneDepth2(vec2 uv)              vbao with a second layer: linear depth
//                                             of the nearest surface at least the
//                                             thickness behind the first (texel of
//                                             uv); none: 0 or FLT_MAX
//   vec3  aoKernel(int i)                     unit-ball offset i (RTGI_AO_MAX_KERNEL)
//   vec4  aoVoSample(int i)                   VO pair i: xy disk position, z half-
//                                             length, w normalized volume weight
// compute/ao/ao.comp is the entry point; a test may define the four over an
// analytic scene instead of textures. View space as in lib/ao.glsl.
#pragma once
#include "lib/ao.glsl"
#include "lib/ao_shared.h"
#include "lib/depth.glsl"
#include "lib/math.glsl"
#include "lib/sampling.glsl"
#include "lib/sh.glsl"

float aoSceneDepth(vec2 uv);
float aoSceneDepth2(vec2 uv);
#ifdef AO_VBAO_GATHER
// aoVbao's gather hooks (near-field light through the bitmask): a sample at uvS (view
// position S, depth zS) first occludes sectors of cosine-weighted measure w (0 when it
// occludes nothing new); each slice's open measure once after its march.
void aoVbaoGather(vec2 uvS, vec3 S, float zS, float w);
void aoVbaoGatherOpen(float open);
#endif
float aoPointOcclusion(vec3 P, vec3 S, float R);
vec3 aoKernel(int i);
vec4 aoVoSample(int i);

// The camera: focal = (cot(fovY/2)/aspect, cot(fovY/2)) (eq. 5.3), the
// projection of lib/depth.glsl, and the AO resolution (texels of the depth
// the estimators march).
struct AoCamera {
    vec2 focal;
    float tanHalfFov;
    float aspect;
    vec2 size;
};

vec3 aoViewPosAt(AoCamera cam, vec2 uv, float d) { return viewPositionFromDepth(uv, d, cam.tanHalfFov, cam.aspect); }

// Point test against the camera's depth: S is occluded when the scene seen
// through it lies in front of it (bias 2 % of R against self-occlusion),
// range-attenuated by the depth distance of the blocker to P.
float aoCameraPointOcclusion(AoCamera cam, vec3 P, vec3 S, float R) {
    vec3 uvS = uvFromViewPosition(S, cam.tanHalfFov, cam.aspect);
    float zScene = aoSceneDepth(uvS.xy);
    if (isSky(zScene) || zScene >= uvS.z - 0.02 * R) return 0.0;
    return rangeAttenuation(R, abs(-P.z - zScene));
}

// ssao-disk (Kajalin / Crytek, seed 003 3.1): the full-sphere kernel reflected
// by the tiled 4x4 noise vector. pointTest: each sample is scored by
// aoPointOcclusion (light depth) instead of eqs. 3.1-3.3 on the camera depth.
float aoSsaoDisk(AoCamera cam, vec3 P, float d, float R, vec3 noiseVec, int count, bool removeEdgeHighlight,
                 bool pointTest) {
    if (dot(noiseVec, noiseVec) < 1e-6) noiseVec = vec3(0, 0, 1);
    noiseVec = normalize(noiseVec);
    float sum = 0.0;
    for (int i = 0; i < count; ++i) {
        vec3 S = P + R * reflect(aoKernel(i), noiseVec);
        if (pointTest) {
            sum += 1.0 - aoPointOcclusion(P, S, R);
        } else {
            vec3 uvS = uvFromViewPosition(S, cam.tanHalfFov, cam.aspect);
            float zScene = aoSceneDepth(uvS.xy);
            sum += isSky(zScene) ? 1.0 : ssaoDiskSampleValue(d, uvS.z, zScene);
        }
    }
    float v = sum / float(count);
    return removeEdgeHighlight ? halfSpaceNormalize(v) : v;
}

// ssao-sphere (kernel rotated about the view axis, half-space normalized) and
// ssao-hemisphere (kernel folded onto the normal's side). noise: x rotation,
// y radius jitter (seed 000 5.3 after [Jp16]).
float aoSsaoKernel(vec3 P, vec3 n, float R, vec2 noise, int count, bool hemisphere) {
    float a = TWO_PI * noise.x;
    mat3 basis = aoBasis(hemisphere ? n : vec3(0, 0, 1), vec3(cos(a), sin(a), 0.0));
    float radiusJitter = 0.75 + 0.5 * noise.y;
    float occ = 0.0;
    for (int i = 0; i < count; ++i) {
        vec3 o = aoKernel(i);
        if (hemisphere) o.z = abs(o.z);
        occ += aoPointOcclusion(P, P + R * radiusJitter * (basis * o), R);
    }
    float v = 1.0 - occ / float(count);
    return hemisphere ? v : halfSpaceNormalize(v);
}

// vo (Loos & Sloan line samples, seed 003 3.2): pairs p, -p rotated by
// noiseAngle in [0, pi); a scene point more than maxOccluderDistance in
// front of the line is invalid and takes its partner's complement.
float aoVo(AoCamera cam, vec2 uv, float d, float R, float noiseAngle, int pairs, float maxOccluderDistance) {
    vec2 rUv = aoTextureRadius(R, d, cam.focal);
    mat2 rot = mat2(cos(noiseAngle), sin(noiseAngle), -sin(noiseAngle), cos(noiseAngle));
    float vis = 0.0;
    for (int i = 0; i < pairs; ++i) {
        vec4 s = aoVoSample(i);
        vec2 off = (rot * s.xy) * rUv;
        float frac[2];
        bool valid[2];
        for (int k = 0; k < 2; ++k) {
            float zScene = aoSceneDepth(uv + (k == 0 ? off : -off));
            // Sky is infinitely far: the line is free.
            valid[k] = isSky(zScene) || d - zScene < maxOccluderDistance;
            frac[k] = isSky(zScene) ? 1.0 : voLineFree(s.z, (zScene - d) / R) / (2.0 * s.z);
        }
        if (!valid[0] && !valid[1]) frac[0] = frac[1] = 0.5;
        else if (!valid[0]) frac[0] = 1.0 - frac[1];
        else if (!valid[1]) frac[1] = 1.0 - frac[0];
        vis += s.w * 0.5 * (frac[0] + frac[1]);
    }
    return halfSpaceNormalize(vis);
}

// hbao (Bavoil & Sainz 2008, seed 003 3.3): `dirs` directions rotated by
// noise.x over 360/dirs, `steps` steps jittered by noise.y; tangent from the
// normal's slice (useNormals) or from the depth one texel along the slice.
float aoHbao(AoCamera cam, vec2 uv, vec3 P, vec3 n, float d, float R, vec2 noise, int dirs, int steps, float tanBias,
             bool useNormals) {
    vec2 rUv = aoTextureRadius(R, d, cam.focal);
    if (rUv.x * cam.size.x < 1.0) return 1.0;  // radius below one pixel: nothing to find
    float R2 = R * R;
    float biasAngle = atan(tanBias);
    float sumAo = 0.0;
    for (int k = 0; k < dirs; ++k) {
        float phi = TWO_PI * (float(k) + noise.x) / float(dirs);
        vec2 dir = vec2(cos(phi), sin(phi));
        float tanT;
        if (useNormals) {
            // Tangent of the slice: the line where the tangent plane meets the
            // plane through the eye that holds this screen direction. Every
            // in-plane sample of the march lies on it, so a plane gives
            // tanH == tanT exactly (the view-aligned -n.xy.dir/n.z differs
            // off-axis under perspective and needs the angle bias to hide it).
            vec3 T = hbaoSliceTangent(P, n, dir);
            tanT = T.z / max(length(T.xy), 1e-6);
        } else {
            vec2 uvT = uv + dir * rUv / (rUv.x * cam.size.x);  // one texel along the slice
            float dT = aoSceneDepth(uvT);
            vec3 T = isSky(dT) ? vec3(dir, 0.0) : aoViewPosAt(cam, uvT, dT) - P;
            tanT = T.z / max(length(T.xy), 1e-6);
        }
        float t = min(atan(tanT) + biasAngle, 1.5607);
        float tanHmax = tan(t), sinPrev = sin(t), a = 0.0;
        for (int j = 0; j < steps; ++j) {
            vec2 uvS = uv + dir * rUv * ((float(j) + noise.y) / float(steps));
            float zS = aoSceneDepth(uvS);
            if (isSky(zS)) continue;
            vec3 D = aoViewPosAt(cam, uvS, zS) - P;
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
}

// Slice k of `slices` of gtao and vbao: its screen direction (rotated by
// `rotation` over 180/slices), the length of the normal projected into the
// slice plane and the normal's angle from V in it (Jimenez et al. 2016, eq. 5).
// False when the normal lies along the slice axis (no hemisphere in the slice).
bool aoSlice(int k, int slices, float rotation, vec3 V, vec3 n, out vec3 dir, out float projLen, out float nAngle) {
    float phi = PI * (float(k) + rotation) / float(slices);
    dir = vec3(cos(phi), sin(phi), 0.0);
    vec3 ortho = dir - dot(dir, V) * V;
    vec3 axis = normalize(cross(ortho, V));
    vec3 projN = n - axis * dot(n, axis);
    projLen = length(projN);
    nAngle = 0.0;
    if (projLen < 1e-4) return false;
    float cosN = clamp(dot(projN, V) / projLen, 0.0, 1.0);
    nAngle = (dot(ortho, projN) >= 0.0 ? 1.0 : -1.0) * acos(cosN);
    return true;
}

// The cosine-weighted mean direction of a slice's visible arc [h0, h1] (view angles from V,
// positive towards `ortho`; h0 <= 0 <= h1): the integral over the arc of
// w(t) cos(t - n) |sin t| dt, w(t) = V cos t + ortho sin t, |sin t| the slice measure of the
// hemisphere (Jimenez et al. 2016, bent normals; derived here from the antiderivatives
// Fo(t) = cos n sin^3 t / 3 + sin n (cos^3 t / 3 - cos t) and Fv(t) = (sin n sin^3 t - cos n cos^3 t) / 3,
// split at t = 0 where |sin t| changes sign). Summed over the slices, weighted by projLen, it is
// the integral of V(w) w (n.w)+ over the hemisphere: the bent normal's direction.
vec3 gtaoSliceBent(float h0, float h1, float n, vec3 V, vec3 ortho) {
    float cn = cos(n), sn = sin(n);
    float s0 = sin(h0), c0 = cos(h0), s1 = sin(h1), c1 = cos(h1);
    float fo = cn * (s1 * s1 * s1 + s0 * s0 * s0) / 3.0 + sn * ((c1 * c1 * c1 + c0 * c0 * c0) / 3.0 - c0 - c1) + sn * (4.0 / 3.0);
    float fv = (sn * (s1 * s1 * s1 + s0 * s0 * s0) - cn * (c1 * c1 * c1 + c0 * c0 * c0)) / 3.0 + cn * (2.0 / 3.0);
    return ortho * fo + V * fv;
}

// gtao (Jimenez et al. 2016, seed 000 4.1): `slices` slices rotated by
// noise.x over 180/slices, `steps` steps per side jittered by noise.y;
// cosine-weighted visibility up to distance R (without multi-bounce).
// `bent`: the normalized sum of the slices' gtaoSliceBent (n where nothing is visible).
float aoGtaoBent(AoCamera cam, vec2 uv, vec3 P, vec3 n, float d, float R, vec2 noise, int slices, int steps,
                 out vec3 bent) {
    vec2 rUv = aoTextureRadius(R, d, cam.focal);
    vec3 V = normalize(-P);
    float vis = 0.0, open = 0.0;
    vec3 bentSum = vec3(0.0);
    for (int k = 0; k < slices; ++k) {
        vec3 dir;
        float projLen, nAngle;
        // normal along the slice axis: the slice sees no hemisphere
        if (!aoSlice(k, slices, noise.x, V, n, dir, projLen, nAngle)) continue;
        float low0 = cos(nAngle + HALF_PI), low1 = cos(nAngle - HALF_PI);
        float hc0 = low0, hc1 = low1;
        // The bent normal's horizons (hb): a sample at distance t < R raises them by the share 1 - t/R
        // of its elevation above the hemisphere's edge. A point-sample estimate of eq. 17 (rays) counts a
        // direction blocked at distance t as open for the samples nearer than t; with the hard horizons
        // the direction bent away from everything behind a thin column within R (the atrium court's
        // final error +1.7 %, docs/ao.md "Bent normals from the slices").
        float hb0 = low0, hb1 = low1;
        for (int j = 0; j < steps; ++j) {
            float s = (float(j) + noise.y) / float(steps);
            vec2 off = dir.xy * rUv * s;
            for (int side = 0; side < 2; ++side) {
                vec2 uvS = side == 0 ? uv + off : uv - off;
                float zS = aoSceneDepth(uvS);
                if (isSky(zS)) continue;
                vec3 D = aoViewPosAt(cam, uvS, zS) - P;
                float dist = length(D);
                if (dist < 1e-6) continue;
                // Hard cut at R: the quantity is visibility up to distance R,
                // the reference's ray length. (The former linear falloff from
                // 0.6 R to R shortened the effective range: +0.02 bias on the
                // corner scene, docs/ao.md "Error against ray-traced AO".)
                if (dist >= R) continue;
                float shc = dot(D / dist, V);
                float sb = mix(side == 0 ? low0 : low1, shc, 1.0 - dist / R);
                if (side == 0) hc0 = max(hc0, shc), hb0 = max(hb0, sb); else hc1 = max(hc1, shc), hb1 = max(hb1, sb);
            }
        }
        float h0 = nAngle + max(-acos(clamp(hc1, -1.0, 1.0)) - nAngle, -HALF_PI);
        float h1 = nAngle + min(acos(clamp(hc0, -1.0, 1.0)) - nAngle, HALF_PI);
        vis += gtaoSliceVisibility(h0, h1, nAngle, projLen);
        open += gtaoSliceVisibility(nAngle - HALF_PI, nAngle + HALF_PI, nAngle, projLen);
        vec3 ortho = dir - dot(dir, V) * V;
        float b0 = nAngle + max(-acos(clamp(hb1, -1.0, 1.0)) - nAngle, -HALF_PI);
        float b1 = nAngle + min(acos(clamp(hb0, -1.0, 1.0)) - nAngle, HALF_PI);
        bentSum += projLen * gtaoSliceBent(b0, b1, nAngle, V, ortho * inversesqrt(max(dot(ortho, ortho), 1e-12)));
    }
    bent = dot(bentSum, bentSum) > 1e-12 ? normalize(bentSum) : n;
    // Self-normalized slice quadrature: a few slices integrate the unoccluded
    // hemisphere only approximately (to 1 +- 0.05 for tilted normals); dividing
    // by the same quadrature of the open hemisphere makes a plane exactly 1
    // instead of clipping the excess at 1 pixel by pixel (a bias under the
    // filter chain). The ratio converges to the same integral (docs/ao.md).
    return open > 1e-6 ? clamp(vis / open, 0.0, 1.0) : 1.0;
}

float aoGtao(AoCamera cam, vec2 uv, vec3 P, vec3 n, float d, float R, vec2 noise, int slices, int steps) {
    vec3 bent;
    return aoGtaoBent(cam, uv, P, n, d, R, noise, slices, steps, bent);
}

// vbao (visibility bitmask, Therrien et al. 2023): GTAO's slices and march,
// the two horizons replaced by a 32-sector bitmask of the slice's hemisphere.
// A sample S (first surface through the marched uv) occludes the view angles
// of its column: S pushed away from the camera along its view ray to linear
// depth z_S + T (T = thickness, or thickness * z_S when depthScaled), clipped
// to the sphere of radius R around P (the reference's ray length).
// thickness < 0: infinite (GTAO's assumption: everything below the horizon of
// a sample within R is occluded, up to the hemisphere's edge). noise: x slice
// rotation, y step jitter, z sector jitter. Visibility cosine-weighted and
// self-normalized as gtao (vis / open). secondLayer: with a finite thickness,
// the second layer's surface behind each sample adds its own column.
float aoVbao(AoCamera cam, vec2 uv, vec3 P, vec3 n, float d, float R, vec3 noise, int slices, int steps,
             float thickness, bool depthScaled, bool secondLayer) {
    vec2 rUv = aoTextureRadius(R, d, cam.focal);
    vec3 V = normalize(-P);
    float vis = 0.0, open = 0.0;
    for (int k = 0; k < slices; ++k) {
        vec3 dir;
        float projLen, nAngle;
        // normal along the slice axis: the slice sees no hemisphere
        if (!aoSlice(k, slices, noise.x, V, n, dir, projLen, nAngle)) continue;
        uint occluded = 0u;
        for (int j = 0; j < steps; ++j) {
            float s = (float(j) + noise.y) / float(steps);
            vec2 off = dir.xy * rUv * s;
            for (int side = 0; side < 2; ++side) {
                float sgn = side == 0 ? 1.0 : -1.0;
                vec2 uvS = uv + sgn * off;
                float zS = aoSceneDepth(uvS);
                if (isSky(zS)) continue;
                vec3 S = aoViewPosAt(cam, uvS, zS);
                uint m;
                if (thickness < 0.0) {
                    vec3 D = S - P;
                    float dist = length(D);
                    if (dist >= R || dist < 1e-6) continue;
                    float a = sgn * acos(clamp(dot(D / dist, V), -1.0, 1.0));
                    // to the hemisphere's edge on this side
                    m = vbaoSectorMask(min(a, sgn * PI), max(a, sgn * PI), nAngle, noise.z);
                } else {
                    m = vbaoColumnMask(P, V, S, zS, depthScaled ? thickness * zS : thickness, R, sgn, nAngle, noise.z);
                }
#ifdef AO_VBAO_GATHER
                // The sectors this sample occludes first see it (near-field light, docs/ao.md
                // "Bitmask near-field light"); the hook is the including entry point's.
                aoVbaoGather(uvS, S, zS, projLen * vbaoOccludedArc(m & ~occluded, nAngle));
#endif
                occluded |= m;
                // The second layer: a surface the depth buffer hides, at least the
                // thickness behind S, with a column of its own (docs/ao.md "Second depth layer").
                float z2 = secondLayer && thickness >= 0.0 ? aoSceneDepth2(uvS) : 0.0;
                if (z2 > zS && z2 < 1e30)
                    occluded |= vbaoColumnMask(P, V, S * (z2 / zS), z2, depthScaled ? thickness * z2 : thickness, R, sgn,
                                               nAngle, noise.z);
            }
        }
        float full = vbaoArc(nAngle + HALF_PI, nAngle) - vbaoArc(nAngle - HALF_PI, nAngle);
        vis += projLen * (full - vbaoOccludedArc(occluded, nAngle));
        open += projLen * full;
#ifdef AO_VBAO_GATHER
        aoVbaoGatherOpen(projLen * full);
#endif
    }
    return open > 1e-6 ? clamp(vis / open, 0.0, 1.0) : 1.0;
}

// Directional occlusion from cosine-distributed, normal-oriented samples
// (seed 000 4.3): xyz bent normal (eq. 17, w 0) when sh is false, else the 4
// SH coefficients of V(l)(n.l)+ (the LPV family's basis: lpv.apply consumes
// it). noise: z azimuth rotation, w radial stratum jitter, y kernel shift.
vec4 aoDirectional(vec3 P, vec3 n, float R, vec4 noise, int count, bool sh) {
    mat3 basis = aoBasis(n, vec3(cos(TWO_PI * noise.z), sin(TWO_PI * noise.z), 0.0));
    vec3 bent = vec3(0.0);
    vec4 shSum = vec4(0.0);
    for (int i = 0; i < count; ++i) {
        // Stratified in cos^2 (radial) and golden-ratio azimuth, rotated per pixel.
        vec2 u = vec2((float(i) + noise.w) / float(count), fract(float(i) * 0.6180339887 + noise.z));
        vec3 l = basis * cosineHemisphere(u);
        // The sample's distance: a kernel radius drawn by a per-pixel shift of
        // the index. Taking kernel[i] paired elevation stratum i with the same
        // radius on every pixel, a fixed coupling that biased the result (the
        // grazing strata reached farther: 1.5 % too much occlusion on the
        // corner, tests/gpu/test_ao_oracles.cpp "bent normals and S3HO").
        int kernelSize = min(count, RTGI_AO_MAX_KERNEL);
        float r = R * length(aoKernel((i + int(noise.y * float(kernelSize))) % kernelSize));
        float v = 1.0 - aoPointOcclusion(P, P + l * max(r, 0.1 * R), R);
        bent += v * l;
        shSum += v * shBasis(l);
    }
    if (!sh) return vec4(dot(bent, bent) > 1e-12 ? normalize(bent) : n, 0.0);
    return shSum * (PI / float(count));  // cosine-weighted pdf cos/pi -> integral of V Y (n.l)+
}
