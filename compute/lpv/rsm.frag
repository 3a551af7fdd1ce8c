// lpv.rsm: reflected flux per texel = albedo * E_perp * A_texel (SPEC 3.2; no
// n.l factor for an orthographic light, SPEC 11.3) and the world normal of
// the lit side. RTGI_RSM_LOCAL: a face of a spot / point / area light's
// perspective RSM: flux = albedo · I(ω) · Ω_texel, the intensity towards the
// texel (colour, range window, cone or cosine lobe) times the texel's solid
// angle seen from the light (docs/lpv.md "RSMs of local lights").
#include "lpv/lpv_common.glsl"
#include "lib/brdf.glsl"
#include "raster/material.glsl"
#ifdef RTGI_RSM_LOCAL
#include "lib/lights.glsl"
layout(location = RTGI_LPV_RSM_LOC_LIGHT) uniform vec4 uLight[4];  // the GpuLight: positionRange, colorIntensity, directionType, cone
layout(location = RTGI_LPV_RSM_LOC_FACE) uniform vec2 uFace;       // tan(half field of view), RSM side R
#endif

layout(location = 0) in vec3 vWorldPos;
layout(location = 1) in vec3 vNormal;
layout(location = 2) in vec2 vUv;
layout(location = 3) flat in uint vMaterial;

layout(location = 0) out vec4 outFlux;
layout(location = 1) out vec4 outNormal;

void main() {
    vec3 n = vNormal;
    float len = length(n);
    vec3 albedo = diffuseAlbedo(materialBaseColor(vMaterial, vUv).rgb, materials[vMaterial].params.y);
#ifdef RTGI_RSM_LOCAL
    GpuLight g = GpuLight(uLight[0], uLight[1], uLight[2], uLight[3]);
    vec3 l;
    float dist;
    float atten = localLightAttenuation(g, vWorldPos, l, dist) * dist * dist;  // window, cone; no 1/d²
    n = len > 0.0 ? n / len : l;
    if (dot(n, l) < 0.0) n = -n;  // two-sided: the side the light sees reflects
    vec2 texel = floor(gl_FragCoord.xy);
    vec2 lo = (texel / uFace.y * 2.0 - 1.0) * uFace.x, hi = ((texel + 1.0) / uFace.y * 2.0 - 1.0) * uFace.x;
    outFlux = vec4(albedo * g.colorIntensity.rgb * (atten * planeRectSolidAngle(lo, hi)), 1.0);
#else
    n = len > 0.0 ? n / len : frame.sunDirection.xyz;
    // Two-sided surfaces: the side the sun sees is the side that reflects.
    if (dot(n, frame.sunDirection.xyz) < 0.0) n = -n;
    outFlux = vec4(albedo * frame.sunIrradiance.rgb * lpv.rsm.x, 1.0);
#endif
    outNormal = vec4(n, 1.0);
}
