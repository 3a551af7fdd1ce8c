// lpv.propagate, cascades i > 0 (docs/lpv.md, "Cascades"): the near part of
// a cascade, the steps whose paths the next finer cascade covers, is
// accum_K + f (accum_{K+1} - accum_K) (K, f from lpv::cascadeNearWeight):
// lpv::propagateCompute copies accum_K into `near`, this mixes in accum_{K+1}.
#include "lpv/lpv_common.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

layout(binding = RTGI_LPV_TEX_SOURCE_R) uniform sampler3D uAccumR;
layout(binding = RTGI_LPV_TEX_SOURCE_G) uniform sampler3D uAccumG;
layout(binding = RTGI_LPV_TEX_SOURCE_B) uniform sampler3D uAccumB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_NEAR_R) uniform image3D uNearR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_NEAR_G) uniform image3D uNearG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_NEAR_B) uniform image3D uNearB;
layout(location = RTGI_LPV_LOC_NEAR_FRACTION) uniform float uFraction;

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(c, lpv.grid.xyz)) return;
    imageStore(uNearR, c, lpvStorable(mix(imageLoad(uNearR, c), texelFetch(uAccumR, c, 0), uFraction)));
    imageStore(uNearG, c, lpvStorable(mix(imageLoad(uNearG, c), texelFetch(uAccumG, c, 0), uFraction)));
    imageStore(uNearB, c, lpvStorable(mix(imageLoad(uNearB, c), texelFetch(uAccumB, c, 0), uFraction)));
}
