// lpv.upsample (lpv.apply_resolution=half; docs/lpv.md, "Half-resolution apply"): the
// half-resolution apply's albedo-free terms (irradiance / pi with the sky alpha; specular
// radiance) to full resolution by joint bilateral upsampling (lib/filter.glsl, the AO chain's
// weights times a normal weight; a pixel none of whose taps is its surface mixes in the best texel of
// the 4x4 around it, upsampleWiden), then times this pixel's albedo (1 - metallic) and BRDF, as
// lpv/apply.comp does at full resolution. Sky pixels get (0, 0, 0, 1) and no specular.
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"
#include "lib/depth.glsl"
#include "lib/brdf.glsl"
#include "lib/filter.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_2D, local_size_y = RTGI_LPV_LOCAL_2D) in;

layout(binding = RTGI_LPV_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
layout(binding = RTGI_LPV_TEX_VIEW_NORMAL) uniform sampler2D uViewNormal;
layout(binding = RTGI_LPV_TEX_ALBEDO) uniform sampler2D uAlbedo;
layout(binding = RTGI_LPV_TEX_MATERIAL) uniform sampler2D uMaterial;
layout(binding = RTGI_LPV_TEX_BRDF_LUT) uniform sampler2D uBrdfLut;
layout(binding = RTGI_LPV_UPSAMPLE_TEX_LOW_INDIRECT) uniform sampler2D uLowIndirect;
layout(binding = RTGI_LPV_UPSAMPLE_TEX_LOW_SPECULAR) uniform sampler2D uLowSpecular;
layout(binding = RTGI_LPV_UPSAMPLE_TEX_LOW_GEOMETRY) uniform sampler2D uLowGeometry;
layout(rgba16f, binding = RTGI_LPV_IMG_INDIRECT) uniform writeonly image2D uIndirect;
layout(rgba16f, binding = RTGI_LPV_IMG_SPECULAR) uniform writeonly image2D uSpecular;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, frameSize()))) return;
    float d = texelFetch(uLinearDepth, p, 0).r;
    if (isSky(d)) {
        imageStore(uIndirect, p, vec4(0.0, 0.0, 0.0, 1.0));
#ifdef RTGI_LPV_SPECULAR
        imageStore(uSpecular, p, vec4(0.0, 0.0, 0.0, 1.0));
#endif
        return;
    }
    vec2 uv = (vec2(p) + 0.5) / vec2(frameSize());
    vec3 vn = texelFetch(uViewNormal, p, 0).xyz;
    vec3 albedo = texelFetch(uAlbedo, p, 0).rgb;
    vec2 rm = texelFetch(uMaterial, p, 0).rg;
    UpsampleTaps taps = upsampleTaps(uLowGeometry, uv, d, true, vn);  // one set of weights for both terms
    upsampleWiden(taps, uLowGeometry, uv, d, vn, 0.01);
    vec4 e = upsampleApply(uLowIndirect, taps);
    imageStore(uIndirect, p, vec4(diffuseAlbedo(albedo, rm.y) * e.rgb, e.a));
#ifdef RTGI_LPV_SPECULAR
    vec3 radiance = upsampleApply(uLowSpecular, taps).rgb;
    vec3 f0 = specularF0(albedo, rm.y);
#ifdef RTGI_LPV_BRDF_LUT
    vec3 vp = viewPositionFromDepth(uv, d, frame.projParams.z, frame.projParams.w);
    vec3 n = dot(vn, vn) > 0.0 ? normalize(viewToWorldDir(vn)) : vec3(0.0, 1.0, 0.0);
    vec3 v = normalize(frame.cameraPos.xyz - viewToWorldPoint(vp));
    vec2 ab = texture(uBrdfLut, vec2(clamp(dot(n, v), 0.0, 1.0), rm.x)).rg;
    vec3 brdf = f0 * ab.x + ab.y;
#else
    vec3 brdf = f0;
#endif
    imageStore(uSpecular, p, vec4(brdf * radiance, 1.0));
#endif
}
