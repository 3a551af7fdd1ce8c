// Direct lighting: sun (shadow-mapped, 3x3 PCF), point/spot/area lights
// (shadow-mapped with RTGI_LOCAL_SHADOWS, 3x3 PCF, lib/lights.glsl),
// emission; sky radiance where no geometry was rasterized.
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
layout(binding = RTGI_POST_TEX_SHADOW_MAP) uniform sampler2DShadow uShadowMap;
layout(rgba16f, binding = RTGI_POST_IMG_DIRECT) uniform writeonly image2D uDirect;
#ifdef RTGI_LOCAL_SHADOWS
layout(binding = RTGI_POST_DIRECT_TEX_LOCAL_SHADOWS) uniform sampler2DArrayShadow uLocalShadows;
#endif

layout(location = RTGI_POST_LOC_HAS_SHADOW_MAP) uniform int uHasShadowMap;

#ifdef RTGI_DIFFUSE_ONLY
vec3 lightBrdfCos(vec3 n, vec3 v, vec3 l, vec3 albedo, vec2 rm) { return evalDiffuseCos(n, l, albedo, rm.y); }
#else
vec3 lightBrdfCos(vec3 n, vec3 v, vec3 l, vec3 albedo, vec2 rm) { return evalBrdfCos(n, v, l, albedo, rm.x, rm.y); }
#endif

layout(std430, binding = RTGI_SSBO_LIGHTS) readonly buffer LightBlock { GpuLight lights[]; };

float sunVisibility(vec3 worldPos, vec3 worldNormal) {
    if (uHasShadowMap == 0) return 1.0;
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
        vec3 l;
        float dist;
        float atten = localLightAttenuation(L, wp, l, dist);
        if (atten <= 0.0 || dot(n, l) <= 0.0) continue;
#ifdef RTGI_LOCAL_SHADOWS
        atten *= localShadow(uLocalShadows, L, wp, n, dist);
#endif
        radiance += lightBrdfCos(n, v, l, albedo, rm) * L.colorIntensity.rgb * atten;
    }
    imageStore(uDirect, p, vec4(clampHalf(radiance), 1.0));
}
