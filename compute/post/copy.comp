// Copies a texture into an image of the same size (frame history); with
// POST_COPY_DEPTH_ALPHA the alpha channel takes the linear depth (the
// reprojecting passes' disocclusion test, docs/temporal.md).
#include "lib/post_shared.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = RTGI_POST_TEX_SOURCE) uniform sampler2D uSource;
layout(rgba16f, binding = RTGI_POST_IMG_TARGET) uniform writeonly image2D uTarget;
#ifdef POST_COPY_DEPTH_ALPHA
layout(binding = RTGI_POST_COPY_TEX_LINEAR_DEPTH) uniform sampler2D uDepth;
#endif
void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(uTarget)))) return;
    vec4 v = texelFetch(uSource, p, 0);
#ifdef POST_COPY_DEPTH_ALPHA
    v.a = texelFetch(uDepth, p, 0).r;
#endif
    imageStore(uTarget, p, v);
}
