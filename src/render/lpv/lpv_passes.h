#pragma once
// Light Propagation Volumes (seed 000 sections 3, 5.2; SPEC section 3).
#include "render/pass.h"

#include <memory>
#include <vector>

namespace rtgi {
// Appends lpv.rsm, lpv.inject, lpv.inject_geometry, lpv.propagate, lpv.apply, ...
void appendLpvPasses(std::vector<std::unique_ptr<Pass>>& frame);
// Rejects settings the LPV cannot run (lpv.sh_order=2 with lpv.path=raster) with a ConfigError.
void validateLpvSettings(const Scene& scene, const Settings& settings);
// Whether the lpv.* passes run (lpv=off, or no sun for the RSM: no).
Need lpvFamily(const Scene& scene, const Settings& settings);
// Whether LPV runs for this scene + settings (auto: when the scene has a sun).
bool lpvActive(const Scene& scene, const Settings& settings);
// Whether lpv.coarse_iterations matters for this frame: the LPV runs, on the compute path, with more than one
// cascade (the coarsest is the one stepped separately). lpv.coarse_iterations=auto measures the scene only then.
bool lpvCoarseStepsUsed(const Scene& scene, const Settings& settings);
// Whether LPV specular runs (auto: when a material is at most ssr.roughness_cutoff rough).
bool lpvSpecularActive(const Scene& scene, const Settings& settings);
}  // namespace rtgi
