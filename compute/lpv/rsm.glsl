// lpv.rsm texel: reflected flux and the world normal of the lit side. Shared
// by the raster path (lpv/rsm.frag) and the visibility-buffer resolve
// (visibility/rsm_resolve.comp).
//   sun:   flux = albedo · E_perp · A_texel (SPEC 3.2; no n.l factor for an
//          orthographic light, SPEC 11.3);
//   local: a face of a spot / point / area light's perspective RSM:
//          flux = albedo · I(ω) · Ω_texel, the intensity towards the texel
//          (colour, range window, cone or cosine lobe) times the texel's
//          solid angle seen from the light (docs/lpv.md "RSMs of local lights").
#pragma once
#include "lpv/lpv_common.glsl"
#include "lib/brdf.glsl"
#include "lib/lights.glsl"
#include "raster/material.glsl"

// Unit normal of the side that faces `towardLight` (two-sided surfaces: the
// side the light sees is the side that reflects); a degenerate interpolated
// normal falls back to `towardLight`.
vec3 rsmLitSideNormal(vec3 normal, vec3 towardLight) {
    float len = length(normal);
    vec3 n = len > 0.0 ? normal / len : towardLight;
    return dot(n, towardLight) < 0.0 ? -n : n;
}

// `normal`: interpolated vertex normal (not normalized); `baseColor`: materialBaseColor at the texel.
void rsmTexel(vec3 normal, uint material, vec4 baseColor, out vec4 flux, out vec4 outNormal) {
    vec3 albedo = diffuseAlbedo(baseColor.rgb, materials[material].params.y);
    flux = vec4(albedo * frame.sunIrradiance.rgb * lpv.rsm.x, 1.0);
    outNormal = vec4(rsmLitSideNormal(normal, frame.sunDirection.xyz), 1.0);
}

// Local light `g`; `texel`: integer texel of the face, `face` = (tan(half
// field of view), RSM side).
void rsmTexelLocal(GpuLight g, vec3 worldPos, vec3 normal, uint material, vec4 baseColor, vec2 texel,
                   vec2 face, out vec4 flux, out vec4 outNormal) {
    vec3 l;
    float dist;
    float atten = localLightAttenuation(g, worldPos, l, dist) * dist * dist;  // window, cone; no 1/d²
    vec2 lo = (texel / face.y * 2.0 - 1.0) * face.x, hi = ((texel + 1.0) / face.y * 2.0 - 1.0) * face.x;
    vec3 albedo = diffuseAlbedo(baseColor.rgb, materials[material].params.y);
    flux = vec4(albedo * g.colorIntensity.rgb * (atten * planeRectSolidAngle(lo, hi)), 1.0);
    outNormal = vec4(rsmLitSideNormal(normal, l), 1.0);
}
