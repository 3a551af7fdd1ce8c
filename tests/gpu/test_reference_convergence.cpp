// Issue 21 on the GPU: the running moments of the reference against a CPU
// double computation on a fixed, fp32-stiff sample stream; a reference
// traced to a noise target stops there and resumes from its cache entry;
// two references with different seeds give errors within their intervals.
#include "gpu_fixture.h"

#include "bench/reference_compare.h"
#include "gl/program.h"
#include "render/gpu_types.h"
#include "render/reference/metrics.h"
#include "render/reference/reference_passes.h"
#include "scene/bvh.h"

#include <filesystem>

using namespace rtgi;
using namespace rtgi::test;

namespace {

Settings aoReference(int spp) {
    Settings s;
    s.reference.kind = ReferenceSettings::Kind::Ao;
    s.reference.spp = spp;
    s.reference.cacheDir = "off";
    s.lpv.mode = Toggle::Off;
    s.ao.radius = 1.0f;
    return s;
}

// A converging AO reference of the corner; the tested image is AO = 1
// everywhere (so the error is the reference's occlusion).
struct Converged {
    FloatImage mean, se;
    nlohmann::json info;
};
Converged convergeCorner(const Settings& st, glm::ivec2 size) {
    Scene s = floorAndWallScene();
    gl::Profiler prof(false);
    Renderer r(s, st, prof);
    auto* out = dynamic_cast<ReferenceOutput*>(r.findPass("ref.ao"));
    REQUIRE(out != nullptr);
    FloatImage ones;
    ones.width = size.x;
    ones.height = size.y;
    ones.channels = 4;
    ones.data.assign(std::size_t(size.x * size.y * 4), 1.0f);
    out->setConvergence([&](const FloatImage& mean, const FloatImage& se) {
        RmseUncertainty u = rmseUncertainty(ones, mean, se, 1);
        ConvergenceCheck c;
        c.noise = u.noiseRms;
        c.error = u.rmseDebiased;
        return c;
    });
    r.render(makeView(resolveCamera(s, st), size, nullptr, 0));
    glFinish();
    return {readTexture(out->mean()), readTexture(out->standardError()), out->convergenceInfo()};
}
}  // namespace

TEST_CASE("Reference moments: fp32 running mean and variance equal a CPU double computation on a stiff stream") {
    GpuFixture fx;
    const int edge = 16;
    gl::MemoryLedger ledger;
    gl::Texture accum(ledger, "t.accum", {GL_TEXTURE_2D, GL_RGBA32F, edge, edge});
    gl::Texture accumSq(ledger, "t.accum_sq", {GL_TEXTURE_2D, GL_RGBA32F, edge, edge});
    accum.clear();
    accumSq.clear();
    gl::ProgramCache programs;
    const gl::Program& prog = programs.compute("ref/moments_test.comp");
    glBindImageTexture(RTGI_REF_IMG_ACCUM, accum.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(RTGI_REF_IMG_ACCUM_SQ, accumSq.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    // Batches of uneven sizes, as a converging reference plans them.
    const std::vector<unsigned> batches = {1, 3, 4, 16, 7, 32, 64, 100, 173, 200};
    unsigned first = 0;
    for (unsigned b : batches) {
        glProgramUniform3ui(prog.id(), RTGI_REF_LOC_SAMPLES, first, b, unsigned(edge));
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);  // producer: the previous batch
        glUseProgram(prog.id());
        glDispatchCompute(2, 2, 1);
        first += b;
    }
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);  // producer: the last batch (read back)
    FloatImage meanN = readTexture(accum), m2 = readTexture(accumSq);
    double worstMean = 0, worstVar = 0, worstNaive = 0;
    for (unsigned y = 0; y < unsigned(edge); ++y)
        for (unsigned x = 0; x < unsigned(edge); ++x) {
            double s = 0, s2 = 0;
            float fs = 0, fs2 = 0;  // what Σx, Σx² in fp32 give
            for (unsigned k = 0; k < first; ++k) {
                const double v = 1000.0 + double((7919u * k + 31u * x + 17u * y) % 101u) / 128.0;
                s += v;
                fs += float(v);
                fs2 += float(v) * float(v);
            }
            const double mean = s / first;
            for (unsigned k = 0; k < first; ++k) {
                const double d = 1000.0 + double((7919u * k + 31u * x + 17u * y) % 101u) / 128.0 - mean;
                s2 += d * d;
            }
            const double var = s2 / (first - 1);
            const std::size_t i = (std::size_t(y) * edge + x) * 4;
            CHECK(meanN.data[i + 3] == float(first));
            worstMean = std::max(worstMean, std::abs(meanN.data[i] - mean));
            worstVar = std::max(worstVar, std::abs(m2.data[i] / (first - 1) - var) / var);
            const double naiveVar = (double(fs2) - double(fs) * double(fs) / first) / (first - 1);
            worstNaive = std::max(worstNaive, std::abs(naiveVar - var) / var);
        }
    MESSAGE("largest mean error " << worstMean << ", variance relative error " << worstVar
                                  << " (fp32 sums of x and x²: " << worstNaive << ")");
    CHECK(worstMean < 1e-3);   // 16 ulp of 1000: the rounding of ~600 running-mean updates
    CHECK(worstVar < 1e-3);
    CHECK(worstNaive > 0.5);   // the stream is stiff: the old accumulation could not pass
}

