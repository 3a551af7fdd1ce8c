#pragma once
// Pure (GL-free) LPV math: volume placement, RSM texel area and the one
// function turning settings into the GPU constant block (unit-tested).
#include "render/gpu_types.h"
#include "render/settings.h"
#include "scene/scene.h"

#include "compute/lib/lpv_shared.h"
#include "compute/lib/sh_shared.h"

#include <array>
#include <vector>

namespace rtgi::gpu {
static_assert(sizeof(LpvUniforms) == 2 * 64 + (9 + RTGI_LPV_MAX_CASCADES) * 16, "LpvUniforms must match std140 layout");
static_assert(sizeof(LpvRsmFace) == 64 + 16, "LpvRsmFace must match std430 layout");
}

namespace rtgi::lpv {

// Lower bound of cos(normal, view or light) when a texel's surface area is
// derived from its projected area: grazing texels count at most 4x.
constexpr float kMinAreaCos = 0.25f;

struct Placement {
    glm::vec3 origin{0.0f};      // world position of the min corner
    float cell = 1.0f;           // cell size s
    glm::ivec3 grid{1};          // cells per axis
    glm::ivec3 originCells{0};   // floor(origin / s) (origin / s exactly when snapped)
    bool fitted = false;         // lpv.cell = 0: fitted to the scene, camera-independent
    bool snapped = true;         // camera-following with lpv.snap=on: the origin lies on whole cells
    Aabb box() const {
        Aabb b;
        b.lo = origin;
        b.hi = origin + glm::vec3(grid) * cell;
        return b;
    }
};

// lpv.cell > 0: grid centre 30 % of the extent ahead of the camera (80/20,
// seed 5.2, SPEC 11.1), origin snapped to whole cells (SPEC 3.1; lpv.snap=off:
// the unsnapped min corner).
// lpv.cell = 0: cells just large enough that the grid holds the scene
// bounds, centred on them (no camera dependence, so nothing to snap).
Placement placeVolume(const LpvSettings& s, const Aabb& sceneBounds, glm::vec3 cameraPos, glm::vec3 cameraForward);

// lpv.cascades = C > 1 (docs/lpv.md, "Cascades"): cascade i has cells
// s_0 * 2^i, each camera-following (centre 30 % of its extent ahead of the
// camera), moved inside the scene bounds where it is smaller than them, and
// its origin snapped to its own cells (lpv.snap=off: not snapped). s_0 = lpv.cell, or for lpv.cell = 0 the
// coarsest cell is chosen so that the coarsest cascade holds the scene bounds
// after snapping (extent >= bounds + 2 cells). C = 1: placeVolume().
std::vector<Placement> placeCascades(const LpvSettings& s, int cascades, const Aabb& sceneBounds, glm::vec3 cameraPos,
                                     glm::vec3 cameraForward);

// Path-length split between cascades (docs/lpv.md): step k of cascade i
// carries the light whose path length lies in [k s_i, (k + 1) s_i). Cascade
// i > 0 counts as "far" only what cascade i - 1 (n + 1 steps of s_{i-1} =
// s_i / 2) did not cover: paths >= t s_i with t = (n + 1) / 2. Returns the
// weight of step k in the near part (1 - clamp(k + 1 - t, 0, 1)).
double cascadeNearWeight(int step, int iterations);

// Self-illumination of the scheme (docs/lpv.md, "Self-illumination"): the
// irradiance that a uniformly lit infinite plane of exitance M receives from
// its own injection through the volume, per unit M, for `iterations` steps
// with the given re-emission and energy conservation (a 1D column of cells
// in double, laterally uniform; nothing below the plane). The truth is 0.
// .x: all steps; .y: the steps weighted by cascadeNearWeight.
// `order`: SH bands used by the scheme (lpv.sh_order, 1 or 2).
// `nearIterations` (0: iterations) sets the near weights (a coarsest cascade with its own step count).
glm::dvec2 planeSelfIrradiance(int iterations, bool flow, bool conserving, int order = 1, int nearIterations = 0);
// Propagation steps of cascade `cascade` of `count`: lpv.coarse_iterations for the coarsest of several
// (when set), lpv.iterations otherwise.
int cascadeSteps(const LpvSettings& s, int cascade, int count);

// SH of bands 0-2 in double (lpv.sh_order=2, docs/lpv.md "Second-order SH"): the 9
// coefficients in the order and with the signs of compute/lib/sh_shared.h; an SH of
// bands 0-1 is one whose coefficients 4-8 are 0.
using Sh9 = std::array<double, 9>;
Sh9 shBasis9(glm::dvec3 d);
// Projection of max(0, n.w): A_l Y_lm(n), A = (pi, 2 pi / 3, pi / 4).
Sh9 shCosineLobe9(glm::dvec3 n);
double shDot9(const Sh9& a, const Sh9& b);
// Keeps the first 4 (order 1) or all 9 (order 2) coefficients.
Sh9 shTruncate(const Sh9& c, int order);
// The propagation's face transfer (docs/lpv.md) in bands 0..order: for a source of
// intensity I flowing along the axis d into a destination, each of its 5 exit faces f
// receives Phi_f = dOmega_f max(0, I(w_f)) and re-emits (Phi_f / pi) cosLobe(n_f or w_f)
// (lpv.reemit=face | flow), truncated to the order, times `transmit`, added to `dst`.
// Returns the sum of Phi_f (before transmission).
double faceTransfer(const Sh9& I, glm::dvec3 d, double transmit, bool flow, int order, Sh9& dst);
// Sum of Phi_f over all 30 faces a source feeds (6 destinations x 5 faces).
double quadratureFlux(const Sh9& I);
// lpv.energy_conserving: the scale that makes the quadrature flux equal 2 sqrt(pi) I_00.
double conservingScale(const Sh9& I);

// Blend width of a cascade's border in cells (apply).
constexpr float kCascadeBlendCells = 2.0f;

// World area of one texel of an orthographic light view-projection with R x R texels.
double rsmTexelArea(const glm::mat4& lightViewProj, int rsmSize);

// Cell shift from this frame's grid to the previous one (temporal re-indexing).
glm::ivec3 temporalShift(const Placement& current, const Placement& previous);
// Whether the previous volume can be re-indexed into this one at all: the same
// grid and cells, and a whole-cell shift (an unsnapped volume only when it did not move).
bool historyCompatible(const Placement& current, const Placement& previous);

struct UniformInputs {
    Placement placement;
    glm::mat4 rsmViewProj{1.0f};
    glm::ivec3 shift{0};
    bool historyValid = false;
    bool specular = false;
    int cascade = 0;                        // this volume's cascade
    std::vector<Placement> cascades;        // all of them (empty: just `placement`)
};
gpu::LpvUniforms makeUniforms(const LpvSettings& s, const UniformInputs& in);

}  // namespace rtgi::lpv
