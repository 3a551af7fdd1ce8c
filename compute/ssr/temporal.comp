// ssr.temporal: the temporal filter of the shared chain (lib/filter.glsl,
// seed 000 listing 11, SPEC 6.2) on the premultiplied reflection, with the
// trace-resolution linear depth kept beside it for the next frame.
#include "lib/common.glsl"
#include "lib/filter.glsl"
#include "lib/ssr_shared.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, binding = RTGI_UBO_SSR) uniform SsrBlock { SsrUniforms ssr; };
layout(binding = 0) uniform sampler2D uCurrent;
layout(binding = 1) uniform sampler2D uHistory;       // previous output, bilinear
layout(binding = 2) uniform sampler2D uHistoryDepth;  // previous trace-resolution depth
layout(binding = 3) uniform sampler2D uLinearDepth;
layout(binding = 4) uniform sampler2D uVelocity;
layout(rgba16f, binding = 0) uniform writeonly image2D uTarget;
layout(r32f, binding = 1) uniform writeonly image2D uDepthOut;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ssr.sizes.xy))) return;
    ivec2 full = min(p * ssr.params.w, ssr.sizes.zw - 1);
    float depth = texelFetch(uLinearDepth, full, 0).r;
    vec4 current = texelFetch(uCurrent, p, 0);
    vec2 velocity = texelFetch(uVelocity, full, 0).xy;
    vec2 prevUv = (vec2(p) + 0.5) / vec2(ssr.sizes.xy) + velocity;
    float alpha = 1.0;
    if (ssr.temporal.x > 0.0 && !cameraCut()) {
        float prevDepth = textureLod(uHistoryDepth, prevUv, 0.0).r;
        alpha = temporalAlpha(abs(depth - prevDepth), velocity, prevUv);
    }
    vec4 history = alpha < 1.0 ? textureLod(uHistory, prevUv, 0.0) : current;
    imageStore(uTarget, p, mix(history, current, alpha));
    imageStore(uDepthOut, p, vec4(depth));
}
