#include "render/reference/reference_runner.h"

#include "gl/image_io.h"
#include "gl/output_files.h"
#include "render/reference/metrics.h"
#include "render/reference/reference_cache.h"
#include "render/reference/reference_passes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace rtgi {

ReferenceSettings::Kind referenceKindFor(const Settings& s, const FrameResources& res) {
    using K = ReferenceSettings::Kind;
    if (s.reference.kind != K::Off) return s.reference.kind;
    if (s.ao.variant != AoSettings::Variant::Off && res.ao) return K::Ao;
    if (res.indirectDiffuse) return K::Indirect;
    return K::Full;
}

namespace {

nlohmann::json metricsJson(const ErrorMetrics& m, bool radiance) {
    auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json("inf"); };
    nlohmann::json j = {{"rmse", m.rmse}, {"mae", m.mae}, {"bias", m.bias}, {"psnr", finite(m.psnr)},
                        {"ssim", m.ssim}, {"pixels", m.pixels}, {"nan_pixels", m.nanPixels},
                        {"inf_pixels", m.infPixels}};
    if (radiance) j["rel_rmse"] = m.relRmse;
    return j;
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
                                    const std::string& outDir, bool writeImages) {
    using K = ReferenceSettings::Kind;
    FrameResources& res = run.resources();
    K kind = referenceKindFor(run.settings(), res);
    const gl::Texture& tested = kind == K::Ao ? res.ao : kind == K::Indirect ? res.indirectDiffuse : res.hdr;
    if (!tested)
        throw ConfigError(std::string("--reference: this run produced no ") +
                          (kind == K::Ao ? "AO (set ao=VARIANT)" : kind == K::Indirect ? "indirect light" : "image") +
                          " to compare with the reference");
    FloatImage test = readTexture(tested);
    FloatImage depth = readTexture(res.gbuffer.linearDepth);

    // The reference renderer: the same scene, camera and lights, with the
    // real-time techniques off (they would only cost time).
    Settings rs = run.settings();
    rs.reference.kind = kind;
    rs.ao.variant = AoSettings::Variant::Off;
    rs.lpv.mode = Toggle::Off;
    rs.ssr.tracer = SsrSettings::Tracer::Off;
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
    e["compared"] = kind == K::Ao ? "ao" : kind == K::Indirect ? "indirectDiffuse" : "hdr";
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
        in.erase("ssim");
        in["relative_depth_jump"] = 0.1;
        e["interior"] = in;
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
    refInfo["from_cache"] = out->fromCache();
    refInfo["cache_key"] = out->cacheKey();
    refInfo["cache_dir"] = rs.reference.cacheDir;
    e["reference"] = refInfo;

    if (writeImages) {
        std::filesystem::create_directories(outDir);
        writePng(outDir + "/error.heatmap.png", errorHeatmap(test, mean, channels, heatMax));
        writePfm(outDir + "/reference.pfm", mean);
        writePfm(outDir + "/reference.stderr.pfm", se);
        for (auto& d : ref.findPass(passName)->debugImages())
            if (d.tex && *d.tex) writePng(outDir + "/" + d.name + ".png", readTexture(*d.tex), d.scale, false);
        e["images"] = {"error.heatmap.png", "reference.pfm", "reference.stderr.pfm"};
    }
    return e;
}

nlohmann::json compareImageFiles(const std::string& image, const std::string& reference, const std::string& outDir) {
    auto load = [](const std::string& p) {
        std::string ext = std::filesystem::path(p).extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        return ext == ".pfm" ? readPfm(p) : readImage(p);
    };
    bool hdr = std::filesystem::path(reference).extension() == ".pfm" || std::filesystem::path(reference).extension() == ".PFM";
    FloatImage t = load(image), r = load(reference);
    double peak = hdr ? peakLuminance(r, {}) : 1.0;
    ErrorMetrics m = compareImages(t, r, 3, peak);
    nlohmann::json j = metricsJson(m, hdr);
    j["image"] = image;
    j["reference"] = reference;
    j["peak"] = peak;
    double heatMax = errorQuantile(t, r, 3, 0.99);
    j["heatmap_max"] = heatMax;
    std::filesystem::create_directories(outDir);
    writePng(outDir + "/error.heatmap.png", errorHeatmap(t, r, 3, heatMax));
    writeFileAtomic(outDir + "/compare.json", j.dump(2) + "\n");
    return j;
}

}  // namespace rtgi
