// ssr.blur: one direction of the separable edge-preserving Gaussian of the
// shared filter chain (lib/filter.glsl, SPEC 6.3) over the premultiplied
// reflection; RTGI_BLUR_VERTICAL picks the direction.
#include "lib/common.glsl"
#include "lib/filter.glsl"
#include "lib/ssr_shared.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, binding = RTGI_UBO_SSR) uniform SsrBlock { SsrUniforms ssr; };
layout(binding = 0) uniform sampler2D uSource;
layout(binding = 1) uniform sampler2D uLinearDepth;
layout(binding = 2) uniform sampler2D uNormal;
layout(rgba16f, binding = 0) uniform writeonly image2D uTarget;

#ifdef RTGI_BLUR_VERTICAL
const ivec2 kAxis = ivec2(0, 1);
#else
const ivec2 kAxis = ivec2(1, 0);
#endif

ivec2 fullPixel(ivec2 p) { return min(p * ssr.params.w, ssr.sizes.zw - 1); }

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ssr.sizes.xy))) return;
    float dC = texelFetch(uLinearDepth, fullPixel(p), 0).r;
    vec3 nC = texelFetch(uNormal, fullPixel(p), 0).xyz;
    vec4 centre = texelFetch(uSource, p, 0);
    vec4 sum = vec4(0.0);
    float wsum = 0.0;
    int radius = int(ssr.blur.y);
    float inv2s2 = 0.5 / (ssr.blur.x * ssr.blur.x);
    for (int i = -radius; i <= radius; ++i) {
        ivec2 q = clamp(p + kAxis * i, ivec2(0), ssr.sizes.xy - 1);
        float w = bilateralWeight(exp(-float(i * i) * inv2s2), dC, texelFetch(uLinearDepth, fullPixel(q), 0).r, nC,
                                  texelFetch(uNormal, fullPixel(q), 0).xyz, ssr.blur.z, ssr.blur.w);
        sum += texelFetch(uSource, q, 0) * w;
        wsum += w;
    }
    imageStore(uTarget, p, wsum > 0.0 ? sum / wsum : centre);
}
