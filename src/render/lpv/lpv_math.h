#pragma once
// Pure (GL-free) LPV math: volume placement, RSM texel area and the one
// function turning settings into the GPU constant block (unit-tested).
#include "render/gpu_types.h"
#include "render/settings.h"
#include "scene/scene.h"

#include "compute/lib/lpv_shared.h"
#include "compute/lib/sh_shared.h"

namespace rtgi::gpu {
static_assert(sizeof(LpvUniforms) == 2 * 64 + 6 * 16, "LpvUniforms must match std140 layout");
}

namespace rtgi::lpv {

// Lower bound of cos(normal, view or light) when a texel's surface area is
// derived from its projected area: grazing texels count at most 4x.
constexpr float kMinAreaCos = 0.25f;

struct Placement {
    glm::vec3 origin{0.0f};      // world position of the min corner
    float cell = 1.0f;           // cell size s
    glm::ivec3 grid{1};          // cells per axis
    glm::ivec3 originCells{0};   // origin / s (integer when camera-following)
    bool fitted = false;         // lpv.cell = 0: fitted to the scene, camera-independent
    Aabb box() const {
        Aabb b;
        b.lo = origin;
        b.hi = origin + glm::vec3(grid) * cell;
        return b;
    }
};

// lpv.cell > 0: grid centre 30 % of the extent ahead of the camera (80/20,
// seed 5.2, SPEC 11.1), origin snapped to whole cells (SPEC 3.1).
// lpv.cell = 0: cells just large enough that the grid holds the scene
// bounds, centred on them (no camera dependence, so nothing to snap).
Placement placeVolume(const LpvSettings& s, const Aabb& sceneBounds, glm::vec3 cameraPos, glm::vec3 cameraForward);

// World area of one texel of an orthographic light view-projection with R x R texels.
double rsmTexelArea(const glm::mat4& lightViewProj, int rsmSize);

// Cell shift from this frame's grid to the previous one (temporal re-indexing).
glm::ivec3 temporalShift(const Placement& current, const Placement& previous);
// Whether the previous volume can be re-indexed into this one at all.
bool historyCompatible(const Placement& current, const Placement& previous);

struct UniformInputs {
    Placement placement;
    glm::mat4 rsmViewProj{1.0f};
    glm::ivec3 shift{0};
    bool historyValid = false;
    bool specular = false;
};
gpu::LpvUniforms makeUniforms(const LpvSettings& s, const UniformInputs& in);

}  // namespace rtgi::lpv
