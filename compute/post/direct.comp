// Direct lighting: sun (shadow-mapped, 3x3 PCF), point/spot lights and
// rectangular area lights (exact diffuse irradiance, representative-point
// GGX; lib/lights.glsl), shadow-mapped with RTGI_LOCAL_SHADOWS (3x3 PCF, or
// soft shadows over the light's extent), emission; sky radiance where no
// geometry was rasterized.
// RTGI_DIFFUSE_ONLY drops the specular lobe (ssr.diffuse_history).
#include "lib/common.glsl"
#include "lib/post_shared.h"
#include "lib/depth.glsl"
#include "lib/brdf.glsl"
#include "lib/lights.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = RTGI_POST_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
layout(binding = RTGI_POST_TEX_NORMAL) uniform sampler2D uNormal;
layout(binding = RTGI_POST_DIRECT_TEX_ALBEDO) uniform sampler2D uAlbedo;
layout(binding = RTGI_POST_DIRECT_TEX_MATERIAL) uniform sampler2D uMaterial;
layout(binding = RTGI_POST_TEX_EMISSIVE) uniform sampler2D uEmissive;
#ifdef RTGI_SUN_SHADOW_MAP
// Declared only with a shadow map bound: NVIDIA reports a shadow sampler on an
// empty unit as undefined behaviour even when it is never sampled.
layout(binding = RTGI_POST_TEX_SHADOW_MAP) uniform sampler2DShadow uShadowMap;
#endif
layout(rgba16f, binding = RTGI_POST_IMG_DIRECT) uniform writeonly image2D uDirect;
#ifdef RTGI_LOCAL_SHADOWS
layout(binding = RTGI_POST_DIRECT_TEX_LOCAL_SHADOWS) uniform sampler2DArrayShadow uLocalShadows;
layout(binding = RTGI_POST_DIRECT_TEX_LOCAL_DEPTH) uniform sampler2DArray uLocalDepth;  // the same maps, raw depth
#endif

#ifdef RTGI_DIFFUSE_ONLY
vec3 lightBrdfCos(vec3 n, vec3 v, vec3 l, vec3 albedo, vec2 rm) { return evalDiffuseCos(n, l, albedo, rm.y); }
#else
vec3 lightBrdfCos(vec3 n, vec3 v, vec3 l, vec3 albedo, vec2 rm) { return evalBrdfCos(n, v, l, albedo, rm.x, rm.y); }
#endif

layout(std430, binding = RTGI_SSBO_LIGHTS) readonly buffer LightBlock { GpuLight lights[]; };
layout(std430, binding = RTGI_SSBO_LIGHT_SHAPES) readonly buffer LightShapeBlock { GpuLightShape lightShapes[]; };

// Radiance reflected towards v from the rectangular area light (sh, g) at p:
// diffuse = ρ/π · Le · Ω⊥ with Ω⊥ the exact projected solid angle of the
// rectangle clipped to the horizon; specular = F·D·V at the representative
// direction × Le · Ω⊥, the lobe widened to α' = min(α + R/(2d), 1) with R =
// √(A/π) the light's equivalent radius and its D renormalized by (α/α')² so
// the widened lobe keeps its energy (docs/lights.md "Area shading").
vec3 areaLightRadiance(GpuLight g, GpuLightShape sh, vec3 p, vec3 n, vec3 v, vec3 albedo, vec2 rm) {
    vec3 nl = cross(sh.halfU.xyz, sh.halfV.xyz);
    float area = 4.0 * length(nl);
    if (!(area > 0.0) || dot(p - sh.centerRadius.xyz, nl) <= 0.0) return vec3(0.0);  // behind the emitter
    vec3 q[4];
    areaLightQuad(sh, p, q);
    float omega = quadProjectedSolidAngle(q, n);
    if (!(omega > 0.0)) return vec3(0.0);
    vec3 le = g.colorIntensity.rgb / area;
    vec3 result = diffuseAlbedo(albedo, rm.y) * INV_PI;
#ifndef RTGI_DIFFUSE_ONLY
    float nv = max(dot(n, v), 1e-4);
    vec3 l = areaLightRepresentativeDir(sh, p, reflect(-v, n));
    float nlr = dot(n, l);
    if (nlr > 0.0) {
        vec3 h = normalize(l + v);
        float alpha = ggxAlpha(rm.x);
        float wide = min(alpha + 0.5 * sqrt(area / PI) / max(length(sh.centerRadius.xyz - p), 1e-6), 1.0);
        float norm = (alpha * alpha) / (wide * wide);
        result += fresnelSchlick(specularF0(albedo, rm.y), dot(v, h)) * ggxD(max(dot(n, h), 0.0), alpha) *
                  smithVisibility(nv, nlr, alpha) * norm;
    }
#endif
    return result * le * omega;
}

