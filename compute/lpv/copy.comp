// lpv.sun_cache (docs/lpv.md, "Sun injection cache"): copies r, g, b volumes (one invocation per cell):
// the packed injection into the kept copy, and the kept copy into step 0. glCopyImageSubData of the
// six 16^3 volumes of two cascades cost 0.117 ms on the H200; this dispatch a few microseconds.
#include "lpv/lpv_common.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

layout(binding = RTGI_LPV_TEX_SRC_R) uniform sampler3D uSrcR;
layout(binding = RTGI_LPV_TEX_SRC_G) uniform sampler3D uSrcG;
layout(binding = RTGI_LPV_TEX_SRC_B) uniform sampler3D uSrcB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_R) uniform writeonly image3D uDstR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_G) uniform writeonly image3D uDstG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_B) uniform writeonly image3D uDstB;

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(c, textureSize(uSrcR, 0)))) return;
    imageStore(uDstR, c, texelFetch(uSrcR, c, 0));
    imageStore(uDstG, c, texelFetch(uSrcG, c, 0));
    imageStore(uDstB, c, texelFetch(uSrcB, c, 0));
}
