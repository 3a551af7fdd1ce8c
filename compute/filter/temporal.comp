// Temporal reprojection filter of seed 000 listing 11 (SPEC 6.2) on any value
// texture (FILTER_FORMAT), with disocclusion detection (docs/temporal.md,
// "Disocclusion"). Keeps its own history of value and linear depth; uReset
// (camera cut / no history) takes the current value.
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
layout(std430, binding = RTGI_FILTER_SSBO_COUNTS) buffer TemporalCounts { uint disoccludedCount; };
layout(location = RTGI_FILTER_LOC_RESET) uniform int uReset;
layout(location = RTGI_FILTER_LOC_CUR_TO_PREV_VIEW) uniform mat4 uCurToPrevView;  // current view -> previous view space
layout(location = RTGI_FILTER_LOC_PROJ_SCALE) uniform vec2 uProjScale;            // tan(fovY/2) * aspect, tan(fovY/2)

shared uint groupDisoccluded;

void main() {
    if (gl_LocalInvocationIndex == 0u) groupDisoccluded = 0u;
    barrier();
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uOut);
    bool inside = all(lessThan(p, size));
    bool disoccluded = false;
    if (inside) {
        vec2 uv = (vec2(p) + 0.5) / vec2(size);
        vec4 current = texelFetch(uCurrent, p, 0);
        float depth = texelFetch(uDepth, p, 0).r;
        vec2 velocity = texture(uVelocity, uv).xy;
        vec2 uvPrev = uv + velocity;
        // Disocclusion: the surface point's depth in the previous view (camera
        // motion; an object's own motion along the view axis is not in the
        // velocity) against the previous depth of each bilinear tap around the
        // reprojected position; taps of another surface are dropped and the
        // others renormalized, no tap left = disoccluded. The depth histories
        // are R32F and the camera step one fp32 matrix: 2^-12 relative.
        bool offScreen = any(lessThan(uvPrev, vec2(0.0001))) || any(greaterThanEqual(uvPrev, vec2(0.9999)));
        bool validHistory = uReset == 0 && !isSky(depth);
        vec4 last = vec4(0.0);
        float residual = 0.0, weight = 0.0;
        if (validHistory && !offScreen) {
            vec3 viewPos = vec3((uv * 2.0 - 1.0) * uProjScale * depth, -depth);
            float expected = -(uCurToPrevView * vec4(viewPos, 1.0)).z;
            float tolerance = disocclusionTolerance(expected, depth, depthSlopePerPixel(uDepth, p, size, depth),
                                                    velocity * vec2(size), exp2(-12.0));
            vec2 st = uvPrev * vec2(size) - 0.5;
            ivec2 i0 = ivec2(floor(st));
            vec2 f = st - vec2(i0);
            float depthSum = 0.0;
            for (int k = 0; k < 4; ++k) {
                ivec2 o = ivec2(k & 1, k >> 1);
                float w = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
                ivec2 q = clamp(i0 + o, ivec2(0), size - 1);  // clamp to edge, as the bilinear fetch did
                float hd = texelFetch(uHistoryDepth, q, 0).r;
                if (!(w > 0.0) || isSky(hd) || !(abs(hd - expected) <= tolerance)) continue;
                // A history texel may hold anything before its first write (NVIDIA does
                // not zero new textures; llvmpipe does): a non-finite one is dropped too.
                vec4 h = texelFetch(uHistory, q, 0);
                if (any(isnan(h)) || any(isinf(h))) continue;
                last += w * h;
                depthSum += w * hd;
                weight += w;
            }
            if (weight > 0.0) {
                last /= weight;
                residual = abs(depthSum / weight - expected);
            }
        }
        disoccluded = validHistory && weight <= 0.0;
        // Listing 11's blend on what the reprojection did not explain. On a reset
        // the history is not touched at all (0 * NaN is NaN).
        float alpha = weight > 0.0 ? temporalAlpha(residual, velocity, uvPrev) : 1.0;
        bool historyValid = validHistory && alpha < 1.0;
        imageStore(uOut, p, historyValid ? mix(last, current, alpha) : current);
        imageStore(uOutDepth, p, vec4(depth));
    }
    if (disoccluded) atomicAdd(groupDisoccluded, 1u);
    barrier();
    if (gl_LocalInvocationIndex == 0u && groupDisoccluded > 0u) atomicAdd(disoccludedCount, groupDisoccluded);
}
