#include "view/live_reference.h"

#include "gl/image_io.h"
#include "render/reference/reference_cache.h"
#include "render/reference/reference_kind.h"
#include "render/reference/reference_passes.h"
#include "render/lpv/lpv_passes.h"

namespace rtgi::view {

namespace {
std::string key(const Settings& s) {
    std::string k;
    for (auto& [name, v] : describe(s)) k += name + "=" + v + "\n";
    return k;
}
}  // namespace

void LiveReference::update(Renderer& run, const View& view, double metricsEvery) {
    using K = ReferenceSettings::Kind;
    const K kind = referenceKindFor(run.settings(), run.resources());
    Settings rs = referenceRunSettings(run.settings(), kind);
    rs.reference.cacheDir = "off";  // progressive samples are not cached
    // Restart only when the reference image changes: the reference cache's key
    // over everything but the view (the trace pass restarts itself on a new
    // view). post.exposure or lpv.grid do not restart an AO reference.
    const std::string runKey = key(run.settings());
    if (runKey != runKey_) {
        runKey_ = runKey;
        imageKey_ = std::to_string(int(kind)) + referenceCacheKey(run.scene(), rs, referenceConstants(rs, run.scene().bounds()), View{});
    }
    view_ = view;
    const std::string k = imageKey_;
    if (!ref_ || k != settingsKey_) {
        if (!profiler_) profiler_ = std::make_unique<gl::Profiler>(false);
        if (ref_) ref_->configure(rs);
        else ref_ = std::make_unique<Renderer>(run.scene(), rs, *profiler_);
        settingsKey_ = k;
        kind_ = kind;
        measuredAt_ = -1;
        errors_ = {};
    }
    auto* out = dynamic_cast<ReferenceOutput*>(ref_->findPass(kind == K::Ao ? "ref.ao" : "ref.path"));
    if (!out) return;
    out->setProgressive(perFrame_);
    // The camera of the technique's frame, as a first frame (no history).
    View v = view;
    v.frame = 0;
    v.cut = true;
    v.prevView = v.view;
    v.prevProj = v.proj;
    ref_->render(v);
    const int done = out->samplesDone();
    errors_.targetSamples = rs.reference.spp;
    if (done < measuredAt_) measuredAt_ = -1;  // restarted (camera moved)
    errors_.samples = done;
    const auto now = std::chrono::steady_clock::now();
    const bool justConverged = done >= rs.reference.spp && measuredAt_ < done;
    if (justConverged || std::chrono::duration<double>(now - lastMeasure_).count() >= metricsEvery) {
        measure(run);
        measuredAt_ = done;
        lastMeasure_ = now;
    }
}

const gl::Texture* LiveReference::mean() const {
    if (!ref_) return nullptr;
    auto* out = dynamic_cast<ReferenceOutput*>(ref_->findPass(kind_ == ReferenceSettings::Kind::Ao ? "ref.ao" : "ref.path"));
    return out && out->mean() ? &out->mean() : nullptr;
}

const gl::Texture* LiveReference::compared(Renderer& run) const {
    const gl::Texture& t = comparedTexture(kind_, run.resources());
    return t ? &t : nullptr;
}

void LiveReference::measure(Renderer& run) {
    using K = ReferenceSettings::Kind;
    const gl::Texture* tested = compared(run);
    auto* out = dynamic_cast<ReferenceOutput*>(ref_->findPass(kind_ == K::Ao ? "ref.ao" : "ref.path"));
    if (!tested || !out || !out->mean()) return;
    FloatImage test = readTexture(*tested), mean = readTexture(out->mean()), se = readTexture(out->standardError());
    FloatImage depth = readTexture(run.resources().gbuffer.linearDepth);
    if (test.width != mean.width || test.height != mean.height) return;  // half-resolution output: not comparable here
    std::vector<std::uint8_t> mask(std::size_t(depth.width) * std::size_t(depth.height));
    double peak = 1e-6;
    const int channels = kind_ == K::Ao ? 1 : 3;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        mask[i] = depth.data[i * 4] > 0.0f ? 1 : 0;
        if (mask[i] && channels == 3) peak = std::max(peak, pixelLuminance(mean, i, 3));
    }
    if (channels == 1) peak = 1.0;
    errors_.metrics = compareImages(test, mean, channels, peak, mask);
    errors_.referenceNoise = rmsStandardError(se, channels, mask);
    errors_.uncertainty = rmseUncertainty(test, mean, se, channels, mask);
    errors_.heatMax = errorQuantile(test, mean, channels, 0.99);
    errors_.compared = kind_ == K::Ao ? "ao" : kind_ == K::Indirect ? "indirect" : "full";
    errors_.valid = true;
    // Gains (issue 22): each technique switched off, the same view, the same reference and pixels.
    errors_.gains.clear();
    if (kind_ == K::Ao) return;
    std::vector<std::pair<std::string, Settings>> off;
    if (lpvActive(run.scene(), run.settings())) {
        Settings w = run.settings();
        w.lpv.mode = Toggle::Off;
        off.emplace_back("lpv", w);
    }
    if (run.settings().ao.nearfield > 0 && run.settings().ao.variant != AoSettings::Variant::Off) {
        Settings w = run.settings();
        w.ao.nearfield = 0.0f;
        off.emplace_back("nearfield", w);
    }
    without_.resize(off.size());
    withoutKeys_.resize(off.size());
    for (std::size_t i = 0; i < off.size(); ++i) {
        auto& [name, renderer] = without_[i];
        const std::string k = key(off[i].second);
        if (!renderer || name != off[i].first) renderer = std::make_unique<Renderer>(run.scene(), off[i].second, *profiler_);
        else if (k != withoutKeys_[i]) renderer->configure(off[i].second);
        name = off[i].first;
        withoutKeys_[i] = k;
        renderer->render(view_);
        const gl::Texture& t = comparedTexture(kind_, renderer->resources());
        if (!t) continue;
        const FloatImage w = readTexture(t);
        if (w.width != mean.width || w.height != mean.height) continue;
        const RmseUncertainty o = rmseUncertainty(w, mean, se, channels, mask);
        const double gain = o.rmseDebiased > 0.0 ? 1.0 - errors_.uncertainty.rmseDebiased / o.rmseDebiased : 0.0;
        errors_.gains.push_back({name, gain, o.rmseDebiased});
    }
}

}  // namespace rtgi::view
