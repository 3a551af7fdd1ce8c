// ssr.trace: one mirror-reflection ray per trace pixel (half resolution by
// default) with the tracer chosen by RTGI_SSR_TRACER (lib/ssr_shared.h).
// Writes the hit's uv offset from the pixel (RG16F), the confidence /
// specular occlusion (R16F, 1 hit, 0 miss) and the view-space hit distance.
// With RTGI_SSR_HALF it also keeps the traced pixel's linear depth and normal
// at trace resolution: the shared blur / temporal / upsample read them.
// The start jitter of linear and DDA is the project's blue noise (8 variants).
#include "lib/common.glsl"
#include "lib/depth.glsl"
#include "lib/noise.glsl"
#include "lib/ssr.glsl"
#include "lib/ssr_shared.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, binding = RTGI_UBO_SSR) uniform SsrBlock { SsrUniforms ssr; };
layout(binding = RTGI_SSR_TRACE_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
layout(binding = RTGI_SSR_TRACE_TEX_NORMAL) uniform sampler2D uNormal;
layout(binding = RTGI_SSR_TRACE_TEX_MATERIAL) uniform sampler2D uMaterial;
layout(binding = RTGI_SSR_TEX_HIZ) uniform sampler2D uHiz;
layout(binding = RTGI_SSR_TEX_NOISE) uniform sampler2DArray uNoise;  // res.blueNoise
layout(rg16f, binding = RTGI_SSR_IMG_HIT) uniform writeonly image2D uHit;
layout(r16f, binding = RTGI_SSR_IMG_CONFIDENCE) uniform writeonly image2D uConfidence;
layout(r16f, binding = RTGI_SSR_IMG_HIT_DISTANCE) uniform writeonly image2D uHitDistance;
#ifdef RTGI_SSR_HALF
layout(r32f, binding = RTGI_SSR_IMG_TRACE_DEPTH) uniform writeonly image2D uTraceDepth;
layout(rgba16f, binding = RTGI_SSR_IMG_TRACE_NORMAL) uniform writeonly image2D uTraceNormal;
#endif

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ssr.sizes.xy))) return;
    ivec2 full = min(p * ssr.params.w, ssr.sizes.zw - 1);
    vec2 hitOffset = vec2(0.0);
    float confidence = 0.0, distance = 0.0;
    float d = texelFetch(uLinearDepth, full, 0).r;
    vec4 normal = texelFetch(uNormal, full, 0);
#ifdef RTGI_SSR_HALF
    imageStore(uTraceDepth, p, vec4(d));
    imageStore(uTraceNormal, p, normal);
#endif
    float roughness = texelFetch(uMaterial, full, 0).r;
    vec2 uv = (vec2(full) + 0.5) / vec2(ssr.sizes.zw);
    vec3 origin = viewPositionFromDepth(uv, d, frame.projParams.z, frame.projParams.w);
    vec3 dir;
    if (!isSky(d) && roughness <= ssr.trace.y &&
        ssrReflectionRay(origin, normal.xyz, dir)) {
        SsrCamera cam = SsrCamera(frame.projParams.z, frame.projParams.w, frame.projParams.x, frame.projParams.y,
                                  vec2(ssr.sizes.zw));
#if RTGI_SSR_TRACER == RTGI_SSR_HIZ
        SsrHit h = ssrTraceHiz(uHiz, ssr.params.z, origin, dir, cam, ssr.params.x, ssr.trace.x);
#else
        float jitter = ssrJitter(blueNoise(uNoise, p, frameIndex()).x);
#if RTGI_SSR_TRACER == RTGI_SSR_DDA
        SsrHit h = ssrTraceDda(uLinearDepth, origin, dir, cam, ssr.params.x, ssr.trace.x, jitter);
#else
        SsrHit h = ssrTraceLinear(uLinearDepth, origin, dir, cam, ssr.params.x, ssr.trace.x, jitter);
#endif
#endif
        confidence = ssrConfidence(h, dir, ssr.trace.z);
        if (confidence > 0.0) {
            hitOffset = h.uv - uv;
            vec3 q = viewPositionFromDepth(h.uv, h.rayDepth, frame.projParams.z, frame.projParams.w);
            distance = length(q - origin);
        }
    }
    imageStore(uHit, p, vec4(hitOffset, 0.0, 0.0));
    imageStore(uConfidence, p, vec4(confidence));
    imageStore(uHitDistance, p, vec4(distance));
}
