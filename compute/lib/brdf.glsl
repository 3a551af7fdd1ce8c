// Lambert + GGX (Trowbridge-Reitz) with Smith height-correlated visibility
// and Schlick Fresnel; roughness is perceptual (alpha = roughness^2).
#pragma once
#include "lib/math.glsl"

float ggxD(float NdotH, float alpha) {
    float a2 = alpha * alpha;
    float t = NdotH * NdotH * (a2 - 1.0) + 1.0;
    return a2 / max(PI * t * t, 1e-12);
}

// Smith-GGX height-correlated visibility V = G / (4 NdotL NdotV).
float smithVisibility(float NdotV, float NdotL, float alpha) {
    float a2 = alpha * alpha;
    float gv = NdotL * sqrt(NdotV * NdotV * (1.0 - a2) + a2);
    float gl = NdotV * sqrt(NdotL * NdotL * (1.0 - a2) + a2);
    return 0.5 / max(gv + gl, 1e-12);
}

vec3 fresnelSchlick(vec3 f0, float VdotH) {
    float f = pow(1.0 - clamp(VdotH, 0.0, 1.0), 5.0);
    return f0 + (1.0 - f0) * f;
}

// Perceptual roughness -> GGX alpha, floored so D stays finite for mirrors.
float ggxAlpha(float roughness) { return max(roughness * roughness, 1e-3); }

// Hammersley point i of n in [0,1)^2 (radical inverse in base 2).
vec2 hammersley(uint i, uint n) { return vec2((float(i) + 0.5) / float(n), float(bitfieldReverse(i)) * 2.3283064365386963e-10); }

// GGX half vector in tangent space (z = normal) distributed with pdf
// D(h)·(n·h) [Walter et al. 2007, eq. 35-36]; xi uniform in [0,1)^2.
vec3 importanceSampleGgx(vec2 xi, float alpha) {
    float phi = TWO_PI * xi.y;
    float cosTheta = sqrt((1.0 - xi.x) / max(1.0 + (alpha * alpha - 1.0) * xi.x, 1e-12));
    float sinTheta = sqrt(max(1.0 - cosTheta * cosTheta, 0.0));
    return vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
}

// Split-sum environment BRDF [Kar13]: (A, B) with ∫ f·cos dl = F0·A + B for
// a GGX lobe with F = 1 split by Schlick's (1 − v·h)^5, estimated with n GGX
// importance samples in a frame where n = (0, 0, 1), v in the xz plane.
// With pdf(l) = D·(n·h) / (4 v·h), f·cos/pdf = 4·V·(n·l)·(v·h)/(n·h).
vec2 splitSumIntegral(float NdotV, float roughness, uint n) {
    NdotV = clamp(NdotV, 1e-4, 1.0);
    float alpha = ggxAlpha(roughness);
    vec3 v = vec3(sqrt(1.0 - NdotV * NdotV), 0.0, NdotV);
    vec2 ab = vec2(0.0);
    for (uint i = 0u; i < n; ++i) {
        vec3 h = importanceSampleGgx(hammersley(i, n), alpha);
        float VdotH = dot(v, h);
        vec3 l = 2.0 * VdotH * h - v;
        if (l.z <= 0.0 || VdotH <= 0.0) continue;
        float w = 4.0 * smithVisibility(NdotV, l.z, alpha) * l.z * VdotH / max(h.z, 1e-12);
        float fc = pow(1.0 - VdotH, 5.0);
        ab += vec2((1.0 - fc) * w, fc * w);
    }
    return ab / float(n);
}

vec3 specularF0(vec3 albedo, float metallic) { return mix(vec3(0.04), albedo, metallic); }
vec3 diffuseAlbedo(vec3 albedo, float metallic) { return albedo * (1.0 - metallic); }

// BRDF × cos for one light direction (radiance per unit irradiance).
vec3 evalBrdfCos(vec3 n, vec3 v, vec3 l, vec3 albedo, float roughness, float metallic) {
    float NdotL = dot(n, l);
    if (NdotL <= 0.0) return vec3(0.0);
    float NdotV = max(dot(n, v), 1e-4);
    vec3 h = normalize(l + v);
    float alpha = ggxAlpha(roughness);
    vec3 F = fresnelSchlick(specularF0(albedo, metallic), dot(v, h));
    vec3 spec = F * ggxD(max(dot(n, h), 0.0), alpha) * smithVisibility(NdotV, NdotL, alpha);
    vec3 diff = diffuseAlbedo(albedo, metallic) * INV_PI;
    return (diff + spec) * NdotL;
}

// Diffuse part of evalBrdfCos alone (diffuse-only radiance, ssr.diffuse_history).
vec3 evalDiffuseCos(vec3 n, vec3 l, vec3 albedo, float metallic) {
    return diffuseAlbedo(albedo, metallic) * INV_PI * max(dot(n, l), 0.0);
}
