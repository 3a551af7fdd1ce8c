// ref.*: accumulation -> mean and per-pixel standard error of the mean,
// SE = sqrt(s² / n) per channel with the unbiased sample variance
// s² = M2 / (n − 1) (running moments, lib/moments.glsl).
// RTGI_REF_RADIANCE also tonemaps the mean with the frame's tonemapper;
// RTGI_REF_TONEMAP_ONLY only tonemaps a mean loaded from the cache.
#include "lib/common.glsl"
#include "lib/tonemap.glsl"
#include "lib/bvh_shared.h"

layout(local_size_x = RTGI_REF_LOCAL, local_size_y = RTGI_REF_LOCAL) in;

#ifdef RTGI_REF_TONEMAP_ONLY
layout(rgba32f, binding = RTGI_REF_IMG_MEAN) uniform readonly image2D uMean;
#else
layout(rgba32f, binding = RTGI_REF_IMG_ACCUM) uniform readonly image2D uAccum;    // running mean (rgb), sample count (a)
layout(rgba32f, binding = RTGI_REF_IMG_ACCUM_SQ) uniform readonly image2D uAccumSq;  // running M2 (rgb)
layout(rgba32f, binding = RTGI_REF_IMG_MEAN) uniform writeonly image2D uMean;    // rgb mean, a = 1
layout(rgba32f, binding = RTGI_REF_IMG_STD_ERR) uniform writeonly image2D uStdErr;  // rgb standard error, a = 1
#endif
#ifdef RTGI_REF_RADIANCE
layout(rgba8, binding = RTGI_REF_IMG_LDR) uniform writeonly image2D uLdr;
#endif

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, frameSize()))) return;
#ifdef RTGI_REF_TONEMAP_ONLY
    vec3 mean = imageLoad(uMean, p).rgb;
#else
    vec4 s = imageLoad(uAccum, p);
    float n = max(s.a, 1.0);
    vec3 mean = s.rgb;
    vec3 var = max(imageLoad(uAccumSq, p).rgb, vec3(0.0)) / max(n - 1.0, 1.0);
    imageStore(uMean, p, vec4(mean, 1.0));
    imageStore(uStdErr, p, vec4(sqrt(var / n), 1.0));
#endif
#ifdef RTGI_REF_RADIANCE
    imageStore(uLdr, p, vec4(tonemap(mean, frame.sky.a), 1.0));
#endif
}
