// lpv.temporal: blends the accumulated volume with the previous frame's
// result re-indexed by the integer cell shift of the snapped grid (seed 3.7).
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

layout(binding = RTGI_LPV_TEX_CUR_R) uniform sampler3D uCurR;
layout(binding = RTGI_LPV_TEX_CUR_G) uniform sampler3D uCurG;
layout(binding = RTGI_LPV_TEX_CUR_B) uniform sampler3D uCurB;
layout(binding = RTGI_LPV_TEX_PREV_R) uniform sampler3D uPrevR;
layout(binding = RTGI_LPV_TEX_PREV_G) uniform sampler3D uPrevG;
layout(binding = RTGI_LPV_TEX_PREV_B) uniform sampler3D uPrevB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_OUT_R) uniform writeonly image3D uOutR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_OUT_G) uniform writeonly image3D uOutG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_OUT_B) uniform writeonly image3D uOutB;

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(c, lpv.grid.xyz)) return;
    vec4 r = texelFetch(uCurR, c, 0), g = texelFetch(uCurG, c, 0), b = texelFetch(uCurB, c, 0);
    ivec3 p = c + lpv.temporalShift.xyz;  // the same world cell in the previous grid
    if (lpv.temporalShift.w != 0 && lpvInside(p, lpv.grid.xyz)) {
        float t = lpv.temporal.x;
        r = mix(r, texelFetch(uPrevR, p, 0), t);
        g = mix(g, texelFetch(uPrevG, p, 0), t);
        b = mix(b, texelFetch(uPrevB, p, 0), t);
    }
    imageStore(uOutR, c, r);
    imageStore(uOutG, c, g);
    imageStore(uOutB, c, b);
}
