// lpv.rsm (raster path): see lpv/rsm.glsl. RTGI_RSM_LOCAL: a face of a
// spot / point / area light's perspective RSM.
#include "lpv/rsm.glsl"
#include "lib/raster_shared.h"
#ifdef RTGI_RSM_LOCAL
layout(location = RTGI_LPV_RSM_LOC_LIGHT) uniform vec4 uLight[4];  // the GpuLight: positionRange, colorIntensity, directionType, cone
layout(location = RTGI_LPV_RSM_LOC_FACE) uniform vec2 uFace;       // tan(half field of view), RSM side R
#endif

layout(location = RTGI_RASTER_VARY_WORLD_POS) in vec3 vWorldPos;
layout(location = RTGI_RASTER_VARY_NORMAL) in vec3 vNormal;
layout(location = RTGI_RASTER_VARY_UV) in vec2 vUv;
layout(location = RTGI_RASTER_VARY_MATERIAL) flat in uint vMaterial;

layout(location = RTGI_RASTER_RSM_OUT_FLUX) out vec4 outFlux;
layout(location = RTGI_RASTER_RSM_OUT_NORMAL) out vec4 outNormal;

void main() {
    vec4 baseColor = materialBaseColor(vMaterial, vUv);
#ifdef RTGI_RSM_LOCAL
    GpuLight g = GpuLight(uLight[0], uLight[1], uLight[2], uLight[3]);
    rsmTexelLocal(g, vWorldPos, vNormal, vMaterial, baseColor, floor(gl_FragCoord.xy), uFace, outFlux, outNormal);
#else
    rsmTexel(vNormal, vMaterial, baseColor, outFlux, outNormal);
#endif
}
