#pragma once
// Screen-space AO family (seed 003 sections 3-5, seed 000 sections 4, 5.3; SPEC 4, 6).
#include "render/pass.h"

#include <memory>
#include <vector>

namespace rtgi {
// ao.<variant>, ao.blur, ao.temporal, ao.upsample, ... (before LPV apply).
void appendAoPasses(std::vector<std::unique_ptr<Pass>>& frame);
// ao.nearfield (after LPV apply: accumulates into R::indirectDiffuse).
void appendNearFieldPasses(std::vector<std::unique_ptr<Pass>>& frame);
// Whether the ao.* passes run (ao != off).
Need aoFamily(const Scene& scene, const Settings& settings);
// ConfigError for AO settings that cannot work together (ao.depth_source=light).
void validateAoSettings(const Scene& scene, const Settings& settings);
}  // namespace rtgi