TEST_CASE("Converging reference: stops at the absolute target, records it, and resumes its cache entry") {
    GpuFixture fx;
    const glm::ivec2 size(24, 24);
    std::filesystem::path dir = std::filesystem::temp_directory_path() / "rtgi-test-ref-converge";
    std::filesystem::remove_all(dir);
    Settings st = aoReference(16);
    st.reference.cacheDir = dir.string();
    st.reference.targetStderr = 0.02;
    st.reference.timeBudget = 0;
    Converged a = convergeCorner(st, size);
    REQUIRE(a.info.is_object());
    CHECK(a.info["stop"] == "target");
    CHECK(a.info["reached"] == true);
    const double noiseA = a.info["noise"].get<double>();
    CHECK(noiseA <= 0.02);
    CHECK(noiseA == doctest::Approx(rmsStandardError(a.se, 1, {})).epsilon(1e-6));
    const auto& checks = a.info["checks"];
    REQUIRE(checks.size() >= 2);
    CHECK(checks[checks.size() - 2]["noise"].get<double>() > 0.02);  // it did not stop late
    const int sppA = a.info["spp"].get<int>();
    CHECK(a.info["resumed_from_spp"] == 0);

    // A tighter target resumes the entry: its samples are kept.
    st.reference.targetStderr = 0.01;
    Converged b = convergeCorner(st, size);
    CHECK(b.info["resumed_from_spp"] == sppA);
    const int sppB = b.info["spp"].get<int>();
    CHECK(sppB > sppA);
    CHECK(b.info["noise"].get<double>() <= 0.01);

    // The same samples traced at once (fixed spp, no cache) give the same
    // mean: the sequence is a pure function of pixel, sample index and seed,
    // only the fp32 merge order differs.
    Settings fixed = aoReference(sppB);
    gl::Profiler prof(false);
    Scene s = floorAndWallScene();
    auto r = renderFrames(s, fixed, size, prof);
    auto* out = dynamic_cast<ReferenceOutput*>(r->findPass("ref.ao"));
    REQUIRE(out != nullptr);
    FloatImage once = readTexture(out->mean()), onceSe = readTexture(out->standardError());
    double worst = 0, worstSe = 0;
    for (std::size_t i = 0; i < once.data.size(); i += 4) {
        worst = std::max(worst, double(std::abs(once.data[i] - b.mean.data[i])));
        worstSe = std::max(worstSe, double(std::abs(onceSe.data[i] - b.se.data[i])));
    }
    CHECK(worst < 1e-5);
    CHECK(worstSe < 1e-4);  // M2 rebuilt from the stored standard error (fp32)

    // A looser target than the entry holds: used as it is.
    st.reference.targetStderr = 0.05;
    Converged c = convergeCorner(st, size);
    CHECK(c.info["spp"] == sppB);
    CHECK(c.info["checks"].size() == 1);
    std::filesystem::remove_all(dir);
}

TEST_CASE("Errors with their uncertainty: two references with different seeds give errors within their intervals") {
    GpuFixture fx;
    gl::Profiler prof(false);
    const glm::ivec2 size(40, 30);
    Scene s = loadBuiltin("cornell");
    Settings st;
    st.reference.cacheDir = "off";
    st.reference.spp = 48;
    st.ao.variant = AoSettings::Variant::Off;
    st.lpv.mode = Toggle::Off;  // compare the whole image (reference=full)
    auto r = renderFrames(s, st, size, prof, 2);
    const Camera cam = resolveCamera(s, st);
    nlohmann::json e1 = compareWithReference(*r, cam, size, "", false, ReferenceSettings::Kind::Full);
    st.reference.seed = 2;  // the seed changes the reference only: the same frame
    auto r2 = renderFrames(s, st, size, prof, 2);
    nlohmann::json e2 = compareWithReference(*r2, cam, size, "", false, ReferenceSettings::Kind::Full);
    CHECK(e1["rmse"] != e2["rmse"]);
    const double d1 = e1["rmse_debiased"], d2 = e2["rmse_debiased"];
    const double lo1 = e1["rmse_ci95"][0], hi1 = e1["rmse_ci95"][1], lo2 = e2["rmse_ci95"][0], hi2 = e2["rmse_ci95"][1];
    MESSAGE("seed 1: " << d1 << " [" << lo1 << ", " << hi1 << "], seed 2: " << d2 << " [" << lo2 << ", " << hi2
                       << "], plain RMSE " << e1["rmse"].get<double>() << " / " << e2["rmse"].get<double>());
    CHECK(lo1 < d1);
    CHECK(d1 < hi1);
    // Both estimate the same RMSE: the intervals overlap, and the difference
    // is within the two-sample 95 % bound (half-widths are 1.96 sd).
    CHECK(std::max(lo1, lo2) <= std::min(hi1, hi2));
    const double sd1 = (hi1 - lo1) / (2 * 1.96), sd2 = (hi2 - lo2) / (2 * 1.96);
    CHECK(std::abs(d1 - d2) <= 1.96 * std::sqrt(sd1 * sd1 + sd2 * sd2) + 1e-12);
    // The plain RMSEs are inflated by the noise; the debiased ones are not.
    CHECK(e1["rmse"].get<double>() >= d1);
    CHECK(e1["interior"].contains("rmse_ci95"));
    // FLIP beside it (HDR-FLIP of the image, the interior's mean from the same map).
    CHECK(e1["flip"]["kind"] == "hdr");
    CHECK(e1["flip"]["mean"].get<double>() > 0.0);
    CHECK(e1["flip"]["mean"].get<double>() < 1.0);
    CHECK(e1["interior"]["flip"]["mean"].get<double>() > 0.0);
}

