#pragma once
// Compute-rasterizer passes (raster.path=compute; docs/visibility.md).
#include "render/pass.h"

#include <memory>
#include <vector>

namespace rtgi {
// visibility.raster -> visibility.resolve (replace the hardware `gbuffer`)
// -> visibility.layer2 (ao.second_layer).
void appendVisibilityPasses(std::vector<std::unique_ptr<Pass>>& frame);
// shadow.raster (replaces the hardware `shadow`).
std::unique_ptr<Pass> makeShadowRasterPass();
}  // namespace rtgi
