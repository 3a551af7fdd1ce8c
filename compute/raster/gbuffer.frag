// G-buffer: linear view depth, view-space normal, albedo, roughness/metallic,
// emission, velocity (previous − current projected position in UV).
#include "raster/gbuffer.glsl"
#include "lib/raster_shared.h"

layout(location = RTGI_RASTER_VARY_WORLD_POS) in vec3 vWorldPos;
layout(location = RTGI_RASTER_VARY_NORMAL) in vec3 vNormal;
layout(location = RTGI_RASTER_VARY_UV) in vec2 vUv;
layout(location = RTGI_RASTER_VARY_MATERIAL) flat in uint vMaterial;
layout(location = RTGI_RASTER_VARY_CUR_CLIP) in vec4 vCurClip;
layout(location = RTGI_RASTER_VARY_PREV_CLIP) in vec4 vPrevClip;

layout(location = RTGI_RASTER_OUT_LINEAR_DEPTH) out float outLinearDepth;
layout(location = RTGI_RASTER_OUT_NORMAL) out vec4 outNormal;
layout(location = RTGI_RASTER_OUT_ALBEDO) out vec4 outAlbedo;
layout(location = RTGI_RASTER_OUT_MATERIAL) out vec4 outMaterial;
layout(location = RTGI_RASTER_OUT_EMISSIVE) out vec3 outEmissive;
layout(location = RTGI_RASTER_OUT_VELOCITY) out vec2 outVelocity;

void main() {
    GBufferTexel g = gbufferTexel(vWorldPos, vNormal, gl_FrontFacing, vMaterial, materialBaseColor(vMaterial, vUv),
                                  vCurClip, vPrevClip);
    outLinearDepth = g.linearDepth;
    outNormal = g.normal;
    outAlbedo = g.albedo;
    outMaterial = g.material;
    outEmissive = g.emissive;
    outVelocity = g.velocity;
}
