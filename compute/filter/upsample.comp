// Half -> full resolution (SPEC 6.4): joint bilateral upsampling of any value
// texture (FILTER_FORMAT), or plain bilinear when UPSAMPLE_DEPTH_AWARE is 0.
#include "lib/depth.glsl"
#include "lib/filter_shared.h"
#include "lib/filter.glsl"

#ifndef FILTER_FORMAT
#define FILTER_FORMAT r16f
#endif
#ifndef UPSAMPLE_DEPTH_AWARE
#define UPSAMPLE_DEPTH_AWARE 1
#endif

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = RTGI_FILTER_TEX_LOW) uniform sampler2D uLow;
layout(binding = RTGI_FILTER_TEX_LOW_DEPTH) uniform sampler2D uLowDepth;
layout(binding = RTGI_FILTER_TEX_FULL_DEPTH) uniform sampler2D uFullDepth;
layout(FILTER_FORMAT, binding = RTGI_FILTER_IMG_OUT) uniform writeonly image2D uOut;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uOut);
    if (any(greaterThanEqual(p, size))) return;
    vec2 uv = (vec2(p) + 0.5) / vec2(size);
#if UPSAMPLE_DEPTH_AWARE
    float dFull = texelFetch(uFullDepth, p, 0).r;
    ivec2 lowSize = textureSize(uLow, 0);
    vec2 t = uv * vec2(lowSize) - 0.5;
    ivec2 base = ivec2(floor(t));
    vec2 f = t - vec2(base);
    vec4 sum = vec4(0.0);
    float wSum = 0.0, bestDiff = 1e30;
    vec4 nearest = vec4(1.0);
    for (int i = 0; i < 4; ++i) {
        ivec2 o = ivec2(i & 1, i >> 1);
        ivec2 q = clamp(base + o, ivec2(0), lowSize - 1);
        float bilinear = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
        float dLow = texelFetch(uLowDepth, q, 0).r;
        vec4 v = texelFetch(uLow, q, 0);
        float diff = abs(dLow - dFull);
        if (diff < bestDiff) bestDiff = diff, nearest = v;
        float w = isSky(dFull) ? (isSky(dLow) ? bilinear : 0.0) : upsampleWeight(bilinear, dFull, dLow);
        sum += w * v;
        wSum += w;
    }
    imageStore(uOut, p, wSum > 1e-6 ? sum / wSum : nearest);
#else
    imageStore(uOut, p, texture(uLow, uv));
#endif
}
