// Half -> full resolution (SPEC 6.4): joint bilateral upsampling of any value
// texture (FILTER_FORMAT), or plain bilinear when UPSAMPLE_DEPTH_AWARE is 0;
// with UPSAMPLE_COPY a texel-for-texel copy of a texture of the output's size
// (copyTexture: a dispatch in place of glCopyImageSubData).
#include "lib/depth.glsl"
#include "lib/filter_shared.h"
#include "lib/filter.glsl"

#ifndef FILTER_FORMAT
#define FILTER_FORMAT r16f
#endif
#ifndef UPSAMPLE_DEPTH_AWARE
#define UPSAMPLE_DEPTH_AWARE 1
#endif

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = RTGI_FILTER_TEX_LOW) uniform sampler2D uLow;
layout(binding = RTGI_FILTER_TEX_LOW_DEPTH) uniform sampler2D uLowDepth;
layout(binding = RTGI_FILTER_TEX_FULL_DEPTH) uniform sampler2D uFullDepth;
layout(FILTER_FORMAT, binding = RTGI_FILTER_IMG_OUT) uniform writeonly image2D uOut;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(uOut);
    if (any(greaterThanEqual(p, size))) return;
    vec2 uv = (vec2(p) + 0.5) / vec2(size);
#if defined(UPSAMPLE_COPY)
    imageStore(uOut, p, texelFetch(uLow, p, 0));
#elif UPSAMPLE_DEPTH_AWARE
    float dFull = texelFetch(uFullDepth, p, 0).r;
    imageStore(uOut, p, upsampleJoint(uLow, uLowDepth, uv, dFull, false, vec3(0.0)));
#else
    imageStore(uOut, p, texture(uLow, uv));
#endif
}
