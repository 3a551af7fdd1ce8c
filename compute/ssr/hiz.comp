// ssr.hiz: min-depth pyramid for the Hi-Z tracer. RTGI_HIZ_COPY builds
// level 0 from the G-buffer's linear depth (sky -> far plane); otherwise
// level L+1 is the min over the 2x2 texels of level L, widened to 3 when
// level L has an odd width / height and this is its last texel, so that
// every level-L texel belongs to some parent (no depth is ever dropped).
#include "lib/common.glsl"
#include "lib/ssr_shared.h"
#include "lib/ssr.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

#ifdef RTGI_HIZ_COPY
layout(binding = RTGI_SSR_HIZ_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
#else
layout(r32f, binding = RTGI_SSR_IMG_SOURCE) uniform readonly image2D uSource;
#endif
layout(r32f, binding = RTGI_SSR_IMG_TARGET) uniform writeonly image2D uTarget;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uTarget);
    if (any(greaterThanEqual(p, size))) return;
#ifdef RTGI_HIZ_COPY
    float m = ssrSceneDepth(texelFetch(uLinearDepth, p, 0).r, frame.projParams.y);
#else
    ivec2 src = imageSize(uSource);
    ivec2 extent = ivec2(2) + ivec2(equal(p, size - 1)) * (src & 1);
    float m = 3.0e38;
    for (int y = 0; y < extent.y; ++y)
        for (int x = 0; x < extent.x; ++x) m = min(m, imageLoad(uSource, min(2 * p + ivec2(x, y), src - 1)).r);
#endif
    imageStore(uTarget, p, vec4(m));
}
