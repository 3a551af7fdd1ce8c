// lpv.temporal: blends the accumulated volume with the previous frame's
// result re-indexed by the integer cell shift of the snapped grid (seed 3.7).
// lpv.sh_order=2 (RTGI_LPV_SH2): the band-2 volumes (hi r, g, b, last) too.
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
#ifdef RTGI_LPV_SH2
layout(binding = RTGI_LPV_TEX_CUR_HI_R) uniform sampler3D uCurHiR;
layout(binding = RTGI_LPV_TEX_CUR_HI_G) uniform sampler3D uCurHiG;
layout(binding = RTGI_LPV_TEX_CUR_HI_B) uniform sampler3D uCurHiB;
layout(binding = RTGI_LPV_TEX_CUR_LAST) uniform sampler3D uCurLast;
layout(binding = RTGI_LPV_TEX_PREV_HI_R) uniform sampler3D uPrevHiR;
layout(binding = RTGI_LPV_TEX_PREV_HI_G) uniform sampler3D uPrevHiG;
layout(binding = RTGI_LPV_TEX_PREV_HI_B) uniform sampler3D uPrevHiB;
layout(binding = RTGI_LPV_TEX_PREV_LAST) uniform sampler3D uPrevLast;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_OUT_HI_R) uniform writeonly image3D uOutHiR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_OUT_HI_G) uniform writeonly image3D uOutHiG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_OUT_HI_B) uniform writeonly image3D uOutHiB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_OUT_LAST) uniform writeonly image3D uOutLast;
#endif

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(c, lpv.grid.xyz)) return;
    vec4 r = texelFetch(uCurR, c, 0), g = texelFetch(uCurG, c, 0), b = texelFetch(uCurB, c, 0);
#ifdef RTGI_LPV_SH2
    vec4 hr = texelFetch(uCurHiR, c, 0), hg = texelFetch(uCurHiG, c, 0), hb = texelFetch(uCurHiB, c, 0);
    vec4 last = texelFetch(uCurLast, c, 0);
#endif
    ivec3 p = c + lpv.temporalShift.xyz;  // the same world cell in the previous grid
    if (lpv.temporalShift.w != 0 && lpvInside(p, lpv.grid.xyz)) {
        float t = lpv.temporal.x;
        r = mix(r, texelFetch(uPrevR, p, 0), t);
        g = mix(g, texelFetch(uPrevG, p, 0), t);
        b = mix(b, texelFetch(uPrevB, p, 0), t);
#ifdef RTGI_LPV_SH2
        hr = mix(hr, texelFetch(uPrevHiR, p, 0), t);
        hg = mix(hg, texelFetch(uPrevHiG, p, 0), t);
        hb = mix(hb, texelFetch(uPrevHiB, p, 0), t);
        last = mix(last, texelFetch(uPrevLast, p, 0), t);
#endif
    }
    imageStore(uOutR, c, r);
    imageStore(uOutG, c, g);
    imageStore(uOutB, c, b);
#ifdef RTGI_LPV_SH2
    imageStore(uOutHiR, c, hr);
    imageStore(uOutHiG, c, hg);
    imageStore(uOutHiB, c, hb);
    imageStore(uOutLast, c, last);
#endif
}
