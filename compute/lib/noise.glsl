// Blue-noise lookups (texture made by src/render/noise.cpp: 64x64 tile,
// 4 independent channels in (0,1), 8 variants cycled per frame).
#pragma once

// 4 blue-noise values for a pixel in this frame's variant.
vec4 blueNoise(sampler2DArray noiseTex, ivec2 pixel, uint frameIdx) {
    return texelFetch(noiseTex, ivec3(pixel & 63, int(frameIdx & 7u)), 0);
}

// The 4x4 tiled noise of seed 003 5.1.1 (same variant every frame: the
// Crytek SSAO has no temporal component), as a vector in [-1,1]^3.
vec3 tiledNoise4x4(sampler2DArray noiseTex, ivec2 pixel) {
    return texelFetch(noiseTex, ivec3(pixel & 3, 0), 0).xyz * 2.0 - 1.0;
}
