#pragma once
// --reference: renders (or loads from the cache) the reference that matches
// a finished run's output and measures the error (results.json "error");
// --compare: the same metrics for two image files.
#include "gl/image_io.h"
#include "render/reference/reference_kind.h"
#include "render/renderer.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace rtgi {

// Compares `run`'s current output with the matching reference; writes
// reference images and the error heat map into outDir when writeImages.
// `framesRendered`: how many frames `run` rendered (the frames without a
// technique, for error.gain, are rendered as many times so that temporal
// filters stand where the run's do).
nlohmann::json compareWithReference(Renderer& run, const Camera& camera, glm::ivec2 resolution,
                                    const std::string& outDir, bool writeImages,
                                    ReferenceSettings::Kind requested = ReferenceSettings::Kind::Off,
                                    int framesRendered = 1);

// What `rtgi-bench --compare` compares (docs/reference.md, "Comparing image
// files"): the quantity and which pixels.
struct CompareOptions {
    // Auto: radiance for a PFM/EXR reference, ldr otherwise. Ao: channel 0 in
    // [0,1] (no relative RMSE: it is meaningless for AO). Ldr: rgb in [0,1].
    // Radiance: HDR rgb, PSNR/SSIM peak = the reference's largest luminance
    // over the compared pixels, plus relative RMSE.
    enum class Quantity { Auto, Ao, Ldr, Radiance } quantity = Quantity::Auto;
    std::string maskFile;             // compare where the mask's channel 0 > 0.5
    std::optional<double> background; // skip pixels whose reference equals this in every compared channel
    std::string outDir = "out";
};
const char* toString(CompareOptions::Quantity q);
CompareOptions::Quantity parseCompareQuantity(const std::string& s);  // throws ConfigError

// Error metrics of IMAGE against REFERENCE (PNG, PFM or EXR); the result says
// which quantity and pixels were compared ("compared"); writes
// error.heatmap.png and compare.json into opts.outDir.
nlohmann::json compareImageFiles(const std::string& image, const std::string& reference, const CompareOptions& opts);

}  // namespace rtgi
