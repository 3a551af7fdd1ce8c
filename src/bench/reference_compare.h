#pragma once
// --reference: renders (or loads from the cache) the reference that matches
// a finished run's output and measures the error (results.json "error");
// --compare: the same metrics for two image files.
#include "gl/image_io.h"
#include "render/reference/flip.h"
#include "render/reference/reference_kind.h"
#include "render/renderer.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rtgi {

class ReferenceOutput;

// The ray-traced reference of `run`'s scene, lights and settings (the
// real-time techniques off: they would only cost time) for `kind`;
// `overrides` (e.g. reference.spp) are applied on top. --reference and the
// Python module's Renderer.reference() trace through it.
class ReferenceTrace {
public:
    ReferenceTrace(const Renderer& run, ReferenceSettings::Kind kind, const Assignments& overrides = {});
    const Settings& settings() const { return settings_; }
    Renderer& renderer() { return *renderer_; }
    ReferenceOutput& output() { return *out_; }
    const char* passName() const;  // "ref.ao" or "ref.path"
    // results.json error.reference (without noise_ratio): the reference's
    // settings, pass statistics, spp, RMS standard error over `mask`, cache.
    nlohmann::json info(const FloatImage& se, int channels, const std::vector<std::uint8_t>& mask) const;

private:
    ReferenceSettings::Kind kind_;
    Settings settings_;
    gl::Profiler profiler_{false};
    std::unique_ptr<Renderer> renderer_;
    ReferenceOutput* out_ = nullptr;
};

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

// The same metrics for images in memory (compareImageFiles reads the files
// and calls this; the Python module passes arrays): no file is read or
// written. `mask` replaces opts.maskFile.
struct CompareData {
    std::string imageName, referenceName;  // as "image" / "reference" in the result and in messages
    bool imageHdr = true, referenceHdr = true;  // PFM/EXR values (linear); false: PNG (sRGB-encoded)
    const FloatImage* mask = nullptr;
    std::string maskName;
};
struct CompareResult {
    nlohmann::json json;  // compare.json
    FlipResult flip;      // its error map makes error.flip.png
    double heatmapMax = 0;
    int channels = 3;
};
CompareResult compareImageData(const FloatImage& image, const FloatImage& reference, const CompareData& data,
                               const CompareOptions& opts);

}  // namespace rtgi
