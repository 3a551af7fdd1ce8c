// brdf_lut: the split-sum environment BRDF [Kar13] (seed 000 3.6.2, SPEC 3.6)
// as an RG16F table, x = n·v, y = perceptual roughness, each at texel
// centres ((i + 0.5) / size), so bilinear lookups at (n·v, roughness) are
// exact there. Computed once per configuration.
#include "lib/brdf.glsl"
#include "lib/post_shared.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(rg16f, binding = RTGI_POST_IMG_LUT) uniform writeonly image2D uLut;
layout(location = RTGI_POST_LOC_SAMPLES) uniform int uSamples;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uLut);
    if (any(greaterThanEqual(p, size))) return;
    vec2 x = (vec2(p) + 0.5) / vec2(size);
    imageStore(uLut, p, vec4(splitSumIntegral(x.x, x.y, uint(uSamples)), 0.0, 0.0));
}
