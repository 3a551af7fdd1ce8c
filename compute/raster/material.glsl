// Material table access for raster passes.
#pragma once
#include "lib/shared.h"

layout(std430, binding = RTGI_SSBO_MATERIALS) readonly buffer MaterialBlock { GpuMaterial materials[]; };
layout(binding = RTGI_TEX_MATERIALS) uniform sampler2DArray uBaseColorTextures;

vec4 materialBaseColor(uint m, vec2 uv) {
    vec4 c = materials[m].baseColor;
    float layer = materials[m].params.z;
    if (layer >= 0.0) c *= texture(uBaseColorTextures, vec3(uv, layer));
    return c;
}

// With explicit UV derivatives (compute resolves of the visibility buffer).
vec4 materialBaseColorGrad(uint m, vec2 uv, vec2 dUvDx, vec2 dUvDy) {
    vec4 c = materials[m].baseColor;
    float layer = materials[m].params.z;
    if (layer >= 0.0) c *= textureGrad(uBaseColorTextures, vec3(uv, layer), dUvDx, dUvDy);
    return c;
}
