// Temporal filters over 10 000 static frames and alternating camera cuts
// (issue 9), with the real shaders on tiny images/volumes: the shared
// screen-space filter (AO: R16F and, for the precision study, R8; SSR:
// RGBA16F) and the LPV volume blend (fp16, fp32).
// Oracle: the same recurrence in CPU double precision. Bound: a history
// stored with quantum q and updated by a fraction a stalls once a·|x - h|
// falls below one rounding step, so |h - x| <= q/a (truncating stores, as
// Mesa's) or q/(2a) (round to nearest); it never drifts further.
#include "gpu_fixture.h"

#include "render/filter.h"
#include "render/lpv/lpv_math.h"
#include "render/lpv/lpv_volumes.h"

#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const int kFrames = 10000;
// A flickering but statistically static input: 8 noise variants, mean 0.5 (as the AO estimate of one pixel).
const float kVariants[8] = {0.2f, 0.8f, 0.4f, 0.6f, 0.1f, 0.9f, 0.35f, 0.65f};

struct Drift {
    double maxDeviation = 0;  // max |GPU - CPU double recurrence| over the sampled frames
    double driftLate = 0;     // |h(10000) - h(1000)| (same phase of the 8-periodic input)
    bool finite = true;
};

// Runs the shared temporal filter in `fmt` for kFrames frames on an 8x8 image.
Drift runFilter(const FilterFormat& fmt, bool alternateCuts) {
    gl::ProgramCache programs;
    gl::MemoryLedger ledger;
    const int w = 8, h = 8;
    gl::Texture depth = floatTexture(ledger, "t.depth", GL_R32F, w, h, 1, std::vector<float>(w * h, 3.0f));
    gl::Texture vel = floatTexture(ledger, "t.vel", GL_RG16F, w, h, 2, std::vector<float>(w * h * 2, 0.0f));
    std::vector<gl::Texture> cur;
    for (float v : kVariants) cur.push_back(floatTexture(ledger, "t.cur", fmt.internal, w, h, 1, std::vector<float>(w * h, v)));
    // What the filter reads is the stored input (8-bit or half), so the oracle starts from it.
    double stored[8];
    for (int i = 0; i < 8; ++i) stored[i] = readTexture(cur[std::size_t(i)]).at(0, 0, 0);
    TemporalFilter tf;
    double cpu = 0;
    Drift d;
    double at1000 = 0;
    for (int f = 0; f < kFrames; ++f) {
        bool cut = f == 0 || (alternateCuts && f % 2 == 0);
        const gl::Texture& out = tf.run(programs, ledger, "t.temporal", fmt, cur[std::size_t(f % 8)], depth, vel, cut);
        cpu = cut ? stored[f % 8] : 0.95 * cpu + 0.05 * stored[f % 8];  // listing 11, alpha 0.05
        if (f == 999 || f == kFrames - 1 || f < 4 || f % 1000 == 7) {
            float g = readTexture(out).at(5, 3, 0);
            d.finite = d.finite && std::isfinite(g);
            d.maxDeviation = std::max(d.maxDeviation, std::abs(double(g) - cpu));
            if (f == 999) at1000 = g;
            if (f == kFrames - 1) d.driftLate = std::abs(double(g) - at1000);
            if (cut) CHECK(g == doctest::Approx(stored[f % 8]).epsilon(1e-6));  // a cut takes the current value
        }
    }
    return d;
}

}  // namespace

TEST_CASE("stress: shared temporal filter over 10000 static frames: no drift, bias within the storage bound") {
    GpuFixture gpu;
    // R16F near 0.5: quantum 2^-11 (truncating: one step 2^-11 below); a = 0.05 -> bound 2^-11/0.05 = 0.0098.
    Drift h = runFilter({GL_R16F, "r16f"}, false);
    // R8: quantum 1/255 -> bound (1/255)/0.05 = 0.078.
    Drift b = runFilter({GL_R8, "r8"}, false);
    MESSAGE("temporal AO, 10000 frames: R16F max |GPU - double| = " << h.maxDeviation << ", drift 1000->10000 = "
                                                                    << h.driftLate << "; R8 max |GPU - double| = "
                                                                    << b.maxDeviation << ", drift = " << b.driftLate);
    CHECK(h.finite);
    CHECK(b.finite);
    CHECK(h.maxDeviation <= std::ldexp(1.0, -11) / 0.05);
    CHECK(b.maxDeviation <= (1.0 / 255.0) / 0.05);
    // The 8-periodic input reaches a periodic steady state: frame 10000 equals frame 1000 up to one
    // storage step (no slow drift).
    CHECK(h.driftLate <= std::ldexp(1.0, -11));
    CHECK(b.driftLate <= 1.0 / 255.0);
}

