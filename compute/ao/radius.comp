// ao.radius: dynamic sample-radius probe (seed 003 4.2.2, algorithms 1-6 by
// AO_RADIUS_ALG) over a Poisson disk of K taps inside the projected radius.
// Writes the radius scale r_new / R and its colour coding (seed 003 fig. 6.10:
// light blue = unchanged, green -> yellow -> red = shrunk, dark blue = grown).
#include "lib/common.glsl"
#include "lib/depth.glsl"
#include "lib/ao_shared.h"
#include "lib/ao.glsl"

#ifndef AO_RADIUS_ALG
#define AO_RADIUS_ALG 6  // the algorithm that works (seed 003 6.4)
#endif

layout(local_size_x = 8, local_size_y = 8) in;
layout(std140, binding = RTGI_UBO_AO) uniform AoBlock { AoParams ao; };
layout(binding = RTGI_AO_TEX_DEPTH) uniform sampler2D uDepth;
layout(binding = RTGI_AO_TEX_NORMAL) uniform sampler2D uNormal;
layout(r16f, binding = RTGI_AO_IMG_SCALE) uniform writeonly image2D uScale;
layout(rgba8, binding = RTGI_AO_IMG_SCALE_COLOR) uniform writeonly image2D uScaleColor;

vec3 scaleColor(float s) {
    const vec3 red = vec3(0.9, 0.1, 0.1), yellow = vec3(1.0, 0.9, 0.1), green = vec3(0.2, 0.8, 0.2),
               lightBlue = vec3(0.55, 0.85, 1.0), darkBlue = vec3(0.1, 0.2, 0.8);
    if (s < 0.5) return mix(red, yellow, clamp((s - 0.25) / 0.25, 0.0, 1.0));
    if (s < 0.75) return mix(yellow, green, (s - 0.5) / 0.25);
    if (s <= 1.0) return mix(green, lightBlue, (s - 0.75) / 0.25);
    return mix(lightBlue, darkBlue, clamp(s - 1.0, 0.0, 1.0));
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ao.size.xy;
    if (any(greaterThanEqual(p, size))) return;
    float d = texelFetch(uDepth, p, 0).r;
    float scale = 1.0;
    if (!isSky(d)) {
        vec2 uv = (vec2(p) + 0.5) / vec2(size);
        float R = ao.radius.x;
        vec3 P = viewPositionFromDepth(uv, d, ao.focal.z, ao.focal.w);
        vec3 nP = aoSafeNormal(texelFetch(uNormal, p, 0).xyz, P);
        vec2 rUv = aoTextureRadius(R, d, ao.focal.xy);
        int K = int(ao.misc.w);
        float dMin = 1e30, sum = 0.0, sumSq = 0.0;
        int closer = 0, n = 0;
        vec3 zMax = vec3(0.0, 0.0, -1e30);
        bool found = false;
        for (int i = 0; i < K; ++i) {
            vec2 uvS = uv + ao.probe[i].xy * rUv;
            if (any(lessThan(uvS, vec2(0.0))) || any(greaterThanEqual(uvS, vec2(1.0)))) continue;
            ivec2 q = ivec2(uvS * vec2(size));
            float dS = texelFetch(uDepth, q, 0).r;
            if (isSky(dS)) continue;
            // The depth belongs to the texel centre: reconstruct S there.
            vec3 S = viewPositionFromDepth((vec2(q) + 0.5) / vec2(size), dS, ao.focal.z, ao.focal.w);
            ++n;
            dMin = min(dMin, dS);
            sumSq += (dS - d) * (dS - d);
            if (dS < d) sum += dS, ++closer;
#if AO_RADIUS_ALG == 5
            if (dS <= -zMax.z && abs(dS - d) < R) zMax = S, found = true;
#elif AO_RADIUS_ALG == 6
            // Seed 003's "z" is height over a camera-facing base; on tilted
            // surfaces that is the height over P's tangent plane: only points
            // above it by more than 2 % of R (blockers) qualify, so a plane
            // keeps the radius (scale 1) at any inclination.
            if (distance(S, P) < R && dot(S - P, nP) > 0.02 * R && length(S) < length(zMax)) zMax = S, found = true;
#endif
        }
        // Seed 003 works with depths where "max z" is the point nearest to the
        // camera; here that is the minimum positive depth.
#if AO_RADIUS_ALG == 1
        if (n > 0) scale = (d - dMin) / dMin;
#elif AO_RADIUS_ALG == 2
        if (closer > 0) scale = (d - sum / float(closer)) / (sum / float(closer));
#elif AO_RADIUS_ALG == 3
        float zStd = sqrt(sumSq / float(max(n, 1)));
        if (n > 0 && zStd > 1e-6) scale = (d - zStd) / zStd;
#elif AO_RADIUS_ALG == 4
        if (n > 0 && abs(d - dMin) < R) scale = (d - dMin) / dMin;
#else
        if (found) scale = distance(zMax, P) / R;
#endif
        // Keep the scaled radius usable: at least 5 %, at most twice R.
        scale = clamp(scale, 0.05, 2.0);
    }
    imageStore(uScale, p, vec4(scale));
    imageStore(uScaleColor, p, vec4(scaleColor(scale), 1.0));
}
