// ao.downsample: half-resolution depth and normals for the AO chain (seed 000
// 5.3). Of each 2x2 block the nearest non-sky texel is kept with its normal,
// so thin foreground geometry survives and depth/normal stay consistent. Its
// depth is moved along its tangent plane to the half-resolution texel centre:
// the estimators reconstruct view positions at that centre, and a depth that
// belongs to a point a quarter texel away would put every position off the
// surface (self-occlusion on planes, docs/ao.md "Reconstruction").
#include "lib/common.glsl"
#include "lib/ao_shared.h"
#include "lib/depth.glsl"
#include "lib/ao.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = RTGI_AO_TEX_DEPTH) uniform sampler2D uDepth;
layout(binding = RTGI_AO_TEX_NORMAL) uniform sampler2D uNormal;
layout(r32f, binding = RTGI_AO_IMG_HALF_DEPTH) uniform writeonly image2D uHalfDepth;
layout(rgba16f, binding = RTGI_AO_IMG_HALF_NORMAL) uniform writeonly image2D uHalfNormal;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 halfSize = imageSize(uHalfDepth);
    if (any(greaterThanEqual(p, halfSize))) return;
    ivec2 at;
    vec4 n;
    vec2 range;  // unused here
    float best = aoHalfTexelSurface(uDepth, uNormal, p, (vec2(p) + 0.5) / vec2(halfSize), 0.0, frame.projParams.z,
                                    frame.projParams.w, at, n, range);
    imageStore(uHalfDepth, p, vec4(best));
    imageStore(uHalfNormal, p, n);
}
