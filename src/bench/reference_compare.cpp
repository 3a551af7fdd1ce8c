#include "bench/reference_compare.h"

#include "app/cli.h"

#include "gl/image_files.h"
#include "gl/image_io.h"
#include "gl/output_files.h"
#include "render/reference/flip.h"
#include "render/reference/metrics.h"
#include "render/reference/reference_cache.h"
#include "render/lpv/lpv_passes.h"
#include "render/lpv/lpv_probe.h"
#include "render/reference/reference_passes.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rtgi {

namespace {

nlohmann::json metricsJson(const ErrorMetrics& m, bool radiance) {
    auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json("inf"); };
    nlohmann::json j = {{"rmse", m.rmse}, {"mae", m.mae}, {"bias", m.bias}, {"psnr", finite(m.psnr)},
                        {"ssim", m.ssim}, {"pixels", m.pixels}, {"nan_pixels", m.nanPixels},
                        {"inf_pixels", m.infPixels}};
    if (radiance) j["rel_rmse"] = m.relRmse;
    return j;
}

// RMSE of predicting zero on the same pixels, and skill = 1 - rmse / rmse_zero
// (issue 12): > 0 means the technique beats predicting black, 1 is exact.
void addSkill(nlohmann::json& j, const FloatImage& test, const FloatImage& ref, int channels, double peak,
              const std::vector<std::uint8_t>& mask) {
    FloatImage zero = test;
    std::fill(zero.data.begin(), zero.data.end(), 0.0f);
    double rmseZero = compareImages(zero, ref, channels, peak, mask).rmse;
    j["rmse_zero"] = rmseZero;
    j["skill"] = rmseZero > 0 ? 1.0 - j["rmse"].get<double>() / rmseZero : 0.0;
}

// The reference's noise in the error (docs/reference.md, "Errors with their
// uncertainty"): the debiased RMSE and its 95 % interval.
void addUncertainty(nlohmann::json& j, const FloatImage& test, const FloatImage& ref, const FloatImage& se,
                    int channels, const std::vector<std::uint8_t>& mask) {
    RmseUncertainty u = rmseUncertainty(test, ref, se, channels, mask);
    j["rmse_debiased"] = u.rmseDebiased;
    j["rmse_ci95"] = {u.low, u.high};
    j["reference_noise"] = u.noiseRms;
}

// FLIP (docs/flip.md): HDR-FLIP for radiance, LDR-FLIP for AO (channel 0 as
// a grey display value in [0,1]).
FlipResult flipOf(const FloatImage& test, const FloatImage& ref, int channels, const std::vector<std::uint8_t>& mask) {
    if (channels == 3) return hdrFlip(test, ref, {}, mask);
    auto grey = [](const FloatImage& img) {
        FloatImage g = img;
        g.channels = 3;
        g.data.resize(std::size_t(img.width) * std::size_t(img.height) * 3);
        for (std::size_t i = 0; i < std::size_t(img.width) * std::size_t(img.height); ++i)
            g.data[i * 3] = g.data[i * 3 + 1] = g.data[i * 3 + 2] = img.data[i * std::size_t(img.channels)];
        return g;
    };
    return ldrFlip(grey(test), grey(ref), {}, mask);
}

// The mean of a FLIP error map over a mask (the map is 0 where an input was
// not finite; those pixels are in FlipResult::nonFinitePixels).
double flipMean(const FloatImage& map, const std::vector<std::uint8_t>& mask) {
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < std::size_t(map.width) * std::size_t(map.height); ++i)
        if (mask.empty() || mask[i]) {
            sum += map.data[i * std::size_t(map.channels)];
            ++n;
        }
    return n ? sum / double(n) : 0.0;
}

