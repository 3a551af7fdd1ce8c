// Scene access and light transport pieces of the reference path tracer:
// surface data at a BVH hit (GpuScene vertex/index buffers, material
// table), next-event estimation of the sun, punctual lights and emissive
// triangles with shadow rays, BRDF sampling.
#pragma once
#include "lib/common.glsl"
#include "lib/brdf.glsl"
#include "lib/random.glsl"
#include "lib/sampling.glsl"
#include "lib/bvh.glsl"
#include "lib/lights.glsl"

layout(std430, binding = RTGI_SSBO_MATERIALS) readonly buffer RefMaterialBlock { GpuMaterial materials[]; };
layout(std430, binding = RTGI_SSBO_LIGHTS) readonly buffer RefLightBlock { GpuLight lights[]; };
// GpuVertex: position[3], normal[3], uv[2], material (uint bits): 9 words.
layout(std430, binding = RTGI_SSBO_REF_VERTICES) readonly buffer RefVertexBlock { float refVertexWords[]; };
layout(std430, binding = RTGI_SSBO_REF_INDICES) readonly buffer RefIndexBlock { uint refIndices[]; };
layout(binding = RTGI_TEX_MATERIALS) uniform sampler2DArray uBaseColorTextures;
// Emissive triangles for next-event estimation: pairs (triangle id, CDF of
// area up to and including it, as float bits), in GpuScene index order.
layout(std430, binding = RTGI_SSBO_REF_EMITTERS) readonly buffer RefEmitterBlock { uint refEmitters[]; };
#ifdef RTGI_REF_EMITTER_NEE
// x: emitter count, y: total emissive area
layout(location = RTGI_REF_LOC_EMITTERS) uniform vec2 uEmitters;
#endif

struct Surface {
    vec3 position;
    vec3 normal;    // shading normal, facing the viewer (the incoming ray's origin)
    vec3 geometric; // geometric normal, same side as `normal`
    vec3 albedo;
    float roughness;
    float metallic;
    vec3 emission;
    float specular; // 1: Lambert + GGX; 0: Lambert only (reference.caustics=off after a diffuse vertex)
};

vec3 refVertexVec3(uint v, uint offset) {
    uint b = v * 9u + offset;
    return vec3(refVertexWords[b], refVertexWords[b + 1u], refVertexWords[b + 2u]);
}

Surface surfaceAt(Hit h, vec3 rayOrigin, vec3 rayDir) {
    uint i0 = refIndices[3u * h.triangle], i1 = refIndices[3u * h.triangle + 1u], i2 = refIndices[3u * h.triangle + 2u];
    vec3 w = vec3(1.0 - h.bary.x - h.bary.y, h.bary);
    vec3 p0 = refVertexVec3(i0, 0u), p1 = refVertexVec3(i1, 0u), p2 = refVertexVec3(i2, 0u);
    Surface s;
    s.position = rayOrigin + rayDir * h.t;
    vec3 ng = cross(p1 - p0, p2 - p0);
    float lg = length(ng);
    s.geometric = lg > 0.0 ? ng / lg : -rayDir;
    vec3 ns = w.x * refVertexVec3(i0, 3u) + w.y * refVertexVec3(i1, 3u) + w.z * refVertexVec3(i2, 3u);
    float ls = length(ns);
    s.normal = ls > 0.0 ? ns / ls : s.geometric;
    // Two-sided surfaces: both normals face the side the ray came from. Emission leaves
    // single-sided emitters only from their front (counter-clockwise) face.
    bool back = dot(s.geometric, rayDir) > 0.0;
    if (back) s.geometric = -s.geometric;
    if (dot(s.normal, s.geometric) < 0.0) s.normal = -s.normal;
    uint m = floatBitsToUint(refVertexWords[i0 * 9u + 8u]);
    vec2 uv = w.x * vec2(refVertexWords[i0 * 9u + 6u], refVertexWords[i0 * 9u + 7u]) +
              w.y * vec2(refVertexWords[i1 * 9u + 6u], refVertexWords[i1 * 9u + 7u]) +
              w.z * vec2(refVertexWords[i2 * 9u + 6u], refVertexWords[i2 * 9u + 7u]);
    GpuMaterial mat = materials[m];
    vec3 base = mat.baseColor.rgb;
    // Level 0: a compute shader has no derivatives; the many samples per
    // pixel filter the texture instead of the mip chain.
    if (mat.params.z >= 0.0) base *= textureLod(uBaseColorTextures, vec3(uv, mat.params.z), 0.0).rgb;
    s.albedo = base;
    s.roughness = mat.params.x;
    s.metallic = mat.params.y;
    s.emission = back && mat.emissive.a == 0.0 ? vec3(0.0) : mat.emissive.rgb;
    s.specular = 1.0;
    return s;
}

