#pragma once
// Screen-space reflections (seed 000 sections 4.4, 5.4; SPEC 5).
#include "render/pass.h"

#include <memory>
#include <vector>

namespace rtgi {
void appendSsrPasses(std::vector<std::unique_ptr<Pass>>& frame);
// Whether the ssr.* passes run (ssr=off, or auto without a glossy material: no).
Need ssrFamily(const Scene& scene, const Settings& settings);
// The tracer that runs for this scene + settings (Off when none; `auto`
// resolves to linear when some material is at most ssr.roughness_cutoff).
SsrSettings::Tracer effectiveSsrTracer(const Scene& scene, const Settings& settings);
}  // namespace rtgi
