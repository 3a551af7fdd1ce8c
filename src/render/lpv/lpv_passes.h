#pragma once
// Light Propagation Volumes (seed 000 sections 3, 5.2; SPEC section 3).
#include "render/pass.h"

#include <memory>
#include <vector>

namespace rtgi {
// Appends lpv.rsm, lpv.inject, lpv.inject_geometry, lpv.propagate, lpv.apply, ...
void appendLpvPasses(std::vector<std::unique_ptr<Pass>>& frame);
}  // namespace rtgi
