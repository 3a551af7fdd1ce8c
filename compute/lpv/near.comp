// lpv.propagate, cascades i > 0 (docs/lpv.md, "Cascades"): the near part of
// a cascade, the steps whose paths the next finer cascade covers, is
// accum_K + f (accum_{K+1} - accum_K) (K, f from lpv::cascadeNearWeight):
// lpv::propagateCompute copies accum_K into `near`, this mixes in accum_{K+1}.
// lpv.sh_order=2 (RTGI_LPV_SH2): also the band-2 volumes (hi r, g, b, last).
#include "lpv/lpv_common.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

layout(binding = RTGI_LPV_TEX_SOURCE_R) uniform sampler3D uAccumR;
layout(binding = RTGI_LPV_TEX_SOURCE_G) uniform sampler3D uAccumG;
layout(binding = RTGI_LPV_TEX_SOURCE_B) uniform sampler3D uAccumB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_NEAR_R) uniform image3D uNearR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_NEAR_G) uniform image3D uNearG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_NEAR_B) uniform image3D uNearB;
layout(location = RTGI_LPV_LOC_NEAR_FRACTION) uniform float uFraction;
// lpv.propagate_cascades=joint: the sum is a stacked volume, this cascade's slab from z = uSlabZ.
layout(location = RTGI_LPV_LOC_NEAR_OFFSET) uniform int uSlabZ = 0;
#ifdef RTGI_LPV_SH2
layout(binding = RTGI_LPV_TEX_SOURCE_HI_R) uniform sampler3D uAccumHiR;
layout(binding = RTGI_LPV_TEX_SOURCE_HI_G) uniform sampler3D uAccumHiG;
layout(binding = RTGI_LPV_TEX_SOURCE_HI_B) uniform sampler3D uAccumHiB;
layout(binding = RTGI_LPV_TEX_SOURCE_LAST) uniform sampler3D uAccumLast;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_NEAR_HI_R) uniform image3D uNearHiR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_NEAR_HI_G) uniform image3D uNearHiG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_NEAR_HI_B) uniform image3D uNearHiB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_NEAR_LAST) uniform image3D uNearLast;
#endif

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(c, lpv.grid.xyz)) return;
    ivec3 s = c + ivec3(0, 0, uSlabZ);
    imageStore(uNearR, c, lpvStorable(mix(imageLoad(uNearR, c), texelFetch(uAccumR, s, 0), uFraction)));
    imageStore(uNearG, c, lpvStorable(mix(imageLoad(uNearG, c), texelFetch(uAccumG, s, 0), uFraction)));
    imageStore(uNearB, c, lpvStorable(mix(imageLoad(uNearB, c), texelFetch(uAccumB, s, 0), uFraction)));
#ifdef RTGI_LPV_SH2
    imageStore(uNearHiR, c, lpvStorable(mix(imageLoad(uNearHiR, c), texelFetch(uAccumHiR, c, 0), uFraction)));
    imageStore(uNearHiG, c, lpvStorable(mix(imageLoad(uNearHiG, c), texelFetch(uAccumHiG, c, 0), uFraction)));
    imageStore(uNearHiB, c, lpvStorable(mix(imageLoad(uNearHiB, c), texelFetch(uAccumHiB, c, 0), uFraction)));
    imageStore(uNearLast, c, lpvStorable(mix(imageLoad(uNearLast, c), texelFetch(uAccumLast, c, 0), uFraction)));
#endif
}