TEST_CASE("Caustic paths: regularized stays within its documented bias of a long unregularized run, off does not") {
    // A glossy metal floor (roughness 0.15) and a diffuse 1 m box under a
    // low sun: the sun reflected by the floor lights the box's sunlit face a
    // second time from below (camera -> box -> floor -> sun, a caustic).
    GpuFixture fx;
    const glm::ivec2 size(32, 24);
    Scene s = floorScene(5.0f, glm::vec3(0.9f), true, {-0.8f, 0.6f, 0.3f}, 3.0f);
    s.materials[0].metallic = 1.0f;
    s.materials[0].roughness = 0.15f;
    Material box;
    box.baseColor = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
    box.roughness = 1.0f;
    s.materials.push_back(box);
    const float h = 0.5f;
    addQuad(s, {-h, 0, h}, {-h, 0, -h}, {-h, 1, -h}, {-h, 1, h}, 1);  // -x: towards the sun and its reflection
    addQuad(s, {h, 0, -h}, {h, 0, h}, {h, 1, h}, {h, 1, -h}, 1);
    addQuad(s, {-h, 0, -h}, {h, 0, -h}, {h, 1, -h}, {-h, 1, -h}, 1);
    addQuad(s, {h, 0, h}, {-h, 0, h}, {-h, 1, h}, {h, 1, h}, 1);
    addQuad(s, {-h, 1, -h}, {h, 1, -h}, {h, 1, h}, {-h, 1, h}, 1);
    s.cameras[0].position = {-3.0f, 1.2f, 1.5f};
    s.cameras[0].target = {0.0f, 0.5f, 0.0f};
    auto traced = [&](ReferenceSettings::Caustics c, int spp) {
        Settings st;
        st.reference.kind = ReferenceSettings::Kind::Full;
        st.reference.spp = spp;
        st.reference.cacheDir = "off";
        st.reference.caustics = c;
        st.lpv.mode = Toggle::Off;
        gl::Profiler prof(false);
        auto r = renderFrames(s, st, size, prof);
        auto* out = dynamic_cast<ReferenceOutput*>(r->findPass("ref.path"));
        REQUIRE(out != nullptr);
        // Image mean over rgb and its standard error (pixels independent).
        FloatImage m = readTexture(out->mean()), se = readTexture(out->standardError());
        double sum = 0, var = 0;
        const double n = double(size.x * size.y * 3);
        for (std::size_t i = 0; i < m.data.size(); i += 4)
            for (int ch = 0; ch < 3; ++ch) {
                sum += m.data[i + std::size_t(ch)];
                var += double(se.data[i + std::size_t(ch)]) * se.data[i + std::size_t(ch)];
            }
        return std::pair<double, double>(sum / n, std::sqrt(var) / n);
    };
    auto [on, onSe] = traced(ReferenceSettings::Caustics::On, 4096);
    auto [reg, regSe] = traced(ReferenceSettings::Caustics::Regularized, 512);
    auto [off, offSe] = traced(ReferenceSettings::Caustics::Off, 512);
    MESSAGE("image mean: on " << on << " ± " << onSe << ", regularized " << reg << " ± " << regSe << ", off " << off
                              << " ± " << offSe);
    // docs/reference.md, "Caustic paths": the bias of the regularized image
    // mean on this scene is within 10 % of the caustic light (on − off);
    // measured −6 % ± 3 % (llvmpipe, these settings).
    const double caustic = on - off;
    const double sdReg = std::sqrt(onSe * onSe + regSe * regSe), sdOff = std::sqrt(onSe * onSe + offSe * offSe);
    CHECK(caustic > 10.0 * sdOff);  // the scene has caustics: the test can tell them apart
    CHECK(std::abs(reg - on) <= 0.1 * caustic + 3.0 * sdReg);
}