nlohmann::json flipJson(const FlipResult& f, int channels) {
    nlohmann::json j = {{"mean", f.mean}, {"kind", channels == 3 ? "hdr" : "ldr"}, {"pixels", f.pixels},
                        {"non_finite_pixels", f.nonFinitePixels}, {"pixels_per_degree", FlipOptions{}.pixelsPerDegree}};
    if (channels == 3) {
        j["start_exposure"] = f.startExposure;
        j["stop_exposure"] = f.stopExposure;
        j["exposures"] = f.exposures;
    }
    return j;
}

// Converging references (reference.target_noise): each check compares the
// tested image with the reference so far over the compared pixels.
void convergeAgainst(ReferenceOutput& out, const Settings& rs, const FloatImage& test, int channels,
                     const std::vector<std::uint8_t>& mask) {
    if (!rs.reference.converging()) return;
    out.setConvergence([&test, channels, &mask](const FloatImage& mean, const FloatImage& se) {
        RmseUncertainty u = rmseUncertainty(test, mean, se, channels, mask);
        ConvergenceCheck c;
        c.noise = u.noiseRms;
        c.error = u.rmseDebiased;
        return c;
    });
}

// The compared image of `run`'s scene and camera rendered with `settings`
// for `frames` frames (error.gain's frame without a technique).
FloatImage renderCompared(const Renderer& run, Settings settings, const Camera& camera, glm::ivec2 resolution,
                          int frames, ReferenceSettings::Kind kind) {
    settings.reference.kind = ReferenceSettings::Kind::Off;  // the frame only
    gl::Profiler profiler(false);
    Renderer r(run.scene(), settings, profiler);
    View prev;
    for (int f = 0; f < std::max(frames, 1); ++f) {
        View v = makeView(camera, resolution, f == 0 ? nullptr : &prev, unsigned(f));
        r.render(v);
        prev = v;
    }
    const gl::Texture& t = comparedTexture(kind, r.resources());
    if (!t) {  // the indirect term without its only technique: no light at all
        FloatImage zero = readTexture(r.resources().gbuffer.linearDepth);
        std::fill(zero.data.begin(), zero.data.end(), 0.0f);
        return zero;
    }
    return readTexture(t);
}

double peakLuminance(const FloatImage& ref, const std::vector<std::uint8_t>& mask) {
    double peak = 0;
    for (std::size_t i = 0; i < std::size_t(ref.width) * std::size_t(ref.height); ++i)
        if (mask.empty() || mask[i]) {
            double l = pixelLuminance(ref, i, 3);
            if (std::isfinite(l)) peak = std::max(peak, l);  // NaN/Inf pixels are counted, not used
        }
    return std::max(peak, 1e-6);
}

// One error object of an indirect image against a reference with its
// standard error (no SSIM): metrics, skill, uncertainty and FLIP over `mask`,
// and the same (FLIP from the same map) over `interior`.
nlohmann::json indirectErrorJson(const FloatImage& test, const FloatImage& ref, const FloatImage& se, double peak,
                                 const std::vector<std::uint8_t>& mask, const std::vector<std::uint8_t>& interior) {
    const int channels = 3;
    nlohmann::json j = metricsJson(compareImages(test, ref, channels, peak, mask), true);
    addSkill(j, test, ref, channels, peak, mask);
    addUncertainty(j, test, ref, se, channels, mask);
    const FlipResult flip = flipOf(test, ref, channels, mask);
    j["flip"] = flipJson(flip, channels);
    j.erase("ssim");
    nlohmann::json in = metricsJson(compareImages(test, ref, channels, peak, interior), true);
    addSkill(in, test, ref, channels, peak, interior);
    addUncertainty(in, test, ref, se, channels, interior);
    in["flip"] = {{"mean", flipMean(flip.errorMap, interior)}};
    in.erase("ssim");
    j["interior"] = in;
    return j;
}

