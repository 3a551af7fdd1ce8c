// Seed-method injection (lpv.path=raster, seed 5.2.3): one GL_POINT per RSM
// texel; the geometry stage moves it to its cell's layer, additive blending
// sums the coefficients. Same math as inject.comp.
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"

// RTGI_LPV_RSM_ARRAY: a local-light face, one layer of the local RSM arrays (lpv.rsm), with the
// inverse of the view it was drawn with (one draw per face: the seed's baseline).
#ifdef RTGI_LPV_RSM_ARRAY
layout(binding = RTGI_LPV_TEX_FLUX) uniform sampler2DArray uFlux;
layout(binding = RTGI_LPV_TEX_NORMAL) uniform sampler2DArray uNormal;
layout(binding = RTGI_LPV_TEX_DEPTH) uniform sampler2DArray uDepth;
layout(location = RTGI_LPV_INJECT_RASTER_LOC_LAYER) uniform int uLayer;
layout(location = RTGI_LPV_INJECT_RASTER_LOC_INV_VIEW_PROJ) uniform mat4 uInvViewProj;
#else
layout(binding = RTGI_LPV_TEX_FLUX) uniform sampler2D uFlux;
layout(binding = RTGI_LPV_TEX_NORMAL) uniform sampler2D uNormal;
layout(binding = RTGI_LPV_TEX_DEPTH) uniform sampler2D uDepth;
#endif

layout(location = RTGI_LPV_VARY_CELL) flat out ivec4 vCell;  // xyz cell, w = 1 when injected
layout(location = RTGI_LPV_VARY_R) flat out vec4 vR;
layout(location = RTGI_LPV_VARY_G) flat out vec4 vG;
layout(location = RTGI_LPV_VARY_B) flat out vec4 vB;

void main() {
#ifdef RTGI_LPV_RSM_ARRAY
    int R = textureSize(uFlux, 0).x;
    ivec2 t = ivec2(gl_VertexID % R, gl_VertexID / R);
    ivec3 tex = ivec3(t, uLayer);
#define LPV_RSM_POSITION(depth) rsmWorldPosition(uInvViewProj, R, t, depth)
#else
    int R = lpv.grid.w;
    ivec2 t = ivec2(gl_VertexID % R, gl_VertexID / R);
    ivec2 tex = t;
#define LPV_RSM_POSITION(depth) rsmWorldPosition(t, depth)
#endif
    vCell = ivec4(0);
    vR = vG = vB = vec4(0.0);
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
    vec4 nrm = texelFetch(uNormal, tex, 0);
    if (nrm.w == 0.0) return;
    vec3 n = normalize(nrm.xyz);
    ivec3 c;
    if (!lpvInjectionCell(LPV_RSM_POSITION(texelFetch(uDepth, tex, 0).r), n, c)) return;
    vec4 lobe = shCosineLobe(n) * INV_PI;
    vec3 flux = texelFetch(uFlux, tex, 0).rgb;
    vCell = ivec4(c, 1);
    vR = flux.r * lobe;
    vG = flux.g * lobe;
    vB = flux.b * lobe;
}
