// Temporal reprojection filter exactly as seed 000 listing 11 (SPEC 6.2) on
// any value texture (FILTER_FORMAT). Keeps its own history of value and
// linear depth; uReset (camera cut / no history) takes the current value.
#include "lib/depth.glsl"
#include "lib/filter_shared.h"
#include "lib/filter.glsl"

#ifndef FILTER_FORMAT
#define FILTER_FORMAT r16f
#endif

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = RTGI_FILTER_TEX_CURRENT) uniform sampler2D uCurrent;
layout(binding = RTGI_FILTER_TEX_HISTORY) uniform sampler2D uHistory;       // previous output (bilinear)
layout(binding = RTGI_FILTER_TEMPORAL_TEX_DEPTH) uniform sampler2D uDepth;         // current linear depth, filter resolution
layout(binding = RTGI_FILTER_TEX_HISTORY_DEPTH) uniform sampler2D uHistoryDepth;  // previous linear depth, filter resolution (bilinear)
layout(binding = RTGI_FILTER_TEX_VELOCITY) uniform sampler2D uVelocity;      // G-buffer velocity: previous - current uv
layout(FILTER_FORMAT, binding = RTGI_FILTER_IMG_OUT) uniform writeonly image2D uOut;
layout(r32f, binding = RTGI_FILTER_IMG_OUT_DEPTH) uniform writeonly image2D uOutDepth;
layout(location = RTGI_FILTER_LOC_RESET) uniform int uReset;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uOut);
    if (any(greaterThanEqual(p, size))) return;
    vec2 uv = (vec2(p) + 0.5) / vec2(size);
    vec4 current = texelFetch(uCurrent, p, 0);
    float depth = texelFetch(uDepth, p, 0).r;
    vec2 velocity = texture(uVelocity, uv).xy;
    vec2 uvPrev = uv + velocity;
    float lastDepth = texture(uHistoryDepth, uvPrev).r;
    float alpha = temporalAlpha(abs(depth - lastDepth), velocity, uvPrev);
    if (uReset != 0 || isSky(depth)) alpha = 1.0;
    // On a reset the history is not touched at all: 0 * NaN is NaN, and a
    // history image may hold anything before its first write (NVIDIA does not
    // zero new textures; llvmpipe does). A non-finite history is rejected too.
    vec4 last = texture(uHistory, uvPrev);
    bool historyValid = alpha < 1.0 && !any(isnan(last)) && !any(isinf(last));
    imageStore(uOut, p, historyValid ? mix(last, current, alpha) : current);
    imageStore(uOutDepth, p, vec4(depth));
}