// Issue 12: an LPV run's indirect light `test` against the path tracer with
// the light transport the LPV models (one bounce, two with lpv.bounce=on,
// Lambert only). `rs`: the settings of the reference already traced
// (`mean`, `se`); when it is an indirect reference with the same transport it
// is reused, else a matching one is traced (into `matching`).
nlohmann::json matchingBounceError(const Renderer& run, const Settings& rs, const FloatImage& test, const FloatImage& mean,
                                   const FloatImage& se, const std::vector<std::uint8_t>& mask,
                                   const std::vector<std::uint8_t>& interior, const View& v, FloatImage& matching,
                                   FloatImage& matchingSe) {
    using K = ReferenceSettings::Kind;
    const int channels = 3;
    Settings ms = referenceRunSettings(run.settings(), K::Indirect);
    ms.reference = rs.reference;
    ms.reference.kind = K::Indirect;
    ms.reference.bounces = run.settings().lpv.bounce ? 2 : 1;
    ms.reference.specular = false;
    const bool same = rs.reference.kind == K::Indirect && ms.reference.bounces == rs.reference.bounces &&
                      ms.reference.specular == rs.reference.specular;
    matching = mean;
    matchingSe = se;
    nlohmann::json matchingInfo;
    if (!same) {
        gl::Profiler profiler(false);
        Renderer mref(run.scene(), ms, profiler);
        auto* mout = dynamic_cast<ReferenceOutput*>(mref.findPass("ref.path"));
        if (!mout) throw ConfigError("--reference: the matching-bounce reference pass did not run");
        convergeAgainst(*mout, ms, test, channels, mask);
        mref.render(v);
        matching = readTexture(mout->mean());
        matchingSe = readTexture(mout->standardError());
        for (auto& [k, val] : mref.findPass("ref.path")->stats()) matchingInfo[k] = val;
        matchingInfo["spp"] = mout->samplesDone();
        matchingInfo["mean_stderr"] = rmsStandardError(matchingSe, channels, mask);
        if (!mout->convergenceInfo().is_null()) matchingInfo["convergence"] = mout->convergenceInfo();
    }
    double mpeak = peakLuminance(matching, mask);
    nlohmann::json mb = indirectErrorJson(test, matching, matchingSe, mpeak, mask, interior);
    mb["bounces"] = ms.reference.bounces;
    mb["specular"] = false;
    mb["same_as_reference"] = same;
    mb["peak"] = mpeak;
    if (!same) mb["reference"] = matchingInfo;
    return mb;
}

}  // namespace

ReferenceTrace::ReferenceTrace(const Renderer& run, ReferenceSettings::Kind kind, const Assignments& overrides)
    : kind_(kind), settings_(referenceRunSettings(run.settings(), kind)) {
    for (auto& [k, v] : overrides) applySetting(settings_, k, v);
    renderer_ = std::make_unique<Renderer>(run.scene(), settings_, profiler_);
    out_ = dynamic_cast<ReferenceOutput*>(renderer_->findPass(passName()));
    if (!out_) throw ConfigError("--reference: the reference pass did not run");
}

const char* ReferenceTrace::passName() const { return kind_ == ReferenceSettings::Kind::Ao ? "ref.ao" : "ref.path"; }

nlohmann::json ReferenceTrace::info(const FloatImage& se, int channels, const std::vector<std::uint8_t>& mask) const {
    nlohmann::json refInfo = referenceSettingsJson(referenceConstants(settings_, renderer_->scene().bounds()));
    for (auto& [k, val] : renderer_->findPass(passName())->stats()) refInfo[k] = val;
    refInfo["spp"] = out_->samplesDone();  // a converging reference's spp is what it took
    // The reference's own noise on the RMSE's scale: RMS of the per-pixel
    // standard error over the compared pixels and channels (docs/reference.md).
    refInfo["mean_stderr"] = rmsStandardError(se, channels, mask);
    if (!out_->convergenceInfo().is_null()) refInfo["convergence"] = out_->convergenceInfo();
    refInfo["from_cache"] = out_->fromCache();
    refInfo["cache_key"] = out_->cacheKey();
    refInfo["cache_dir"] = settings_.reference.cacheDir;
    return refInfo;
}

