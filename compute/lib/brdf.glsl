// Lambert + GGX (Trowbridge-Reitz) with Smith height-correlated visibility
// and Schlick Fresnel; roughness is perceptual (alpha = roughness^2).
#pragma once

float ggxD(float NdotH, float alpha) {
    float a2 = alpha * alpha;
    float t = NdotH * NdotH * (a2 - 1.0) + 1.0;
    return a2 / max(3.14159265358979 * t * t, 1e-12);
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

vec3 specularF0(vec3 albedo, float metallic) { return mix(vec3(0.04), albedo, metallic); }
vec3 diffuseAlbedo(vec3 albedo, float metallic) { return albedo * (1.0 - metallic); }

// BRDF × cos for one light direction (radiance per unit irradiance).
vec3 evalBrdfCos(vec3 n, vec3 v, vec3 l, vec3 albedo, float roughness, float metallic) {
    float NdotL = dot(n, l);
    if (NdotL <= 0.0) return vec3(0.0);
    float NdotV = max(dot(n, v), 1e-4);
    vec3 h = normalize(l + v);
    float alpha = max(roughness * roughness, 1e-3);
    vec3 F = fresnelSchlick(specularF0(albedo, metallic), dot(v, h));
    vec3 spec = F * ggxD(max(dot(n, h), 0.0), alpha) * smithVisibility(NdotV, NdotL, alpha);
    vec3 diff = diffuseAlbedo(albedo, metallic) * 0.31830988618379067;
    return (diff + spec) * NdotL;
}
