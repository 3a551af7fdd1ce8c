// --check: counts NaN, ±Inf, negative values (where impossible) and fp16
// saturation (|x| >= 65504) over every texel/channel of one output.
#include "lib/post_shared.h"
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
#ifdef RTGI_VOLUME
layout(binding = RTGI_POST_TEX_SOURCE) uniform sampler3D uSource;
#elif defined(RTGI_ARRAY)  // a 2D array texture: every layer
layout(binding = RTGI_POST_TEX_SOURCE) uniform sampler2DArray uSource;
#else
layout(binding = RTGI_POST_TEX_SOURCE) uniform sampler2D uSource;
#endif
layout(std430, binding = RTGI_POST_SSBO_COUNTS) buffer Counts { uint nanCount, infCount, negativeCount, saturatedCount; };
layout(location = RTGI_POST_LOC_CHANNELS) uniform int uChannels;
layout(location = RTGI_POST_LOC_MAY_BE_NEGATIVE) uniform int uMayBeNegative;
void main() {
#if defined(RTGI_VOLUME) || defined(RTGI_ARRAY)
    ivec3 p = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(p, textureSize(uSource, 0)))) return;
    vec4 v = texelFetch(uSource, p, 0);
#else
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, textureSize(uSource, 0)))) return;
    vec4 v = texelFetch(uSource, p, 0);
#endif
    for (int c = 0; c < uChannels; ++c) {
        float x = v[c];
        if (isnan(x)) atomicAdd(nanCount, 1u);
        else if (isinf(x)) atomicAdd(infCount, 1u);
        else {
            if (uMayBeNegative == 0 && x < 0.0) atomicAdd(negativeCount, 1u);
            if (abs(x) >= 65504.0) atomicAdd(saturatedCount, 1u);
        }
    }
}