// ---- caustic paths (reference.caustics) ----------------------------------
// A path is "diffuse" from the first vertex whose sampled direction came
// from the cosine lobe, or whose roughness is at least
// RTGI_REF_CAUSTIC_ROUGHNESS. Later vertices see light through a glossy
// lobe: camera → diffuse → glossy → light, the caustic paths none of the
// real-time techniques model and the source of the reference's fireflies
// (a sharp GGX lobe evaluated towards the sun by next-event estimation).
//   regularized: path-space regularization (Kaplanyan & Dachsbacher 2013,
//     "Path Space Regularization for Holistic and Robust Light
//     Transport"): such a vertex is shaded with roughness at least
//     RTGI_REF_CAUSTIC_ROUGHNESS — the lobe is widened, so its peak value
//     (and the variance) is bounded, at a bias the docs measure;
//   off: such a vertex reflects with its Lambert lobe only (the caustic
//     transport is removed: biased dark where caustics exist);
//   on (neither define): unmodified.
void refRegularize(inout Surface s, bool afterDiffuse) {
#if defined(RTGI_REF_CAUSTICS_REGULARIZED)
    if (afterDiffuse) s.roughness = max(s.roughness, RTGI_REF_CAUSTIC_ROUGHNESS);
#elif defined(RTGI_REF_CAUSTICS_OFF)
    if (afterDiffuse) s.specular = 0.0;
#endif
}

// Whether the path is diffuse after leaving s by a sample of the given lobe.
bool refDiffuseAfter(Surface s, bool specularLobe, bool afterDiffuse) {
#ifdef RTGI_REF_CAUSTIC_ROUGHNESS
    return afterDiffuse || !specularLobe || s.roughness >= RTGI_REF_CAUSTIC_ROUGHNESS;
#else
    return afterDiffuse || !specularLobe;
#endif
}

// BRDF × cos of the reference: the real-time BRDF (brdf.glsl) or, with
// RTGI_REF_DIFFUSE_ONLY, its Lambert lobe alone (furnace tests, diffuse-only
// comparisons).
vec3 refBrdfCos(Surface s, vec3 v, vec3 l) {
#ifdef RTGI_REF_DIFFUSE_ONLY
    return evalDiffuseCos(s.normal, l, s.albedo, s.metallic);
#else
    return s.specular > 0.0 ? evalBrdfCos(s.normal, v, l, s.albedo, s.roughness, s.metallic)
                            : evalDiffuseCos(s.normal, l, s.albedo, s.metallic);
#endif
}

// Sun and point/spot lights at p with shadow rays (the attenuation of
// lib/lights.glsl, shared with post/direct.comp). origin = p offset off the
// surface. Only the scene's own lights (frame.counts.x): emissive surfaces
// are sampled as what they are (sampleEmitters), not as the real-time
// path's area-light approximations.
vec3 directLight(Surface s, vec3 v, vec3 origin) {
    vec3 L = vec3(0.0);
    if (frame.sunDirection.w > 0.0) {
        vec3 l = frame.sunDirection.xyz;
        if (dot(s.geometric, l) > 0.0 && !traceAny(origin, l, 0.0, BVH_MISS))
            L += refBrdfCos(s, v, l) * frame.sunIrradiance.rgb;
    }
    for (int i = 0; i < frame.counts.x; ++i) {
        GpuLight g = lights[i];
        vec3 l;
        float dist;
        float atten = localLightAttenuation(g, s.position, l, dist);
        if (atten <= 0.0 || dot(s.geometric, l) <= 0.0) continue;
        if (traceAny(origin, l, 0.0, dist)) continue;
        L += refBrdfCos(s, v, l) * g.colorIntensity.rgb * atten;
    }
    return L;
}

#ifdef RTGI_REF_DIFFUSE_ONLY
const float REF_P_SPEC = 0.0;
#else
const float REF_P_SPEC = 0.5;
#endif

