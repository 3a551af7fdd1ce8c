// Seed-method injection (lpv.path=raster, seed 5.2.3): one GL_POINT per RSM
// texel; the geometry stage moves it to its cell's layer, additive blending
// sums the coefficients. Same math as inject.comp.
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"

layout(binding = RTGI_LPV_TEX_FLUX) uniform sampler2D uFlux;
layout(binding = RTGI_LPV_TEX_NORMAL) uniform sampler2D uNormal;
layout(binding = RTGI_LPV_TEX_DEPTH) uniform sampler2D uDepth;

layout(location = RTGI_LPV_VARY_CELL) flat out ivec4 vCell;  // xyz cell, w = 1 when injected
layout(location = RTGI_LPV_VARY_R) flat out vec4 vR;
layout(location = RTGI_LPV_VARY_G) flat out vec4 vG;
layout(location = RTGI_LPV_VARY_B) flat out vec4 vB;

void main() {
    int R = lpv.grid.w;
    ivec2 t = ivec2(gl_VertexID % R, gl_VertexID / R);
    vCell = ivec4(0);
    vR = vG = vB = vec4(0.0);
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
    vec4 nrm = texelFetch(uNormal, t, 0);
    if (nrm.w == 0.0) return;
    vec3 n = normalize(nrm.xyz);
    ivec3 c;
    if (!lpvInjectionCell(rsmWorldPosition(t, texelFetch(uDepth, t, 0).r), n, c)) return;
    vec4 lobe = shCosineLobe(n) * INV_PI;
    vec3 flux = texelFetch(uFlux, t, 0).rgb;
    vCell = ivec4(c, 1);
    vR = flux.r * lobe;
    vG = flux.g * lobe;
    vB = flux.b * lobe;
}
