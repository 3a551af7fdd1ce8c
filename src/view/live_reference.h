#pragma once
// rtgi-view's live reference comparison (docs/viewer.md): a second renderer
// with the matching ray-traced reference (ray-traced AO, path-traced indirect
// light or image; render/reference/reference_kind.h) adds a few samples per
// frame in progressive mode, so the window stays interactive; a camera move
// or a new configuration restarts it. Error numbers against the technique's
// output are recomputed a few times a second on the CPU (metrics.h).
#include "gl/profiler.h"
#include "render/reference/metrics.h"
#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rtgi::view {

struct LiveErrors {
    bool valid = false;
    ErrorMetrics metrics;      // over the geometry pixels (SSIM: whole image)
    double referenceNoise = 0; // RMS standard error of the reference over the same pixels
    RmseUncertainty uncertainty; // debiased RMSE and its 95 % interval (docs/reference.md)
    double heatMax = 0;        // 99th percentile of |Δ luminance| (the heat map's scale, as rtgi-bench's)
    int samples = 0, targetSamples = 0;
    std::string compared;      // "ao", "indirect", "full"
    // Issue 22: does the GI help? The same view rendered without the technique ("lpv": lpv=off,
    // "nearfield": ao.nearfield=0) against the same reference; gain = 1 - RMSE / RMSE without, on the
    // debiased RMSEs (as rtgi-bench's error.gain). Not for AO references.
    struct Gain {
        std::string technique;
        double gain = 0.0, rmseWithout = 0.0;
    };
    std::vector<Gain> gains;
};

class LiveReference {
public:
    // `samplesPerFrame` samples each frame until reference.spp of the run's settings.
    explicit LiveReference(int samplesPerFrame = 4) : perFrame_(samplesPerFrame) {}
    // Follows `run`'s scene and settings (rebuilds when they changed), renders
    // the next samples for `view`, and refreshes the errors at most every
    // `metricsEvery` seconds (always when the reference just converged).
    void update(Renderer& run, const View& view, double metricsEvery = 0.25);
    void reset() {
        ref_.reset();
        runKey_.clear();
    }
    bool active() const { return ref_ != nullptr; }
    void setSamplesPerFrame(int n) { perFrame_ = std::max(n, 1); }
    int samplesPerFrame() const { return perFrame_; }
    // The reference mean (RGBA32F; AO in rgb, or radiance), null before the first update.
    const gl::Texture* mean() const;
    // The run's texture it is compared with.
    const gl::Texture* compared(Renderer& run) const;
    ReferenceSettings::Kind kind() const { return kind_; }
    const LiveErrors& errors() const { return errors_; }
    bool converged() const { return errors_.samples >= errors_.targetSamples && errors_.targetSamples > 0; }

private:
    void measure(Renderer& run);

    int perFrame_;
    std::unique_ptr<gl::Profiler> profiler_;
    std::unique_ptr<Renderer> ref_;
    View view_;  // the technique's last view (the frames rendered without it use it)
    // The renderers without a technique (gains), keyed by technique, and their settings' keys.
    std::vector<std::pair<std::string, std::unique_ptr<Renderer>>> without_;
    std::vector<std::string> withoutKeys_;
    std::string settingsKey_, runKey_, imageKey_;
    ReferenceSettings::Kind kind_ = ReferenceSettings::Kind::Off;
    LiveErrors errors_;
    int measuredAt_ = -1;
    std::chrono::steady_clock::time_point lastMeasure_{};
};

}  // namespace rtgi::view