// Solid-angle pdf of sampleBrdf's one-sample mixture: cosine lobe (1 − p)
// and GGX half-vector sampling p (pdf D·N·H / (4 V·H), Walter et al. 2007
// eq. 35/38). The MIS weights of emitter sampling need it for any l.
float brdfPdf(Surface s, vec3 v, vec3 l) {
    vec3 n = s.normal;
    float nl = dot(n, l);
    if (nl <= 0.0) return 0.0;
    float pSpec = REF_P_SPEC * s.specular;
    float pdf = (1.0 - pSpec) * nl * INV_PI;
    if (pSpec > 0.0) {
        float alpha = max(s.roughness * s.roughness, 1e-3);
        vec3 h = normalize(l + v);
        pdf += pSpec * ggxD(max(dot(n, h), 0.0), alpha) * max(dot(n, h), 0.0) / max(4.0 * dot(v, h), 1e-6);
    }
    return pdf;
}

// Samples an outgoing direction for the BRDF of s from the mixture above;
// weight = BRDF·cos / mixture pdf (balance heuristic over the two
// techniques), pdf = the mixture's solid-angle pdf, specularLobe = which
// technique drew it. Returns false when the direction is below the surface.
bool sampleBrdf(Surface s, vec3 v, inout Rng rng, out vec3 l, out vec3 weight, out float pdf, out bool specularLobe) {
    vec3 n = s.normal;
    float alpha = max(s.roughness * s.roughness, 1e-3);
    float choose = rngNext(rng);
    vec2 u = rngNext2(rng);
    specularLobe = choose < REF_P_SPEC * s.specular;
    if (specularLobe) {
        float phi = TWO_PI * u.x;
        float cosT = sqrt((1.0 - u.y) / (1.0 + (alpha * alpha - 1.0) * u.y));
        float sinT = sqrt(max(1.0 - cosT * cosT, 0.0));
        vec3 h = basisAround(n) * vec3(sinT * cos(phi), sinT * sin(phi), cosT);
        l = reflect(-v, h);
    } else {
        l = cosineHemisphere(u, n);
    }
    weight = vec3(0.0);
    pdf = brdfPdf(s, v, l);
    if (!(pdf > 0.0)) return false;
    weight = refBrdfCos(s, v, l) / pdf;
    return true;
}

// ---- emissive triangles: area-weighted light sampling with MIS ----------
// An emitter point y is drawn uniformly over the total emissive area A
// (pick a triangle by its area CDF, then a uniform point on it), so its
// solid-angle pdf at x is p_light = d² / (|cos θ_y| · A). A single-sided
// emitter (glTF doubleSided = false) sends light only from its front,
// counter-clockwise face, in both techniques (surfaceAt zeroes the emission
// a BRDF-sampled ray finds on its back); a double-sided one from either. Both techniques are combined with the power heuristic
// (Veach 1997, ch. 9): a BRDF-sampled ray that hits an emitter is weighted
// p_brdf² / (p_brdf² + p_light²), the light sample by the complement.

#ifdef RTGI_REF_EMITTER_NEE
float emitterLightPdf(float dist2, float cosY) {
    return uEmitters.y > 0.0 && cosY > 0.0 ? dist2 / (cosY * uEmitters.y) : 0.0;
}
#endif

float misPower(float a, float b) {
    float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

// MIS weight of emission found by a BRDF-sampled ray (pdf brdfPdfValue)
// that left `from` and hit the emitter at distance t with geometric normal ng.
float emissionMisWeight(float brdfPdfValue, float t, vec3 rd, vec3 ng) {
#ifdef RTGI_REF_EMITTER_NEE
    return misPower(brdfPdfValue, emitterLightPdf(t * t, abs(dot(ng, rd))));
#else
    return 1.0;
#endif
}

// One light sample on the emissive triangles for the surface s seen from v;
// origin = s.position offset off the surface, magnitude = its fp scale.
vec3 sampleEmitters(Surface s, vec3 v, vec3 origin, inout Rng rng) {
#ifdef RTGI_REF_EMITTER_NEE
    int count = int(uEmitters.x);
    if (count <= 0 || !(uEmitters.y > 0.0)) return vec3(0.0);
    float target = rngNext(rng) * uEmitters.y;
    // Binary search for the first emitter whose CDF exceeds target.
    int lo = 0, hi = count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (uintBitsToFloat(refEmitters[2 * mid + 1]) > target) hi = mid;
        else lo = mid + 1;
    }
    uint tri = refEmitters[2 * lo];
    vec2 u = rngNext2(rng);
    uint i0 = refIndices[3u * tri], i1 = refIndices[3u * tri + 1u], i2 = refIndices[3u * tri + 2u];
    vec3 p0 = refVertexVec3(i0, 0u), p1 = refVertexVec3(i1, 0u), p2 = refVertexVec3(i2, 0u);
    float su = sqrt(u.x);  // uniform on the triangle (Turk 1990)
    vec3 y = (1.0 - su) * p0 + su * (1.0 - u.y) * p1 + su * u.y * p2;
    vec3 ng = cross(p1 - p0, p2 - p0);
    float lg = length(ng);
    if (!(lg > 0.0)) return vec3(0.0);
    ng /= lg;
    vec3 toY = y - s.position;
    float dist2 = dot(toY, toY);
    if (!(dist2 > 0.0)) return vec3(0.0);
    vec3 l = toY * inversesqrt(dist2);
    float cosY = abs(dot(ng, l));
    if (dot(s.geometric, l) <= 0.0 || dot(s.normal, l) <= 0.0 || cosY <= 0.0) return vec3(0.0);
    vec4 emissive = materials[floatBitsToUint(refVertexWords[i0 * 9u + 8u])].emissive;
    vec3 le = emissive.rgb;
    if (all(equal(le, vec3(0.0))) || (emissive.a == 0.0 && dot(ng, l) >= 0.0)) return vec3(0.0);
    // The shadow ray ends at y moved off the emitter towards the receiver,
    // so the emitter itself never occludes its own sample.
    vec3 yOff = offsetRayOrigin(y, dot(ng, l) < 0.0 ? ng : -ng, maxAbs(s.position));
    vec3 seg = yOff - origin;
    float len = length(seg);
    if (!(len > 0.0) || traceAny(origin, seg / len, 0.0, len)) return vec3(0.0);
    float pl = emitterLightPdf(dist2, cosY);
    float w = misPower(pl, brdfPdf(s, v, l));
    return refBrdfCos(s, v, l) * le * (w / pl);
#else
    return vec3(0.0);
#endif
}

