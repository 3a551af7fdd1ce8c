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
        float lastDepth = texture(uHistoryDepth, uvPrev).r;
        // Disocclusion: the surface point's depth in the previous view (camera
        // motion; an object's own motion along the view axis is not in the
        // velocity) against the previous depth where it reprojects. The depth
        // histories are R32F and the camera step one fp32 matrix: 2^-12 relative.
        float expected = depth;
        float residual = 0.0;
        bool reject = false;
        if (!isSky(depth)) {
            vec3 viewPos = vec3((uv * 2.0 - 1.0) * uProjScale * depth, -depth);
            expected = -(uCurToPrevView * vec4(viewPos, 1.0)).z;
            residual = abs(lastDepth - expected);
            reject = historyDisoccluded(lastDepth, expected, depth, depthSlopePerPixel(uDepth, p, size, depth),
                                        velocity * vec2(size), exp2(-12.0));
        }
        // Listing 11's blend on what the reprojection did not explain.
        float alpha = temporalAlpha(residual, velocity, uvPrev);
        bool validHistory = uReset == 0 && !isSky(depth);
        bool offScreen = any(lessThan(uvPrev, vec2(0.0001))) || any(greaterThanEqual(uvPrev, vec2(0.9999)));
        disoccluded = validHistory && (reject || offScreen);
        if (!validHistory || reject) alpha = 1.0;
        // On a reset the history is not touched at all: 0 * NaN is NaN, and a
        // history image may hold anything before its first write (NVIDIA does not
        // zero new textures; llvmpipe does). A non-finite history is rejected too.
        vec4 last = texture(uHistory, uvPrev);
        bool historyValid = alpha < 1.0 && !any(isnan(last)) && !any(isinf(last));
        imageStore(uOut, p, historyValid ? mix(last, current, alpha) : current);
        imageStore(uOutDepth, p, vec4(depth));
    }
    if (disoccluded) atomicAdd(groupDisoccluded, 1u);
    barrier();
    if (gl_LocalInvocationIndex == 0u && groupDisoccluded > 0u) atomicAdd(disoccludedCount, groupDisoccluded);
}
