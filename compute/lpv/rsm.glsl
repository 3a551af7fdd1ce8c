// lpv.rsm texel: reflected flux = albedo * E_perp * A_texel (SPEC 3.2; no
// n.l factor for an orthographic light, SPEC 11.3) and the world normal of
// the lit side. Shared by the raster path (lpv/rsm.frag) and the
// visibility-buffer resolve (visibility/rsm_resolve.comp).
#pragma once
#include "lpv/lpv_common.glsl"
#include "lib/brdf.glsl"
#include "raster/material.glsl"

// `normal`: interpolated vertex normal (not normalized); `baseColor`: materialBaseColor at the texel.
void rsmTexel(vec3 normal, uint material, vec4 baseColor, out vec4 flux, out vec4 outNormal) {
    vec3 n = normal;
    float len = length(n);
    n = len > 0.0 ? n / len : frame.sunDirection.xyz;
    // Two-sided surfaces: the side the sun sees is the side that reflects.
    if (dot(n, frame.sunDirection.xyz) < 0.0) n = -n;
    vec3 albedo = diffuseAlbedo(baseColor.rgb, materials[material].params.y);
    flux = vec4(albedo * frame.sunIrradiance.rgb * lpv.rsm.x, 1.0);
    outNormal = vec4(n, 1.0);
}