nlohmann::json compareWithReference(Renderer& run, const Camera& camera, glm::ivec2 resolution,
                                    const std::string& outDir, bool writeImages, ReferenceSettings::Kind requested,
                                    int framesRendered) {
    using K = ReferenceSettings::Kind;
    FrameResources& res = run.resources();
    K kind = requested != K::Off ? requested : referenceKindFor(run.settings(), res);
    const gl::Texture& tested = comparedTexture(kind, res);
    if (!tested)
        throw ConfigError(std::string("--reference: this run produced no ") +
                          (kind == K::Ao ? "AO (set ao=VARIANT)" : kind == K::Indirect ? "indirect light" : "image") +
                          " to compare with the reference");
    FloatImage test = readTexture(tested);
    FloatImage depth = readTexture(res.gbuffer.linearDepth);
    std::vector<std::uint8_t> mask(std::size_t(depth.width) * std::size_t(depth.height));
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = depth.data[i * 4] > 0.0f ? 1 : 0;
    const int channels = kind == K::Ao ? 1 : 3;

    // The reference renderer: the same scene, camera and lights, with the
    // real-time techniques off (they would only cost time).
    ReferenceTrace trace(run, kind);
    const Settings& rs = trace.settings();
    Renderer& ref = trace.renderer();
    ReferenceOutput* out = &trace.output();
    const char* passName = trace.passName();
    View v = makeView(camera, resolution, nullptr, 0);
    convergeAgainst(*out, rs, test, channels, mask);
    ref.render(v);
    FloatImage mean = readTexture(out->mean()), se = readTexture(out->standardError());

    double peak = kind == K::Ao ? 1.0 : peakLuminance(mean, mask);
    ErrorMetrics m = compareImages(test, mean, channels, peak, mask);
    nlohmann::json e = metricsJson(m, kind != K::Ao);
    addSkill(e, test, mean, channels, peak, mask);
    addUncertainty(e, test, mean, se, channels, mask);
    const FlipResult flip = flipOf(test, mean, channels, mask);
    e["flip"] = flipJson(flip, channels);
    e["compared"] = kind == K::Ao ? "ao" : kind == K::Indirect ? "indirectDiffuse" : "hdr";
    e["kind"] = kind == K::Ao ? "ao" : kind == K::Indirect ? "indirect" : "full";  // results.json config.reference
    e["pixels_compared"] = "geometry (linear depth > 0; sky excluded)";
    e["peak"] = peak;
    double heatMax = errorQuantile(test, mean, channels, 0.99);
    e["heatmap_max"] = heatMax;
    // The same metrics over the pixels away from depth discontinuities (3×3
    // relative depth jump <= 10 %): separates the estimator's error from the
    // edge band's (docs/ao.md, "Error against ray-traced AO"). SSIM is a
    // whole-image metric and not repeated.
    {
        const std::vector<std::uint8_t> interior = depthInteriorMask(depth, 0.1);
        nlohmann::json in = metricsJson(compareImages(test, mean, channels, peak, interior), kind != K::Ao);
        addSkill(in, test, mean, channels, peak, interior);
        addUncertainty(in, test, mean, se, channels, interior);
        in["flip"] = {{"mean", flipMean(flip.errorMap, interior)}};
        in.erase("ssim");
        in["relative_depth_jump"] = 0.1;
        e["interior"] = in;
    }
    // Issue 12: an LPV run's indirect light against the path tracer with the
    // light transport the LPV models (one bounce, two with lpv.bounce=on,
    // Lambert only), beside the error against the reference asked for. The
    // same reference when the settings already match, else a second one.
    if (kind == K::Indirect && lpvActive(run.scene(), run.settings())) {
        const std::vector<std::uint8_t> interior = depthInteriorMask(depth, 0.1);
        FloatImage matching, matchingSe;
        nlohmann::json mb = matchingBounceError(run, rs, test, mean, se, mask, interior, v, matching, matchingSe);
        const double mpeak = mb["peak"].get<double>();
        const nlohmann::json in = mb["interior"];
        e["matching_bounce"] = mb;
        // Stage attribution (docs/lpv.md): the same frame with the path-traced
        // probe volumes; probe vs matching = lookup error, propagated vs probe
        // = what the propagation adds.
        if (run.settings().lpv.source == LpvSettings::Source::Propagated) {
            FloatImage probe = lpv::renderProbeIndirect(run, v);
            nlohmann::json lookup = indirectErrorJson(probe, matching, matchingSe, mpeak, mask, interior);
            const nlohmann::json lin = lookup["interior"];
            // The propagated against the probe volume: both are estimates
            // without a per-pixel standard error, so no debiasing or interval.
            nlohmann::json prop = metricsJson(compareImages(test, probe, channels, mpeak, mask), true);
            prop["flip"] = flipJson(flipOf(test, probe, channels, mask), channels);
            prop["uncertainty"] = "none: the probe volume has no per-pixel standard error";
            prop.erase("ssim");
            prop["rmse_delta"] = mb["rmse"].get<double>() - lookup["rmse"].get<double>();
            prop["interior"] = {{"rmse", compareImages(test, probe, channels, mpeak, interior).rmse},
                                {"rmse_delta", in["rmse"].get<double>() - lin["rmse"].get<double>()}};
            e["stage"] = {{"lookup", lookup}, {"propagation", prop},
                          {"probe_directions", run.settings().lpv.probeDirections}};
        }
    }
    // Issue 22: with a full reference, also the LPV's indirect term against
    // the matching-bounce reference (the suite's skill column).
    if (kind == K::Full && lpvActive(run.scene(), run.settings()) && res.indirectDiffuse) {
        FloatImage matching, matchingSe;
        e["matching_bounce"] = matchingBounceError(run, rs, readTexture(res.indirectDiffuse), mean, se, mask,
                                                   depthInteriorMask(depth, 0.1), v, matching, matchingSe);
    }
    // Issue 26: with a full reference and reference.split=on, the error of
    // the direct and the indirect part of the frame, each against its part
    // of the path tracer: res.indirectDiffuse against the indirect reference
    // with the full reference's bounces (light reaching x1 over at least one
    // other surface, x1's Lambert lobe), res.direct against full − indirect
    // (emission + direct light; it also holds the reference's indirect
    // glossy part, which res.direct does not model). Standard errors add in
    // quadrature; rows with "bias" tell which part makes the frame too dark.
    if (kind == K::Full && run.settings().reference.split) {
        const std::vector<std::uint8_t> interior = depthInteriorMask(depth, 0.1);
        Settings is = referenceRunSettings(run.settings(), K::Indirect);
        is.reference = rs.reference;
        is.reference.kind = K::Indirect;
        FloatImage testIndirect = res.indirectDiffuse ? readTexture(res.indirectDiffuse) : readTexture(res.gbuffer.linearDepth);
        if (!res.indirectDiffuse) std::fill(testIndirect.data.begin(), testIndirect.data.end(), 0.0f);
        gl::Profiler iprof(false);
        Renderer iref(run.scene(), is, iprof);
        auto* iout = dynamic_cast<ReferenceOutput*>(iref.findPass("ref.path"));
        if (!iout) throw ConfigError("--reference: the indirect reference pass did not run (reference.split)");
        convergeAgainst(*iout, is, testIndirect, 3, mask);
        iref.render(v);
        FloatImage ind = readTexture(iout->mean()), indSe = readTexture(iout->standardError());
        FloatImage dir = mean, dirSe = se;
        for (std::size_t i = 0; i < dir.data.size(); ++i) {
            dir.data[i] = mean.data[i] - ind.data[i];
            dirSe.data[i] = std::sqrt(se.data[i] * se.data[i] + indSe.data[i] * indSe.data[i]);
        }
        nlohmann::json split;
        split["direct"] = indirectErrorJson(readTexture(res.direct), dir, dirSe, peak, mask, interior);
        split["indirect"] = indirectErrorJson(testIndirect, ind, indSe, peak, mask, interior);
        split["indirect"]["reference_spp"] = iout->samplesDone();
        split["note"] = "direct: res.direct vs full - indirect reference; indirect: res.indirectDiffuse vs the indirect "
                        "reference (same bounces); both relative to the full reference's peak";
        e["split"] = split;
    }
    // Issue 22: does the technique help? The same frame composed without its
    // contribution, against the same reference: gain = 1 − rmse / rmse_without
    // on the debiased RMSEs (> 0: better than switching it off). LPV off
    // leaves the ambient term as lpv=off has it; the near-field term off is
    // ao.nearfield=0.
    if (kind != K::Ao) {
        const std::vector<std::uint8_t> interior = depthInteriorMask(depth, 0.1);
        auto gainOf = [&](const Settings& without) {
            FloatImage w = renderCompared(run, without, camera, resolution, framesRendered, kind);
            nlohmann::json g;
            for (const std::vector<std::uint8_t>* part : {static_cast<const std::vector<std::uint8_t>*>(&mask), &interior}) {
                RmseUncertainty on = rmseUncertainty(test, mean, se, channels, *part);
                RmseUncertainty off = rmseUncertainty(w, mean, se, channels, *part);
                nlohmann::json x = {{"rmse", on.rmseDebiased}, {"rmse_without", off.rmseDebiased},
                                    {"rmse_without_ci95", {off.low, off.high}},
                                    {"gain", off.rmseDebiased > 0 ? 1.0 - on.rmseDebiased / off.rmseDebiased : 0.0}};
                if (part == &mask) g = x;
                else g["interior"] = x;
            }
            return g;
        };
        nlohmann::json gains;
        if (lpvActive(run.scene(), run.settings())) {
            Settings w = run.settings();
            w.lpv.mode = Toggle::Off;
            gains["lpv"] = gainOf(w);
        }
        if (run.settings().ao.nearfield > 0 && run.settings().ao.variant != AoSettings::Variant::Off) {
            Settings w = run.settings();
            w.ao.nearfield = 0.0f;
            gains["nearfield"] = gainOf(w);
        }
        if (!gains.empty()) e["gain"] = gains;
    }
    // Issue 6: the reflection error on the glossy pixels (roughness <=
    // ssr.roughness_cutoff, the ones SSR shades; also with ssr=off, as the
    // baseline), beside the whole-image one. SSIM is computed over the whole
    // image, so it is not repeated here.
    if (kind == K::Full) {
        FloatImage material = readTexture(res.gbuffer.material);
        std::vector<std::uint8_t> glossy(mask.size());
        const float cutoff = run.settings().ssr.roughnessCutoff;
        for (std::size_t i = 0; i < glossy.size(); ++i)
            glossy[i] = mask[i] && material.data[i * std::size_t(material.channels)] <= cutoff;
        nlohmann::json g = metricsJson(compareImages(test, mean, channels, peak, glossy), true);
        addUncertainty(g, test, mean, se, channels, glossy);
        g["flip"] = {{"mean", flipMean(flip.errorMap, glossy)}};
        g.erase("ssim");
        e["glossy"] = g;
    }
    nlohmann::json refInfo = trace.info(se, channels, mask);
    // The reference's noise as a fraction of the (debiased) error: above 0.2
    // the error says more about the reference than about the frame.
    {
        const double deb = e["rmse_debiased"].get<double>(), noise = refInfo["mean_stderr"].get<double>();
        const double ratio = deb > 0 ? noise / deb : (noise > 0 ? std::numeric_limits<double>::infinity() : 0.0);
        refInfo["noise_ratio"] = std::isfinite(ratio) ? nlohmann::json(ratio) : nlohmann::json("inf");
        if (ratio > 0.2)
            std::fprintf(stderr,
                         "rtgi: warning: the reference's noise (%.3g) is %.2f of the error (%.3g); the error mostly "
                         "measures the reference: set reference.target_noise=0.2 or raise reference.spp\n",
                         noise, ratio, deb);
    }
    e["reference"] = refInfo;

    if (writeImages) {
        std::filesystem::create_directories(outDir);
        writePng(outDir + "/error.heatmap.png", errorHeatmap(test, mean, channels, heatMax));
        writePng(outDir + "/error.flip.png", flipErrorColorMap(flip.errorMap), 1.0f, false);
        writePfm(outDir + "/reference.pfm", mean);
        writePfm(outDir + "/reference.stderr.pfm", se);
        // EXR (tev, Nuke, Blender, OpenImageIO read it): float, bit-exact, so
        // the heat map's two inputs can be re-compared elsewhere.
        writeExr(outDir + "/reference.exr", mean, channels, ExrPixel::Float);
        writeExr(outDir + "/reference.stderr.exr", se, channels, ExrPixel::Float);
        writeExr(outDir + "/compared.exr", test, channels, ExrPixel::Float);
        {  // The compared pixels, for `rtgi-bench --compare ... --mask compared.mask.png`.
            FloatImage mk = depth;
            for (std::size_t i = 0; i < mask.size(); ++i)
                for (int c = 0; c < 3; ++c) mk.data[i * 4 + std::size_t(c)] = mask[i] ? 1.0f : 0.0f;
            writePng(outDir + "/compared.mask.png", mk);
        }
        for (auto& d : ref.debugImages(*ref.findPass(passName)))
            if (d.tex && *d.tex) writePng(outDir + "/" + d.name + ".png", readTexture(*d.tex), d.scale, false);
        e["images"] = {"error.heatmap.png", "error.flip.png", "reference.exr", "reference.stderr.exr", "compared.exr", "compared.mask.png", "reference.pfm",
                       "reference.stderr.pfm"};
    }
    return e;
}