TEST_CASE("stress: shared temporal filter with a camera cut every other frame follows the CPU recurrence") {
    GpuFixture gpu;
    Drift h = runFilter({GL_R16F, "r16f"}, true);
    CHECK(h.finite);
    // One blend step after each cut: error of one half rounding of values <= 1 (2^-10 when truncating).
    CHECK(h.maxDeviation <= std::ldexp(1.0, -10));
}

TEST_CASE("stress: SSR's temporal filter (shared filter, RGBA16F) over 10000 frames, static and with cuts") {
    GpuFixture gpu;
    // ssr.temporal runs the shared filter on the RGBA16F premultiplied reflection.
    for (bool cuts : {false, true}) {
        Drift d = runFilter({GL_RGBA16F, "rgba16f"}, cuts);
        MESSAGE("RGBA16F temporal, 10000 frames" << std::string(cuts ? " with cuts" : "") << ": max |GPU - double| = "
                                                 << d.maxDeviation << ", drift 1000->10000 = " << d.driftLate);
        CHECK(d.finite);
        // Values in [0.1, 0.9]: half quantum <= 2^-11, a = 0.05 -> 2^-11/0.05 = 0.0098.
        CHECK(d.maxDeviation <= std::ldexp(1.0, -11) / 0.05);
        if (!cuts) CHECK(d.driftLate <= std::ldexp(1.0, -11));
    }
}

TEST_CASE("stress: LPV temporal blend (t = 0.99) over 10000 static frames, fp16 and fp32") {
    GpuFixture gpu;
    for (GLenum format : {GL_RGBA16F, GL_RGBA32F}) {
        gl::ProgramCache programs;
        gl::MemoryLedger ledger;
        const glm::ivec3 grid(2, 2, 2);
        LpvSettings ls;
        ls.temporal = 0.99f;
        ls.format = format == GL_RGBA32F ? LpvSettings::Format::Rgba32f : LpvSettings::Format::Rgba16f;
        lpv::Volumes v;
        v.ensureLight(ledger, grid, format);
        v.ensureHistory(ledger);
        lpv::UniformInputs in;
        in.placement.grid = grid;
        in.historyValid = true;
        gpu::LpvUniforms valid = lpv::makeUniforms(ls, in);
        in.historyValid = false;
        gpu::LpvUniforms reset = lpv::makeUniforms(ls, in);
        gl::Buffer uboValid(ledger, "t.lpv.valid", sizeof valid, &valid);
        gl::Buffer uboReset(ledger, "t.lpv.reset", sizeof reset, &reset);
        // Flickering static light: coefficient 0 of every channel alternates 100 * (1 +- 0.1) (mean 100).
        auto fill = [&](float c0) {
            std::vector<float> px;
            for (int i = 0; i < 8; ++i) px.insert(px.end(), {c0, -0.3f * c0, 0.2f * c0, 0.1f * c0});
            for (auto& t : v.accum) glTextureSubImage3D(t.id(), 0, 0, 0, 0, 2, 2, 2, GL_RGBA, GL_FLOAT, px.data());
        };
        double cpu = 0, maxRel = 0, at1000 = 0, late = 0;
        bool finite = true;
        for (int f = 0; f < kFrames; ++f) {
            float x = f % 2 ? 110.0f : 90.0f;
            fill(x);
            int target = f % 2;
            lpv::temporalBlend(programs, f == 0 ? uboReset : uboValid, v, target);
            cpu = f == 0 ? x : 0.01 * x + 0.99 * cpu;  // mix(accum, history, 0.99)
            if (f == 999 || f == kFrames - 1 || f < 4 || f % 1000 == 7 || f % 1000 == 8) {
                glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);  // producer: lpv.temporal's image stores
                FloatImage img = readTexture(v.history[std::size_t(target)][1], 1);
                float g = img.at(1, 0, 0);
                finite = finite && std::isfinite(g) && std::isfinite(img.at(1, 0, 1));
                maxRel = std::max(maxRel, std::abs(double(g) - cpu) / cpu);
                if (f == 999) at1000 = g;
                if (f == kFrames - 1) late = std::abs(double(g) - at1000) / cpu;
            }
        }
        MESSAGE("LPV temporal t=0.99, 10000 frames, " << std::string(format == GL_RGBA32F ? "fp32" : "fp16")
                                                     << ": max relative |GPU - double| = " << maxRel
                                                     << ", drift 1000->10000 = " << late);
        CHECK(finite);
        // Bound q/a relative: fp16 quantum 2^-10 relative (truncating) over a = 0.01 -> 0.098;
        // fp32 2^-23 / 0.01 -> 1.2e-5 (plus the alternation's own ripple, identical in the oracle).
        double bound = format == GL_RGBA32F ? std::ldexp(1.0, -23) / 0.01 : std::ldexp(1.0, -10) / 0.01;
        CHECK(maxRel <= bound);
        CHECK(late <= bound);
    }
}
