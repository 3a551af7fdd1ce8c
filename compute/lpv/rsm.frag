// lpv.rsm (raster path): see lpv/rsm.glsl.
#include "lpv/rsm.glsl"
#include "lib/raster_shared.h"

layout(location = RTGI_RASTER_VARY_WORLD_POS) in vec3 vWorldPos;
layout(location = RTGI_RASTER_VARY_NORMAL) in vec3 vNormal;
layout(location = RTGI_RASTER_VARY_UV) in vec2 vUv;
layout(location = RTGI_RASTER_VARY_MATERIAL) flat in uint vMaterial;

layout(location = RTGI_RASTER_RSM_OUT_FLUX) out vec4 outFlux;
layout(location = RTGI_RASTER_RSM_OUT_NORMAL) out vec4 outNormal;

void main() { rsmTexel(vNormal, vMaterial, materialBaseColor(vMaterial, vUv), outFlux, outNormal); }