const char* toString(CompareOptions::Quantity q) {
    using Q = CompareOptions::Quantity;
    return q == Q::Ao ? "ao" : q == Q::Ldr ? "ldr" : q == Q::Radiance ? "radiance" : "auto";
}

CompareOptions::Quantity parseCompareQuantity(const std::string& s) {
    using Q = CompareOptions::Quantity;
    for (Q q : {Q::Auto, Q::Ao, Q::Ldr, Q::Radiance})
        if (s == toString(q)) return q;
    throw ConfigError("--quantity '" + s + "': expected auto|ao|ldr|radiance");
}

CompareResult compareImageData(const FloatImage& t, const FloatImage& r, const CompareData& d,
                               const CompareOptions& opts) {
    using Q = CompareOptions::Quantity;
    if (t.width != r.width || t.height != r.height)
        throw ConfigError(d.imageName + " is " + std::to_string(t.width) + "x" + std::to_string(t.height) + " but " +
                          d.referenceName + " is " + std::to_string(r.width) + "x" + std::to_string(r.height));
    Q q = opts.quantity;
    if (q == Q::Auto) q = d.referenceHdr ? Q::Radiance : Q::Ldr;
    const int channels = q == Q::Ao ? 1 : 3;
    const std::size_t n = std::size_t(r.width) * std::size_t(r.height);

    // Which pixels: a mask image, the reference's background value, or all.
    std::vector<std::uint8_t> mask;
    std::string maskDesc = "all pixels";
    if (d.mask) {
        const FloatImage& m = *d.mask;
        if (m.width != r.width || m.height != r.height)
            throw ConfigError("--mask " + d.maskName + ": " + std::to_string(m.width) + "x" +
                              std::to_string(m.height) + " does not match the images' size");
        mask.resize(n);
        for (std::size_t i = 0; i < n; ++i) mask[i] = m.data[i * std::size_t(m.channels)] > 0.5f ? 1 : 0;
        maskDesc = "mask " + d.maskName + " (channel 0 > 0.5)";
    } else if (opts.background) {
        mask.resize(n);
        const double bg = *opts.background;
        for (std::size_t i = 0; i < n; ++i) {
            bool isBg = true;
            for (int c = 0; c < channels; ++c)
                isBg &= std::abs(double(r.data[i * std::size_t(r.channels) + std::size_t(c)]) - bg) <= 1e-6;
            mask[i] = isBg ? 0 : 1;
        }
        std::ostringstream desc;
        desc << "pixels whose reference is not the background value " << bg;
        maskDesc = desc.str();
    }
    std::size_t compared = mask.empty() ? n : std::size_t(std::count(mask.begin(), mask.end(), 1));
    if (compared == 0) throw ConfigError("--compare: the mask leaves no pixel to compare (" + maskDesc + ")");

    double peak = q == Q::Radiance ? peakLuminance(r, mask) : 1.0;
    ErrorMetrics m = compareImages(t, r, channels, peak, mask);
    CompareResult out;
    nlohmann::json& j = out.json;
    j = metricsJson(m, q == Q::Radiance);
    j["image"] = d.imageName;
    j["reference"] = d.referenceName;
    j["version"] = versionString();
    j["compared"] = {{"quantity", toString(q)},
                     {"quantity_from", opts.quantity == Q::Auto ? "reference file type" : "--quantity"},
                     {"channels", channels == 1 ? "channel 0" : "rgb"},
                     {"pixels", maskDesc},
                     {"compared_pixels", compared},
                     {"total_pixels", n}};
    j["peak"] = peak;
    out.heatmapMax = errorQuantile(t, r, channels, 0.99);
    j["heatmap_max"] = out.heatmapMax;
    // FLIP: HDR-FLIP of radiance; LDR-FLIP of ldr images (PNG values are
    // sRGB-encoded display values: decoded to linear first, as FLIP's sRGB
    // input; PFM/EXR values are taken as linear) and of AO (grey).
    if (q == Q::Ldr) {
        auto linear = [](FloatImage img, bool encoded) {
            if (!encoded) return img;
            for (std::size_t i = 0; i < img.data.size(); ++i) {
                if (img.channels == 4 && i % 4 == 3) continue;
                const double c = std::clamp(double(img.data[i]), 0.0, 1.0);
                img.data[i] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
            }
            return img;
        };
        out.flip = ldrFlip(linear(t, !d.imageHdr), linear(r, !d.referenceHdr), {}, mask);
    } else {
        out.flip = flipOf(t, r, channels, mask);
    }
    j["flip"] = flipJson(out.flip, q == Q::Radiance ? 3 : 1);
    out.channels = channels;
    return out;
}

nlohmann::json compareImageFiles(const std::string& image, const std::string& reference, const CompareOptions& opts) {
    FloatImage t = readImageFile(image), r = readImageFile(reference);
    CompareData d;
    d.imageName = image;
    d.referenceName = reference;
    d.imageHdr = isHdrImageFile(image);
    d.referenceHdr = isHdrImageFile(reference);
    FloatImage m;
    if (!opts.maskFile.empty()) {
        m = readImageFile(opts.maskFile);
        d.mask = &m;
        d.maskName = opts.maskFile;
    }
    CompareResult c = compareImageData(t, r, d, opts);
    std::filesystem::create_directories(opts.outDir);
    writePng(opts.outDir + "/error.heatmap.png", errorHeatmap(t, r, c.channels, c.heatmapMax));
    writePng(opts.outDir + "/error.flip.png", flipErrorColorMap(c.flip.errorMap), 1.0f, false);
    writeFileAtomic(opts.outDir + "/compare.json", c.json.dump(2) + "\n");
    return c.json;
}

}  // namespace rtgi
