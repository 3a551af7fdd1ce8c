// Copies a texture into an image of the same size (frame history).
#include "lib/post_shared.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = RTGI_POST_TEX_SOURCE) uniform sampler2D uSource;
layout(rgba16f, binding = RTGI_POST_IMG_TARGET) uniform writeonly image2D uTarget;
void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(uTarget)))) return;
    imageStore(uTarget, p, texelFetch(uSource, p, 0));
}
