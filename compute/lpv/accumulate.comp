// lpv.propagate with lpv.sh_order=2 (docs/lpv.md, "Second-order SH"): accum +=
// step k over the 7 volumes of bands 0-2, one dispatch after each step (the
// propagation itself already uses 7 image units). lpv::propagateCompute copies
// step 0 into accum before the first step, so every step is the same addition.
#include "lpv/lpv_common.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

layout(binding = RTGI_LPV_ACC_TEX_STEP_R) uniform sampler3D uStepR;
layout(binding = RTGI_LPV_ACC_TEX_STEP_G) uniform sampler3D uStepG;
layout(binding = RTGI_LPV_ACC_TEX_STEP_B) uniform sampler3D uStepB;
layout(binding = RTGI_LPV_ACC_TEX_STEP_HI_R) uniform sampler3D uStepHiR;
layout(binding = RTGI_LPV_ACC_TEX_STEP_HI_G) uniform sampler3D uStepHiG;
layout(binding = RTGI_LPV_ACC_TEX_STEP_HI_B) uniform sampler3D uStepHiB;
layout(binding = RTGI_LPV_ACC_TEX_STEP_LAST) uniform sampler3D uStepLast;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_ACC_IMG_ACCUM_R) uniform image3D uAccumR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_ACC_IMG_ACCUM_G) uniform image3D uAccumG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_ACC_IMG_ACCUM_B) uniform image3D uAccumB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_ACC_IMG_ACCUM_HI_R) uniform image3D uAccumHiR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_ACC_IMG_ACCUM_HI_G) uniform image3D uAccumHiG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_ACC_IMG_ACCUM_HI_B) uniform image3D uAccumHiB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_ACC_IMG_ACCUM_LAST) uniform image3D uAccumLast;

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(c, lpv.grid.xyz)) return;
    // Each invocation owns its cell: the read-modify-write needs no atomics.
    imageStore(uAccumR, c, lpvStorable(imageLoad(uAccumR, c) + texelFetch(uStepR, c, 0)));
    imageStore(uAccumG, c, lpvStorable(imageLoad(uAccumG, c) + texelFetch(uStepG, c, 0)));
    imageStore(uAccumB, c, lpvStorable(imageLoad(uAccumB, c) + texelFetch(uStepB, c, 0)));
    imageStore(uAccumHiR, c, lpvStorable(imageLoad(uAccumHiR, c) + texelFetch(uStepHiR, c, 0)));
    imageStore(uAccumHiG, c, lpvStorable(imageLoad(uAccumHiG, c) + texelFetch(uStepHiG, c, 0)));
    imageStore(uAccumHiB, c, lpvStorable(imageLoad(uAccumHiB, c) + texelFetch(uStepHiB, c, 0)));
    imageStore(uAccumLast, c, lpvStorable(imageLoad(uAccumLast, c) + texelFetch(uStepLast, c, 0)));
}