// Interleaved gradient noise [Jimenez 2014]: per-pixel jitter of the soft-shadow taps.
vec2 shadowJitter(ivec2 p) {
    float a = fract(52.9829189 * fract(0.06711056 * float(p.x) + 0.00583715 * float(p.y)));
    float b = fract(52.9829189 * fract(0.00583715 * float(p.x) + 0.06711056 * float(p.y)));
    return vec2(a, b);
}

float sunVisibility(vec3 worldPos, vec3 worldNormal) {
#ifndef RTGI_SUN_SHADOW_MAP
    return 1.0;
#else
    // Normal offset against acne; bias in world units from the frame block.
    vec3 p = worldPos + worldNormal * frame.sunIrradiance.a;
    vec4 c = frame.shadowViewProj * vec4(p, 1.0);
    vec3 s = c.xyz / c.w * 0.5 + 0.5;
    if (any(lessThan(s, vec3(0.0))) || any(greaterThan(s, vec3(1.0)))) return 1.0;
    vec2 texel = 1.0 / vec2(textureSize(uShadowMap, 0));
    float v = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) v += texture(uShadowMap, vec3(s.xy + vec2(x, y) * texel, s.z));
    return v / 9.0;
#endif
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, frameSize()))) return;
    float d = texelFetch(uLinearDepth, p, 0).r;
    if (isSky(d)) {
        imageStore(uDirect, p, vec4(clampHalf(frame.sky.rgb), 0.0));
        return;
    }
    vec2 uv = (vec2(p) + 0.5) / vec2(frameSize());
    vec3 vp = viewPositionFromDepth(uv, d, frame.projParams.z, frame.projParams.w);
    vec3 wp = viewToWorldPoint(vp);
    vec3 n = viewToWorldDir(texelFetch(uNormal, p, 0).xyz);
    float nl = length(n);
    n = nl > 0.0 ? n / nl : vec3(0.0, 1.0, 0.0);
    vec3 v = normalize(frame.cameraPos.xyz - wp);
    vec3 albedo = texelFetch(uAlbedo, p, 0).rgb;
    vec2 rm = texelFetch(uMaterial, p, 0).rg;
    vec3 radiance = texelFetch(uEmissive, p, 0).rgb;
    if (frame.sunDirection.w > 0.0) {
        vec3 l = frame.sunDirection.xyz;
        radiance += lightBrdfCos(n, v, l, albedo, rm) * frame.sunIrradiance.rgb * sunVisibility(wp, n);
    }
    for (int i = 0; i < frame.counts.w; ++i) {
        GpuLight L = lights[i];
        int type = int(L.directionType.w);
        if (type == 0) continue;  // culled this frame
        GpuLightShape sh = lightShapes[i];
        vec3 lit;
        float dist;
        if (type == RTGI_LIGHT_AREA) {
            lit = areaLightRadiance(L, sh, wp, n, v, albedo, rm);
            dist = length(L.positionRange.xyz - wp);
        } else {
            vec3 l;
            float atten = localLightAttenuation(L, wp, l, dist);
            if (atten <= 0.0 || dot(n, l) <= 0.0) continue;
            lit = lightBrdfCos(n, v, l, albedo, rm) * L.colorIntensity.rgb * atten;
        }
        if (all(equal(lit, vec3(0.0)))) continue;
#ifdef RTGI_LOCAL_SHADOWS
        lit *= localShadowSoft(uLocalShadows, uLocalDepth, L, sh, wp, n, dist, shadowJitter(p));
#endif
        radiance += lit;
    }
    imageStore(uDirect, p, vec4(clampHalf(radiance), 1.0));
}
