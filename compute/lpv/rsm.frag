// lpv.rsm (raster path): see lpv/rsm.glsl.
#include "lpv/rsm.glsl"

layout(location = 0) in vec3 vWorldPos;
layout(location = 1) in vec3 vNormal;
layout(location = 2) in vec2 vUv;
layout(location = 3) flat in uint vMaterial;

layout(location = 0) out vec4 outFlux;
layout(location = 1) out vec4 outNormal;

void main() { rsmTexel(vNormal, vMaterial, materialBaseColor(vMaterial, vUv), outFlux, outNormal); }
