// Copies of LPV volumes (one invocation per cell): the sun cache's kept step 0 (lpv.sun_cache), a
// cascade's near part taken from step 0 or the sum, band 2's first sum (lpv::copyVolumes). Three volumes
// (r, g, b) at the SRC / DST units, or with RTGI_LPV_COPY_HI the four band-2 volumes (hi r, g, b, last)
// at the SRC_HI / DST_HI units, or with RTGI_LPV_COPY_ONE the one volume at SRC_R / DST_R (the
// injection cache's band-2 last volume, lpv::copyInjectCache). glCopyImageSubData of a 16^3 volume cost ~20 us on the H200 (six of them
// 0.117 ms, docs/lpv.md "Sun injection cache"); this dispatch a few microseconds.
#include "lpv/lpv_common.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

#ifdef RTGI_LPV_COPY_HI
layout(binding = RTGI_LPV_TEX_SRC_HI_R) uniform sampler3D uSrc0;
layout(binding = RTGI_LPV_TEX_SRC_HI_G) uniform sampler3D uSrc1;
layout(binding = RTGI_LPV_TEX_SRC_HI_B) uniform sampler3D uSrc2;
layout(binding = RTGI_LPV_TEX_SRC_LAST) uniform sampler3D uSrc3;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_HI_R) uniform writeonly image3D uDst0;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_HI_G) uniform writeonly image3D uDst1;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_HI_B) uniform writeonly image3D uDst2;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_LAST) uniform writeonly image3D uDst3;
#else
layout(binding = RTGI_LPV_TEX_SRC_R) uniform sampler3D uSrc0;
layout(binding = RTGI_LPV_TEX_SRC_G) uniform sampler3D uSrc1;
layout(binding = RTGI_LPV_TEX_SRC_B) uniform sampler3D uSrc2;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_R) uniform writeonly image3D uDst0;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_G) uniform writeonly image3D uDst1;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_B) uniform writeonly image3D uDst2;
#endif

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(c, textureSize(uSrc0, 0)))) return;
    imageStore(uDst0, c, texelFetch(uSrc0, c, 0));
#ifndef RTGI_LPV_COPY_ONE
    imageStore(uDst1, c, texelFetch(uSrc1, c, 0));
    imageStore(uDst2, c, texelFetch(uSrc2, c, 0));
#endif
#ifdef RTGI_LPV_COPY_HI
    imageStore(uDst3, c, texelFetch(uSrc3, c, 0));
#endif
}
