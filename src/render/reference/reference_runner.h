#pragma once
// --reference: renders (or loads from the cache) the reference that matches
// a finished run's output and measures the error (results.json "error");
// --compare: the same metrics for two image files.
#include "render/renderer.h"

#include <nlohmann/json.hpp>

#include <string>

namespace rtgi {

// What a run's output is compared with: res.ao with ray-traced AO (the run
// has an AO variant), res.indirectDiffuse with path-traced indirect light
// (an indirect technique wrote it), else res.hdr with the full path-traced
// image. An explicit `reference=KIND` in the settings wins.
ReferenceSettings::Kind referenceKindFor(const Settings& settings, const FrameResources& res);

// Compares `run`'s current output with the matching reference; writes
// reference images and the error heat map into outDir when writeImages.
nlohmann::json compareWithReference(Renderer& run, const Camera& camera, glm::ivec2 resolution,
                                    const std::string& outDir, bool writeImages);

// rtgi-bench --compare IMAGE REFERENCE: PNG (compared in [0,1]) or PFM
// (HDR: PSNR/SSIM peak = the reference's largest luminance, plus relative
// RMSE); writes error.heatmap.png and compare.json into outDir.
nlohmann::json compareImageFiles(const std::string& image, const std::string& reference, const std::string& outDir);

}  // namespace rtgi