// Radiance arriving along (ro, rd), times `throughput`: at most maxBounces
// surfaces (each adds its emission and next-event direct light), Russian
// roulette from the third on; the ray was sampled at its origin with
// solid-angle pdf `pdf` (the MIS weight of emission it hits). Without
// RTGI_REF_FULL (indirect kind), the first segment is the one leaving the
// G-buffer surface x1: a ray escaping there sees no sky (the compose pass's
// ambient term) and emission hit there is weighted 1 (x1 samples no
// emitters), or 0 with RTGI_REF_EMISSION_IS_DIRECT. Shared by ref/path.comp
// and the LPV probe reference lpv/probe.comp (a cell centre in place of x1,
// the same matching-bounce transport). afterDiffuse: whether the path was
// already diffuse when it left ro (reference.caustics, refRegularize).
vec3 refTraceRadiance(vec3 ro, vec3 rd, float pdf, vec3 throughput, uint maxBounces, bool afterDiffuse, inout Rng rng) {
    vec3 L = vec3(0.0);
    for (uint bounce = 1u; bounce <= maxBounces; ++bounce) {
        Hit h;
        if (!traceClosest(ro, rd, 0.0, BVH_MISS, h)) {
#ifndef RTGI_REF_FULL
            if (bounce == 1u) break;  // direct skylight at x1: the compose pass's ambient term
#endif
            L += throughput * frame.sky.rgb;
            break;
        }
        Surface x = surfaceAt(h, ro, rd);
        refRegularize(x, afterDiffuse);
        vec3 v = -rd;
        vec3 origin = offsetRayOrigin(x.position, x.geometric, maxAbs(ro));
        float misWeight = emissionMisWeight(pdf, h.t, rd, x.geometric);
#ifndef RTGI_REF_FULL
        if (bounce == 1u) misWeight = 1.0;  // x1 samples no emitters in the indirect kind
#ifdef RTGI_REF_EMISSION_IS_DIRECT
        if (bounce == 1u) misWeight = 0.0;  // emission seen from x1 is x1's direct light (emissive.lights=on)
#endif
#endif
        L += throughput * x.emission * misWeight;
        L += throughput * (directLight(x, v, origin) + sampleEmitters(x, v, origin, rng));
        if (bounce == maxBounces) break;
        vec3 l, w;
        bool specularLobe;
        if (!sampleBrdf(x, v, rng, l, w, pdf, specularLobe)) break;
        afterDiffuse = refDiffuseAfter(x, specularLobe, afterDiffuse);
        if (dot(l, x.geometric) <= 0.0) break;  // shading normal sent the ray into the surface
        throughput *= w;
        if (bounce >= 3u) {
            float q = min(max(throughput.r, max(throughput.g, throughput.b)), 0.95);
            if (rngNext(rng) >= q) break;
            throughput /= q;
        }
        ro = origin;
        rd = l;
    }
    return L;
}
