// ssr.resolve: the hit reprojected into the previous frame with the velocity
// buffer (seed 000 5.4), radiance fetched from the previous frame's history
// (full HDR or diffuse-only), premultiplied by the confidence:
// out = (L·c, c), so that blur and temporal filtering stay linear.
#include "lib/common.glsl"
#include "lib/ssr_shared.h"
#include "lib/filter.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, binding = RTGI_UBO_SSR) uniform SsrBlock { SsrUniforms ssr; };
layout(binding = RTGI_SSR_TEX_HIT) uniform sampler2D uHit;
layout(binding = RTGI_SSR_TEX_CONFIDENCE) uniform sampler2D uConfidence;
layout(binding = RTGI_SSR_TEX_VELOCITY) uniform sampler2D uVelocity;
layout(binding = RTGI_SSR_TEX_HISTORY) uniform sampler2D uHistory;  // bilinear; a: the previous linear depth
layout(binding = RTGI_SSR_RESOLVE_TEX_LINEAR_DEPTH) uniform sampler2D uDepth;  // full resolution
layout(rgba16f, binding = RTGI_SSR_IMG_RESOLVED) uniform writeonly image2D uResolved;

layout(location = RTGI_SSR_LOC_HAVE_HISTORY) uniform int uHaveHistory;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ssr.sizes.xy))) return;
    vec4 outValue = vec4(0.0);
    float c = texelFetch(uConfidence, p, 0).r;
    if (uHaveHistory != 0 && c > 0.0) {
        ivec2 full = min(p * ssr.params.w, ssr.sizes.zw - 1);
        vec2 hitUv = (vec2(full) + 0.5) / vec2(ssr.sizes.zw) + texelFetch(uHit, p, 0).xy;
        ivec2 hitPixel = clamp(ivec2(hitUv * vec2(ssr.sizes.zw)), ivec2(0), ssr.sizes.zw - 1);
        vec2 velocity = texelFetch(uVelocity, hitPixel, 0).xy;
        vec2 prevUv = hitUv + velocity;
        vec4 history = textureLod(uHistory, prevUv, 0.0);
        vec3 radiance = history.rgb;
        bool inside = all(greaterThanEqual(prevUv, vec2(0.0))) && all(lessThanEqual(prevUv, vec2(1.0)));
        bool finite = !any(isnan(radiance)) && !any(isinf(radiance));
        // The hit point's history must be the hit surface (docs/temporal.md, "Disocclusion"); the hit's depth is
        // the G-buffer's at the hit pixel, its previous depth from the camera step (history depth fp16: 2^-10).
        float zHit = texelFetch(uDepth, hitPixel, 0).r;
        bool same = false;
        if (zHit > 0.0) {
            vec3 P = vec3((hitUv * 2.0 - 1.0) * frame.projParams.z * vec2(frame.projParams.w, 1.0) * zHit, -zHit);
            float expected = -(frame.prevView * vec4(viewToWorldPoint(P), 1.0)).z;
            same = !historyDisoccluded(history.a, expected, zHit, depthSlopePerPixel(uDepth, hitPixel, ssr.sizes.zw, zHit),
                                       velocity * vec2(ssr.sizes.zw), exp2(-10.0));
        }
        if (inside && finite && same) outValue = vec4(max(radiance, vec3(0.0)) * c, c);
    }
    imageStore(uResolved, p, outValue);
}
