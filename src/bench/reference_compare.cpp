#include "bench/reference_compare.h"

#include "app/cli.h"

#include "gl/image_files.h"
#include "gl/image_io.h"
#include "gl/output_files.h"
#include "render/reference/metrics.h"
#include "render/reference/reference_cache.h"
#include "render/lpv/lpv_passes.h"
#include "render/lpv/lpv_probe.h"
#include "render/reference/reference_passes.h"

#include <algorithm>
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

double peakLuminance(const FloatImage& ref, const std::vector<std::uint8_t>& mask) {
    double peak = 0;
    for (std::size_t i = 0; i < std::size_t(ref.width) * std::size_t(ref.height); ++i)
        if (mask.empty() || mask[i]) {
            double l = pixelLuminance(ref, i, 3);
            if (std::isfinite(l)) peak = std::max(peak, l);  // NaN/Inf pixels are counted, not used
        }
    return std::max(peak, 1e-6);
}

}  // namespace

nlohmann::json compareWithReference(Renderer& run, const Camera& camera, glm::ivec2 resolution,
                                    const std::string& outDir, bool writeImages, ReferenceSettings::Kind requested) {
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

    // The reference renderer: the same scene, camera and lights, with the
    // real-time techniques off (they would only cost time).
    Settings rs = referenceRunSettings(run.settings(), kind);
    gl::Profiler profiler(false);
    Renderer ref(run.scene(), rs, profiler);
    View v = makeView(camera, resolution, nullptr, 0);
    ref.render(v);
    const char* passName = kind == K::Ao ? "ref.ao" : "ref.path";
    auto* out = dynamic_cast<ReferenceOutput*>(ref.findPass(passName));
    if (!out) throw ConfigError("--reference: the reference pass did not run");
    FloatImage mean = readTexture(out->mean()), se = readTexture(out->standardError());

    std::vector<std::uint8_t> mask(std::size_t(depth.width) * std::size_t(depth.height));
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = depth.data[i * 4] > 0.0f ? 1 : 0;
    int channels = kind == K::Ao ? 1 : 3;
    double peak = kind == K::Ao ? 1.0 : peakLuminance(mean, mask);
    ErrorMetrics m = compareImages(test, mean, channels, peak, mask);
    nlohmann::json e = metricsJson(m, kind != K::Ao);
    addSkill(e, test, mean, channels, peak, mask);
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
        in.erase("ssim");
        in["relative_depth_jump"] = 0.1;
        e["interior"] = in;
    }
    // Issue 12: an LPV run's indirect light against the path tracer with the
    // light transport the LPV models (one bounce, two with lpv.bounce=on,
    // Lambert only), beside the error against the reference asked for. The
    // same reference when the settings already match, else a second one.
    if (kind == K::Indirect && lpvActive(run.scene(), run.settings())) {
        Settings ms = rs;
        ms.reference.bounces = run.settings().lpv.bounce ? 2 : 1;
        ms.reference.specular = false;
        bool same = ms.reference.bounces == rs.reference.bounces && ms.reference.specular == rs.reference.specular;
        FloatImage matching = mean;
        if (!same) {
            Renderer mref(run.scene(), ms, profiler);
            mref.render(v);
            auto* mout = dynamic_cast<ReferenceOutput*>(mref.findPass(passName));
            if (!mout) throw ConfigError("--reference: the matching-bounce reference pass did not run");
            matching = readTexture(mout->mean());
        }
        double mpeak = peakLuminance(matching, mask);
        nlohmann::json mb = metricsJson(compareImages(test, matching, channels, mpeak, mask), true);
        addSkill(mb, test, matching, channels, mpeak, mask);
        mb.erase("ssim");
        const std::vector<std::uint8_t> interior = depthInteriorMask(depth, 0.1);
        nlohmann::json in = metricsJson(compareImages(test, matching, channels, mpeak, interior), true);
        addSkill(in, test, matching, channels, mpeak, interior);
        in.erase("ssim");
        mb["interior"] = in;
        mb["bounces"] = ms.reference.bounces;
        mb["specular"] = false;
        mb["same_as_reference"] = same;
        e["matching_bounce"] = mb;
        // Stage attribution (docs/lpv.md): the same frame with the path-traced
        // probe volumes; probe vs matching = lookup error, propagated vs probe
        // = what the propagation adds.
        if (run.settings().lpv.source == LpvSettings::Source::Propagated) {
            FloatImage probe = lpv::renderProbeIndirect(run, v);
            nlohmann::json lookup = metricsJson(compareImages(probe, matching, channels, mpeak, mask), true);
            addSkill(lookup, probe, matching, channels, mpeak, mask);
            lookup.erase("ssim");
            nlohmann::json lin = metricsJson(compareImages(probe, matching, channels, mpeak, interior), true);
            addSkill(lin, probe, matching, channels, mpeak, interior);
            lin.erase("ssim");
            lookup["interior"] = lin;
            nlohmann::json prop = metricsJson(compareImages(test, probe, channels, mpeak, mask), true);
            prop.erase("ssim");
            prop["rmse_delta"] = mb["rmse"].get<double>() - lookup["rmse"].get<double>();
            prop["interior"] = {{"rmse", compareImages(test, probe, channels, mpeak, interior).rmse},
                                {"rmse_delta", in["rmse"].get<double>() - lin["rmse"].get<double>()}};
            e["stage"] = {{"lookup", lookup}, {"propagation", prop},
                          {"probe_directions", run.settings().lpv.probeDirections}};
        }
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
        g.erase("ssim");
        e["glossy"] = g;
    }
    nlohmann::json refInfo = referenceSettingsJson(referenceConstants(rs, run.scene().bounds()));
    for (auto& [k, val] : ref.findPass(passName)->stats()) refInfo[k] = val;
    refInfo["spp"] = rs.reference.spp;
    // The reference's own noise on the RMSE's scale: RMS of the per-pixel
    // standard error over the compared pixels and channels (docs/reference.md).
    refInfo["mean_stderr"] = rmsStandardError(se, channels, mask);
    refInfo["from_cache"] = out->fromCache();
    refInfo["cache_key"] = out->cacheKey();
    refInfo["cache_dir"] = rs.reference.cacheDir;
    e["reference"] = refInfo;

    if (writeImages) {
        std::filesystem::create_directories(outDir);
        writePng(outDir + "/error.heatmap.png", errorHeatmap(test, mean, channels, heatMax));
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
        e["images"] = {"error.heatmap.png", "reference.exr", "reference.stderr.exr", "compared.exr", "compared.mask.png", "reference.pfm",
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

nlohmann::json compareImageFiles(const std::string& image, const std::string& reference, const CompareOptions& opts) {
    using Q = CompareOptions::Quantity;
    FloatImage t = readImageFile(image), r = readImageFile(reference);
    if (t.width != r.width || t.height != r.height)
        throw ConfigError(image + " is " + std::to_string(t.width) + "x" + std::to_string(t.height) + " but " +
                          reference + " is " + std::to_string(r.width) + "x" + std::to_string(r.height));
    Q q = opts.quantity;
    if (q == Q::Auto) q = isHdrImageFile(reference) ? Q::Radiance : Q::Ldr;
    const int channels = q == Q::Ao ? 1 : 3;
    const std::size_t n = std::size_t(r.width) * std::size_t(r.height);

    // Which pixels: a mask file, the reference's background value, or all.
    std::vector<std::uint8_t> mask;
    std::string maskDesc = "all pixels";
    if (!opts.maskFile.empty()) {
        FloatImage m = readImageFile(opts.maskFile);
        if (m.width != r.width || m.height != r.height)
            throw ConfigError("--mask " + opts.maskFile + ": " + std::to_string(m.width) + "x" +
                              std::to_string(m.height) + " does not match the images' size");
        mask.resize(n);
        for (std::size_t i = 0; i < n; ++i) mask[i] = m.data[i * std::size_t(m.channels)] > 0.5f ? 1 : 0;
        maskDesc = "mask " + opts.maskFile + " (channel 0 > 0.5)";
    } else if (opts.background) {
        mask.resize(n);
        const double bg = *opts.background;
        for (std::size_t i = 0; i < n; ++i) {
            bool isBg = true;
            for (int c = 0; c < channels; ++c)
                isBg &= std::abs(double(r.data[i * std::size_t(r.channels) + std::size_t(c)]) - bg) <= 1e-6;
            mask[i] = isBg ? 0 : 1;
        }
        std::ostringstream d;
        d << "pixels whose reference is not the background value " << bg;
        maskDesc = d.str();
    }
    std::size_t compared = mask.empty() ? n : std::size_t(std::count(mask.begin(), mask.end(), 1));
    if (compared == 0) throw ConfigError("--compare: the mask leaves no pixel to compare (" + maskDesc + ")");

    double peak = q == Q::Radiance ? peakLuminance(r, mask) : 1.0;
    ErrorMetrics m = compareImages(t, r, channels, peak, mask);
    nlohmann::json j = metricsJson(m, q == Q::Radiance);
    j["image"] = image;
    j["reference"] = reference;
    j["version"] = versionString();
    j["compared"] = {{"quantity", toString(q)},
                     {"quantity_from", opts.quantity == Q::Auto ? "reference file type" : "--quantity"},
                     {"channels", channels == 1 ? "channel 0" : "rgb"},
                     {"pixels", maskDesc},
                     {"compared_pixels", compared},
                     {"total_pixels", n}};
    j["peak"] = peak;
    double heatMax = errorQuantile(t, r, channels, 0.99);
    j["heatmap_max"] = heatMax;
    std::filesystem::create_directories(opts.outDir);
    writePng(opts.outDir + "/error.heatmap.png", errorHeatmap(t, r, channels, heatMax));
    writeFileAtomic(opts.outDir + "/compare.json", j.dump(2) + "\n");
    return j;
}

}  // namespace rtgi
