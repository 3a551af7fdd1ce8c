// lpv.rsm: reflected flux per texel = albedo * E_perp * A_texel (SPEC 3.2; no
// n.l factor for an orthographic light, SPEC 11.3) and the world normal of
// the lit side.
#include "lpv/lpv_common.glsl"
#include "lib/brdf.glsl"
#include "raster/material.glsl"

layout(location = 0) in vec3 vWorldPos;
layout(location = 1) in vec3 vNormal;
layout(location = 2) in vec2 vUv;
layout(location = 3) flat in uint vMaterial;

layout(location = 0) out vec4 outFlux;
layout(location = 1) out vec4 outNormal;

void main() {
    vec3 n = vNormal;
    float len = length(n);
    n = len > 0.0 ? n / len : frame.sunDirection.xyz;
    // Two-sided surfaces: the side the sun sees is the side that reflects.
    if (dot(n, frame.sunDirection.xyz) < 0.0) n = -n;
    vec3 albedo = diffuseAlbedo(materialBaseColor(vMaterial, vUv).rgb, materials[vMaterial].params.y);
    outFlux = vec4(albedo * frame.sunIrradiance.rgb * lpv.rsm.x, 1.0);
    outNormal = vec4(n, 1.0);
}
