// ssr.shade (full resolution): specular = splitSum(F0, n·v, roughness) ×
// reflection × specular occlusion + LPV specular × (1 − specular occlusion)
// (seed 000 5.2.6, 5.4; SPEC 3.6, 5). The filtered reflection is
// premultiplied (L·c, c); at ssr.resolution=half (RTGI_SSR_SHADE_UPSAMPLE) it is
// brought to the pixel here by the shared joint bilateral upsampling (lib/filter.glsl,
// the traced pixels' depth as the guide), only for the pixels SSR shades.
#include "lib/common.glsl"
#include "lib/depth.glsl"
#include "lib/brdf.glsl"
#include "lib/ssr_shared.h"
#ifdef RTGI_SSR_SHADE_UPSAMPLE
#include "lib/filter.glsl"
#endif

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, binding = RTGI_UBO_SSR) uniform SsrBlock { SsrUniforms ssr; };
layout(binding = RTGI_SSR_TEX_REFLECTION) uniform sampler2D uReflection;  // trace resolution
#ifdef RTGI_SSR_SHADE_UPSAMPLE
layout(binding = RTGI_SSR_SHADE_TEX_LOW_DEPTH) uniform sampler2D uLowDepth;
#endif
layout(binding = RTGI_SSR_TEX_BRDF_LUT) uniform sampler2D uBrdfLut;     // bilinear, (n·v, roughness)
layout(binding = RTGI_SSR_SHADE_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
layout(binding = RTGI_SSR_SHADE_TEX_NORMAL) uniform sampler2D uNormal;
layout(binding = RTGI_SSR_TEX_ALBEDO) uniform sampler2D uAlbedo;
layout(binding = RTGI_SSR_SHADE_TEX_MATERIAL) uniform sampler2D uMaterial;
layout(rgba16f, binding = RTGI_SSR_IMG_SPECULAR) uniform image2D uSpecular;  // LPV specular in (when uHaveLpv), result out
layout(r16f, binding = RTGI_SSR_IMG_OCCLUSION) uniform writeonly image2D uOcclusion;

layout(location = RTGI_SSR_LOC_HAVE_LPV) uniform int uHaveLpv;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ssr.sizes.zw))) return;
    vec3 lpv = uHaveLpv != 0 ? imageLoad(uSpecular, p).rgb : vec3(0.0);
    float d = texelFetch(uLinearDepth, p, 0).r;
    vec2 rm = texelFetch(uMaterial, p, 0).rg;
    vec4 reflection = vec4(0.0);
    vec3 splitSum = vec3(0.0);
    if (!isSky(d) && rm.x <= ssr.trace.y) {
        vec2 uv = (vec2(p) + 0.5) / vec2(ssr.sizes.zw);
        vec3 v = -normalize(viewPositionFromDepth(uv, d, frame.projParams.z, frame.projParams.w));
        vec3 n = texelFetch(uNormal, p, 0).xyz;
        float nn = dot(n, n);
        float NdotV = nn > 1e-12 && nn < 1e12 ? clamp(dot(n * inversesqrt(nn), v), 0.0, 1.0) : 0.0;
        vec2 ab = textureLod(uBrdfLut, vec2(NdotV, rm.x), 0.0).rg;
        splitSum = specularF0(texelFetch(uAlbedo, p, 0).rgb, rm.y) * ab.x + ab.y;
#ifdef RTGI_SSR_SHADE_UPSAMPLE
        reflection = upsampleJoint(uReflection, uLowDepth, uv, d, false, vec3(0.0));
#else
        reflection = texelFetch(uReflection, p, 0);
#endif
        reflection.a = clamp(reflection.a, 0.0, 1.0);
    }
    imageStore(uSpecular, p, vec4(splitSum * reflection.rgb + lpv * (1.0 - reflection.a), 1.0));
    imageStore(uOcclusion, p, vec4(reflection.a));
}
