#pragma once
// Settings -> GPU constants of the AO family (one pure function, no GL), and
// the sample sets it generates in code: sphere kernel (seed 003 5.5), VO
// line-sample pairs with Voronoi volume weights (seed 003 3.2.2, SPEC 11.8),
// the Poisson-disk probe of the dynamic radius (seed 003 4.2.2).
#include "render/gpu_types.h"
#include "render/settings.h"

#include "compute/lib/ao_shared.h"

#include <vector>

namespace rtgi {

static_assert(sizeof(gpu::AoParams) ==
                  7 * 16 + 16 * (RTGI_AO_MAX_KERNEL + RTGI_AO_MAX_VO_PAIRS + RTGI_AO_MAX_PROBE),
              "AoParams must match the std140 layout of compute/lib/ao_shared.h");

// Directions x steps for the horizon-based variants (seed 003 table 6.2:
// 8 -> 4x2, 16 -> 4x4, 24 -> 6x4; other counts: 6 directions from 24 on, else 4).
glm::ivec2 horizonSampling(int samples);

// Inverse CDF of d(x) = 3/2 (1 - x^2) on [0, 1]: F(x) = (3x - x^3)/2 = u
// solved in closed form x = 2 sin(asin(u)/3).
double sphereKernelRadius(double u);
// n unit-ball offsets: directions uniform on the sphere (Algorithm 2), radius
// drawn from d(x); antithetic pairs k[2i+1] = -k[2i] (odd n: the last one
// unpaired); fixed seed. w = 0.
std::vector<glm::vec4> sphereKernel(int n, unsigned seed = 7);

// VO: `pairs` line-sample positions p_i on the unit disk (Vogel spiral over a
// half disk; the pair partner is -p_i), each with half-length z_s and the
// exact volume of its Voronoi cell column, integral of 2 sqrt(1 - r^2) dA over
// the cell (grid of `grid`^2 cells). Returned per pair (both partners share the
// weight by symmetry): x, y, z_s, volume of ONE partner.
std::vector<glm::vec4> voSamplePairs(int pairs, int grid = 384);

// K points of a Poisson disk (dart throwing with a shrinking minimum
// distance) in the unit disk; fixed seed.
std::vector<glm::vec2> poissonDisk(int k, unsigned seed = 11);

// The whole GPU block. aoSize = AO resolution, fullSize = G-buffer size.
gpu::AoParams makeAoParams(const AoSettings& s, glm::ivec2 aoSize, glm::ivec2 fullSize, float fovY);

}  // namespace rtgi
