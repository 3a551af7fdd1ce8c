// Scene access and light transport pieces of the reference path tracer:
// surface data at a BVH hit (GpuScene vertex/index buffers, material
// table), next-event estimation of the sun and punctual lights with shadow
// rays, BRDF sampling.
#pragma once
#include "lib/common.glsl"
#include "lib/brdf.glsl"
#include "lib/random.glsl"
#include "lib/sampling.glsl"
#include "lib/bvh.glsl"

layout(std430, binding = RTGI_SSBO_MATERIALS) readonly buffer RefMaterialBlock { GpuMaterial materials[]; };
layout(std430, binding = RTGI_SSBO_LIGHTS) readonly buffer RefLightBlock { GpuLight lights[]; };
// GpuVertex: position[3], normal[3], uv[2], material (uint bits): 9 words.
layout(std430, binding = RTGI_SSBO_REF_VERTICES) readonly buffer RefVertexBlock { float refVertexWords[]; };
layout(std430, binding = RTGI_SSBO_REF_INDICES) readonly buffer RefIndexBlock { uint refIndices[]; };
layout(binding = RTGI_TEX_MATERIALS) uniform sampler2DArray uBaseColorTextures;

struct Surface {
    vec3 position;
    vec3 normal;    // shading normal, facing the viewer (the incoming ray's origin)
    vec3 geometric; // geometric normal, same side as `normal`
    vec3 albedo;
    float roughness;
    float metallic;
    vec3 emission;
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
    // Two-sided surfaces: both normals face the side the ray came from.
    if (dot(s.geometric, rayDir) > 0.0) s.geometric = -s.geometric;
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
    s.emission = mat.emissive.rgb;
    return s;
}

// BRDF × cos of the reference: the real-time BRDF (brdf.glsl) or, with
// RTGI_REF_DIFFUSE_ONLY, its Lambert lobe alone (furnace tests, diffuse-only
// comparisons).
vec3 refBrdfCos(vec3 n, vec3 v, vec3 l, vec3 albedo, float roughness, float metallic) {
#ifdef RTGI_REF_DIFFUSE_ONLY
    return diffuseAlbedo(albedo, metallic) * INV_PI * max(dot(n, l), 0.0);
#else
    return evalBrdfCos(n, v, l, albedo, roughness, metallic);
#endif
}

// Sun and point/spot lights at p with shadow rays (the same attenuation as
// post/direct.comp: inverse square, KHR_lights_punctual range window, spot
// smoothstep). origin = p offset off the surface.
vec3 directLight(Surface s, vec3 v, vec3 origin) {
    vec3 L = vec3(0.0);
    if (frame.sunDirection.w > 0.0) {
        vec3 l = frame.sunDirection.xyz;
        if (dot(s.geometric, l) > 0.0 && !traceAny(origin, l, 0.0, BVH_MISS))
            L += refBrdfCos(s.normal, v, l, s.albedo, s.roughness, s.metallic) * frame.sunIrradiance.rgb;
    }
    for (int i = 0; i < frame.counts.x; ++i) {
        GpuLight g = lights[i];
        vec3 toL = g.positionRange.xyz - s.position;
        float dist2 = max(dot(toL, toL), 1e-8);
        float dist = sqrt(dist2);
        vec3 l = toL / dist;
        float atten = 1.0 / dist2;
        if (g.positionRange.w > 0.0) {
            float r = dist / g.positionRange.w;
            atten *= clamp(1.0 - r * r * r * r, 0.0, 1.0);
        }
        if (int(g.directionType.w) == RTGI_LIGHT_SPOT) atten *= smoothstep(g.cone.y, g.cone.x, dot(-l, normalize(g.directionType.xyz)));
        if (atten <= 0.0 || dot(s.geometric, l) <= 0.0) continue;
        if (traceAny(origin, l, 0.0, dist)) continue;
        L += refBrdfCos(s.normal, v, l, s.albedo, s.roughness, s.metallic) * g.colorIntensity.rgb * atten;
    }
    return L;
}

// Samples an outgoing direction for the BRDF at n: one-sample mixture of
// the cosine lobe and GGX half-vector sampling (pdf D·NdotH, Walter et al.
// 2007 eq. 35/38), weight = BRDF·cos / mixture pdf (balance heuristic over
// the two techniques). Returns false when the direction is below the surface.
bool sampleBrdf(vec3 n, vec3 v, vec3 albedo, float roughness, float metallic, inout Rng rng, out vec3 l,
                out vec3 weight) {
#ifdef RTGI_REF_DIFFUSE_ONLY
    const float pSpec = 0.0;
#else
    const float pSpec = 0.5;
#endif
    float alpha = max(roughness * roughness, 1e-3);
    float choose = rngNext(rng);
    vec2 u = rngNext2(rng);
    if (choose < pSpec) {
        float phi = TWO_PI * u.x;
        float cosT = sqrt((1.0 - u.y) / (1.0 + (alpha * alpha - 1.0) * u.y));
        float sinT = sqrt(max(1.0 - cosT * cosT, 0.0));
        vec3 h = basisAround(n) * vec3(sinT * cos(phi), sinT * sin(phi), cosT);
        l = reflect(-v, h);
    } else {
        l = cosineHemisphere(u, n);
    }
    float nl = dot(n, l);
    weight = vec3(0.0);
    if (nl <= 0.0) return false;
    vec3 h = normalize(l + v);
    float pdf = (1.0 - pSpec) * nl * INV_PI;
    if (pSpec > 0.0) pdf += pSpec * ggxD(max(dot(n, h), 0.0), alpha) * max(dot(n, h), 0.0) / max(4.0 * dot(v, h), 1e-6);
    if (!(pdf > 0.0)) return false;
    weight = refBrdfCos(n, v, l, albedo, roughness, metallic) / pdf;
    return true;
}
