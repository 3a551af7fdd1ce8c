// lpv.inject (compute): one invocation per RSM texel adds Phi/pi * cosLobe(n)
// (seed eq. 9, SPEC 3.3) to its cell's 12 coefficients with fp32 image
// atomics, pre-reduced per workgroup in shared memory (lpv_reduce.glsl).
// Layout of each r32f accumulation texture: coefficient k of cell (x, y, z)
// at (4x + k, y, z). The textures are zero on entry (lpv.pack zeroes what it
// consumed). Texels outside the grid are counted.
#extension GL_NV_shader_atomic_float : require  // float atomics (images, shared memory)
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"

layout(local_size_x = RTGI_LPV_LOCAL_REDUCE, local_size_y = RTGI_LPV_LOCAL_REDUCE) in;

layout(binding = RTGI_LPV_TEX_FLUX) uniform sampler2D uFlux;
layout(binding = RTGI_LPV_TEX_NORMAL) uniform sampler2D uNormal;
layout(binding = RTGI_LPV_TEX_DEPTH) uniform sampler2D uDepth;
layout(r32f, binding = RTGI_LPV_INJECT_IMG_INJECT_R) uniform image3D uInjectR;
layout(r32f, binding = RTGI_LPV_INJECT_IMG_INJECT_G) uniform image3D uInjectG;
layout(r32f, binding = RTGI_LPV_INJECT_IMG_INJECT_B) uniform image3D uInjectB;
layout(std430, binding = RTGI_SSBO_LPV_STATS) buffer Stats { uint droppedTexels; };

#define LPV_REDUCE_CHANNELS 12  // colour * 4 + SH coefficient
void lpvGlobalAdd(uint key, int channel, float value) {
    ivec3 c = lpvCellOfKey(key, lpv.grid.xyz);
    ivec3 a = ivec3(4 * c.x + (channel & 3), c.y, c.z);
    int colour = channel >> 2;
    if (colour == 0) imageAtomicAdd(uInjectR, a, value);
    else if (colour == 1) imageAtomicAdd(uInjectG, a, value);
    else imageAtomicAdd(uInjectB, a, value);
}
#include "lpv/lpv_reduce.glsl"

void main() {
    lpvReduceBegin();
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    vec4 nrm = all(lessThan(t, ivec2(lpv.grid.w))) ? texelFetch(uNormal, t, 0) : vec4(0.0);
    if (nrm.w != 0.0) {  // a surface in this texel
        vec3 n = normalize(nrm.xyz);
        ivec3 c;
        if (lpvInjectionCell(rsmWorldPosition(t, texelFetch(uDepth, t, 0).r), n, c)) {
            vec4 lobe = shCosineLobe(n) * INV_PI;
            vec3 flux = texelFetch(uFlux, t, 0).rgb;
            float v[12];
            for (int k = 0; k < 4; ++k) {
                v[k] = flux.r * lobe[k];
                v[4 + k] = flux.g * lobe[k];
                v[8 + k] = flux.b * lobe[k];
            }
            lpvReduceAdd(lpvKeyOfCell(c, lpv.grid.xyz), v);
        } else {
            if (lpv.cascade.z != 0) atomicAdd(droppedTexels, 1u);  // the coarsest cascade counts (finer ones hold less by design)
        }
    }
    lpvReduceEnd();
}
