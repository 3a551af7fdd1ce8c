// lpv.inject (compute): one invocation per RSM texel adds Phi/pi * cosLobe(n)
// (seed eq. 9, SPEC 3.3) to its cell's 12 coefficients with fp32 image
// atomics. Layout of each r32f accumulation texture: coefficient k of cell
// (x, y, z) at (4x + k, y, z). Texels outside the grid are counted.
#extension GL_NV_shader_atomic_float : require
#include "lpv/lpv_common.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_2D, local_size_y = RTGI_LPV_LOCAL_2D) in;

layout(binding = 0) uniform sampler2D uFlux;
layout(binding = 1) uniform sampler2D uNormal;
layout(binding = 2) uniform sampler2D uDepth;
layout(r32f, binding = 0) uniform image3D uInjectR;
layout(r32f, binding = 1) uniform image3D uInjectG;
layout(r32f, binding = 2) uniform image3D uInjectB;
layout(std430, binding = RTGI_SSBO_LPV_STATS) buffer Stats { uint droppedTexels; };

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, ivec2(lpv.grid.w)))) return;
    vec4 nrm = texelFetch(uNormal, t, 0);
    if (nrm.w == 0.0) return;  // no surface in this texel
    vec3 n = normalize(nrm.xyz);
    ivec3 c;
    if (!lpvInjectionCell(rsmWorldPosition(t, texelFetch(uDepth, t, 0).r), n, c)) {
        atomicAdd(droppedTexels, 1u);
        return;
    }
    vec4 lobe = shCosineLobe(n) * INV_PI;
    vec3 flux = texelFetch(uFlux, t, 0).rgb;
    for (int k = 0; k < 4; ++k) {
        ivec3 a = ivec3(4 * c.x + k, c.y, c.z);
        imageAtomicAdd(uInjectR, a, flux.r * lobe[k]);
        imageAtomicAdd(uInjectG, a, flux.g * lobe[k]);
        imageAtomicAdd(uInjectB, a, flux.b * lobe[k]);
    }
}
