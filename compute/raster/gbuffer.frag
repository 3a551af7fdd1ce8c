// G-buffer: linear view depth, view-space normal, albedo, roughness/metallic,
// emission, velocity (previous − current projected position in UV).
#include "raster/gbuffer.glsl"

layout(location = 0) in vec3 vWorldPos;
layout(location = 1) in vec3 vNormal;
layout(location = 2) in vec2 vUv;
layout(location = 3) flat in uint vMaterial;
layout(location = 4) in vec4 vCurClip;
layout(location = 5) in vec4 vPrevClip;

layout(location = 0) out float outLinearDepth;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec4 outAlbedo;
layout(location = 3) out vec4 outMaterial;
layout(location = 4) out vec3 outEmissive;
layout(location = 5) out vec2 outVelocity;

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
