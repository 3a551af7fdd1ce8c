// Separable edge-preserving Gaussian (SPEC 6.3) on any value texture:
// FILTER_FORMAT is the image format of the output (r16f for AO, rgba16f for
// SSR). Run twice: uDirection (1,0) then (0,1).
#include "lib/depth.glsl"
#include "lib/filter_shared.h"
#include "lib/filter.glsl"

#ifndef FILTER_FORMAT
#define FILTER_FORMAT r16f
#endif
#define BLUR_RADIUS 4

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = RTGI_FILTER_TEX_VALUE) uniform sampler2D uValue;
layout(binding = RTGI_FILTER_BLUR_TEX_DEPTH) uniform sampler2D uDepth;
layout(binding = RTGI_FILTER_TEX_NORMAL) uniform sampler2D uNormal;
layout(FILTER_FORMAT, binding = RTGI_FILTER_IMG_OUT) uniform writeonly image2D uOut;
layout(location = RTGI_FILTER_LOC_DIRECTION) uniform ivec2 uDirection;
layout(location = RTGI_FILTER_LOC_DEPTH_THRESHOLD) uniform float uDepthThreshold;   // relative depth difference
layout(location = RTGI_FILTER_LOC_NORMAL_THRESHOLD) uniform float uNormalThreshold;  // minimum cosine between normals

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uOut);
    if (any(greaterThanEqual(p, size))) return;
    float dC = texelFetch(uDepth, p, 0).r;
    vec4 centre = texelFetch(uValue, p, 0);
    if (isSky(dC)) {
        imageStore(uOut, p, centre);
        return;
    }
    vec3 nC = texelFetch(uNormal, p, 0).xyz;
    vec4 sum = vec4(0.0);
    float wSum = 0.0;
    for (int i = -BLUR_RADIUS; i <= BLUR_RADIUS; ++i) {
        ivec2 q = clamp(p + i * uDirection, ivec2(0), size - 1);
        float g = exp(-float(i * i) / (2.0 * 2.0 * 2.0));  // sigma = 2 texels
        float w = bilateralWeight(g, dC, texelFetch(uDepth, q, 0).r, nC, texelFetch(uNormal, q, 0).xyz,
                                  uDepthThreshold, uNormalThreshold);
        sum += w * texelFetch(uValue, q, 0);
        wSum += w;
    }
    imageStore(uOut, p, wSum > 0.0 ? sum / wSum : centre);  // the centre tap always has weight > 0
}
