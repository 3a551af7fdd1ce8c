#pragma once
// Project-generated blue noise (SPEC 6.1, seed 000 5.3 after [MG16]): white
// noise, high-pass filtered on a torus, rank-remapped back to a uniform
// distribution. Shared by every screen-space family: AO rotations/jitter and
// the SSR ray-start jitter read res.blueNoise through compute/lib/noise.glsl.
#include "render/frame_resources.h"

#include <vector>

namespace rtgi {

constexpr int kBlueNoiseSize = 64;     // tile edge (texels), tiled over the screen
constexpr int kBlueNoiseVariants = 8;  // layers, cycled per frame (frame % 8)

// One size x size tileable blue-noise channel with values (rank + 0.5)/n in
// (0, 1), exactly uniform. Deterministic for a seed.
std::vector<float> blueNoiseTile(int size, unsigned seed);

// Creates res.blueNoise once (RGBA8 2D array, 64 x 64 x 8, channels from
// independent seeds) and returns it; later calls return the same texture.
const gl::Texture& ensureBlueNoise(FrameResources& res, gl::MemoryLedger& ledger);
// Its descriptor (the memory estimate counts it for the AO and SSR families, its users).
gl::TextureDesc blueNoiseDesc();

}  // namespace rtgi
