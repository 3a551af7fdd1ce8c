// G-buffer: linear view depth, view-space normal, albedo, roughness/metallic,
// emission, velocity (previous − current projected position in UV).
#include "lib/common.glsl"
#include "raster/material.glsl"

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
    vec3 viewPos = (frame.view * vec4(vWorldPos, 1.0)).xyz;
    outLinearDepth = -viewPos.z;
    vec3 n = normalize(vNormal);
    // Two-sided: flip normals of back faces so thin geometry shades correctly.
    if (!gl_FrontFacing) n = -n;
    vec3 nv = normalize(mat3(frame.view) * n);
    if (any(isnan(nv))) nv = vec3(0.0, 0.0, 1.0);
    outNormal = vec4(nv, 1.0);
    outAlbedo = vec4(materialBaseColor(vMaterial, vUv).rgb, 1.0);
    outMaterial = vec4(materials[vMaterial].params.x, materials[vMaterial].params.y, 0.0, 1.0);
    outEmissive = materials[vMaterial].emissive.rgb;
    vec2 cur = vCurClip.xy / vCurClip.w * 0.5 + 0.5;
    vec2 prev = vPrevClip.xy / vPrevClip.w * 0.5 + 0.5;
    outVelocity = prev - cur;
}
