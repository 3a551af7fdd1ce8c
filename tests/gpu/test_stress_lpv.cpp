// Stress cases of the LPV (issue 9): grids 1^3 .. 32^3 and non-cubic, cell
// sizes 1e-3 .. 1e3, 64 iterations, fully blocking geometry, and the stiff
// case of a very bright small light beside a very dim large one in fp16 vs
// fp32. Oracles: invariants (finiteness, non-negative radiance, light moves
// one cell per iteration, a blocking potential of 1 stops all transport,
// cells the bright light cannot reach compute bit-identically without it)
// and the fp32 run of the same configuration.
#include "gpu_fixture.h"

#include "render/lpv/lpv_math.h"
#include "render/lpv/lpv_volumes.h"

#include <algorithm>
#include <cmath>
#include <random>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const double kPi = 3.14159265358979323846;
const double kY00 = 0.5 / std::sqrt(kPi);
const double kC0 = std::sqrt(kPi) / 2.0, kC1 = std::sqrt(kPi / 3.0);

// Flux Phi leaving a surface with normal n as the SH the injection writes: Phi/pi * cosLobe(n) (docs/lpv.md).
glm::vec4 lobe(double phi, glm::dvec3 n) {
    return glm::vec4(phi / kPi * glm::dvec4(kC0, -kC1 * n.y, kC1 * n.z, -kC1 * n.x));
}

// Every output of every pass: no NaN/Inf, no negative where impossible.
void checkAll(const Renderer& r) {
    CHECK_FALSE(r.finiteCounts().empty());
    for (auto& c : r.finiteCounts()) {
        INFO(c.pass << " " << c.resource << " nan=" << c.nan << " inf=" << c.inf << " neg=" << c.negative);
        CHECK(c.nan + c.inf + c.negative == 0);
    }
}

std::unique_ptr<Renderer> checkedFrames(const Scene& s, const Settings& st, glm::ivec2 size, gl::Profiler& prof) {
    auto r = std::make_unique<Renderer>(s, st, prof);
    r->setCheck(true);
    Camera cam = resolveCamera(s, st);
    View prev;
    for (int f = 0; f < 2; ++f) {
        View v = makeView(cam, size, f ? &prev : nullptr, unsigned(f));
        r->render(v);
        prev = v;
    }
    return r;
}

// Synthetic volumes on a unit-cell grid at the origin (the kernels of lpv_volumes.h).
struct Lpv {
    gl::MemoryLedger ledger;
    gl::ProgramCache programs;
    lpv::Volumes v;
    gl::Buffer ubo;
    Lpv(glm::ivec3 grid, GLenum format, bool occlusion, bool bounce) {
        LpvSettings s;
        s.occlusion = occlusion;
        s.bounce = bounce;
        s.format = format == GL_RGBA32F ? LpvSettings::Format::Rgba32f : LpvSettings::Format::Rgba16f;
        // The seed's scheme (first step unoccluded, bounce into the destination): docs/lpv.md, "Leaks".
        s.injectSide = LpvSettings::InjectSide::Offset;
        s.firstStepBlocked = false;
        s.blocking = LpvSettings::Blocking::Oriented;
        s.reflect = LpvSettings::Reflect::Destination;
        lpv::UniformInputs in;
        in.placement.grid = grid;
        in.placement.cell = 1.0f;
        gpu::LpvUniforms u = lpv::makeUniforms(s, in);
        ubo = gl::Buffer(ledger, "t.lpv", sizeof u, &u);
        v.ensureLight(ledger, grid, format);
        v.ensureGeometry(ledger);
    }
    // Light (the same for R, G, B) into step[0] and accum.
    void setLight(const std::vector<glm::vec4>& cells) {
        for (int k = 0; k < 2; ++k)
            for (auto& t : k ? v.accum : v.step[0])
                glTextureSubImage3D(t.id(), 0, 0, 0, 0, t.width(), t.height(), t.depth(), GL_RGBA, GL_FLOAT,
                                    cells.data());
    }
    void setGeometry(glm::vec4 sh, glm::vec3 albedo) {
        glm::ivec3 n = v.grid + 1;
        std::vector<glm::vec4> g(std::size_t(n.x * n.y * n.z), sh), a(g.size(), glm::vec4(albedo, 1));
        glTextureSubImage3D(v.geometry.id(), 0, 0, 0, 0, n.x, n.y, n.z, GL_RGBA, GL_FLOAT, g.data());
        glTextureSubImage3D(v.geometryAlbedo.id(), 0, 0, 0, 0, n.x, n.y, n.z, GL_RGBA, GL_FLOAT, a.data());
    }
    int propagate(int iterations) { return lpv::propagateCompute(programs, ubo, v, iterations); }
};

// Channel R of a volume, cell-major (x fastest), 4 coefficients per cell.
std::vector<float> readR(const lpv::Rgb& t) {
    std::vector<float> out;
    for (int z = 0; z < t[0].depth(); ++z) {
        FloatImage img = readTexture(t[0], z);
        out.insert(out.end(), img.data.begin(), img.data.end());
    }
    return out;
}

bool allFinite(const std::vector<float>& v) {
    return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

}  // namespace

TEST_CASE("stress: LPV grids 1^3 .. 32^3, non-cubic, 64 iterations, cells 1e-3 .. 1e3 stay finite and non-negative") {
    GpuFixture gpu;
    Scene scene = loadBuiltin("cornell");
    struct Case {
        glm::ivec3 grid;
        int iterations;
        float cell;
        LpvSettings::Format format;
    };
    const Case cases[] = {
        {{1, 1, 1}, 8, 0, LpvSettings::Format::Rgba16f},   {{2, 2, 2}, 64, 0, LpvSettings::Format::Rgba16f},
        {{1, 8, 3}, 64, 0, LpvSettings::Format::Rgba16f},  {{16, 2, 5}, 64, 0, LpvSettings::Format::Rgba32f},
        {{32, 32, 32}, 8, 0, LpvSettings::Format::Rgba16f}, {{8, 8, 8}, 8, 1e-3f, LpvSettings::Format::Rgba16f},
        {{8, 8, 8}, 8, 1.0f, LpvSettings::Format::Rgba16f}, {{8, 8, 8}, 8, 1e3f, LpvSettings::Format::Rgba16f},
        {{4, 4, 4}, 64, 1e3f, LpvSettings::Format::Rgba32f},
    };
    for (const Case& c : cases) {
        INFO("grid " << c.grid.x << "x" << c.grid.y << "x" << c.grid.z << ", " << c.iterations << " iterations, cell "
                     << c.cell << std::string(c.format == LpvSettings::Format::Rgba32f ? " fp32" : " fp16"));
        Settings s;
        s.lpv.mode = Toggle::On;
        s.lpv.grid = c.grid;
        s.lpv.iterations = c.iterations;
        s.lpv.cell = c.cell;
        s.lpv.format = c.format;
        s.lpv.rsm = 32;
        s.lpv.temporal = 0.5f;
        s.light.shadowSize = 128;
        gl::Profiler prof(false);
        auto r = checkedFrames(scene, s, {16, 12}, prof);
        checkAll(*r);
    }
}

TEST_CASE("stress: LPV with blocking potential 1 everywhere stops all transport after the first iteration") {
    GpuFixture gpu;
    const glm::ivec3 grid(5);
    const int centre = (2 * 5 + 2) * 5 + 2;
    std::vector<glm::vec4> light(125, glm::vec4(0));
    light[std::size_t(centre)] = lobe(1.0, glm::normalize(glm::dvec3(0.3, 1, -0.2)));
    for (GLenum format : {GL_RGBA32F, GL_RGBA16F})
        for (double potential : {1.0, 1.5}) {
            INFO(std::string(format == GL_RGBA32F ? "fp32" : "fp16") << ", blocking potential " << potential);
            // B(w) = potential for every direction: SH (potential / Y00, 0, 0, 0).
            const glm::vec4 block(float(potential / kY00), 0, 0, 0);
            std::vector<float> acc2, acc64, last64;
            for (int iterations : {2, 64}) {
                Lpv g(grid, format, true, false);
                g.setLight(light);
                g.setGeometry(block, glm::vec3(0.5f));
                int last = g.propagate(iterations);
                (iterations == 2 ? acc2 : acc64) = readR(g.v.accum);
                if (iterations == 64) last64 = readR(g.v.step[std::size_t(last)]);
            }
            REQUIRE(allFinite(acc64));
            // Iteration 1 is unoccluded (seed 3.5.1: no self-shadowing of the injected cell); from
            // iteration 2 on the transmitted fraction 1 - clamp(B, 0, 1) is 0. A potential of exactly 1
            // stored in the volume format rounds below 1: by <= 2^-23 in fp32 (1e-6 allowed for the SH
            // product), by <= 2^-10 in fp16 (truncating stores). That fraction of the iteration-1 light
            // (<= 2x the source's coefficient: the 13.5 % gain of docs/lpv.md, 6 neighbours) may leak.
            const double fraction = format == GL_RGBA32F ? 1e-6 : std::ldexp(1.0, -10);
            const double leak = potential > 1.0 ? 0.0 : 2.0 * fraction * double(light[std::size_t(centre)].x);
            double maxLast = 0, maxFar = 0, maxDiff = 0;
            for (float x : last64) maxLast = std::max(maxLast, double(std::abs(x)));
            for (int z = 0; z < 5; ++z)
                for (int y = 0; y < 5; ++y)
                    for (int x = 0; x < 5; ++x) {
                        int dist = std::abs(x - 2) + std::abs(y - 2) + std::abs(z - 2);
                        std::size_t i = std::size_t((z * 5 + y) * 5 + x) * 4;
                        for (int k = 0; k < 4; ++k) {
                            if (dist >= 2) maxFar = std::max(maxFar, double(std::abs(acc64[i + std::size_t(k)])));
                            maxDiff = std::max(maxDiff, double(std::abs(acc64[i + std::size_t(k)] - acc2[i + std::size_t(k)])));
                        }
                    }
            MESSAGE(std::string(format == GL_RGBA32F ? "fp32" : "fp16") << " potential " << potential << ": max |step 64| = "
                                                             << maxLast << ", max beyond 1 cell = " << maxFar);
            CHECK(maxLast <= leak);
            CHECK(maxFar <= leak);
            CHECK(maxDiff <= leak);
            // Iteration 1 did reach the 6 neighbours.
            CHECK(acc2[std::size_t(centre + 1) * 4] > 0.0f);
        }
    // With the bounce on, the fully blocked flux is re-emitted backwards (albedo 1, the worst case for
    // growth) for 64 iterations: finite in both formats.
    for (GLenum format : {GL_RGBA32F, GL_RGBA16F}) {
        Lpv g(grid, format, true, true);
        std::vector<glm::vec4> big = light;
        big[std::size_t(centre)] *= 1e3f;
        g.setLight(big);
        g.setGeometry(glm::vec4(float(1.0 / kY00), 0, 0, 0), glm::vec3(1.0f));
        g.propagate(64);
        CHECK(allFinite(readR(g.v.accum)));
    }
}

TEST_CASE("stress: stiff LPV, a bright small light beside a dim large one: fp16 keeps the dim part where the bright cannot reach") {
    GpuFixture gpu;
    // 16x3x3 cells, 8 iterations: the bright cell at x = 0 (flux 1e4) reaches x <= 8; the dim light
    // (flux 1e-3 .. 2e-3 in every cell, random directions) fills the whole grid. Ratio 1e7.
    const glm::ivec3 grid(16, 3, 3);
    const int iterations = 8;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1), pos(1, 2);
    std::vector<glm::vec4> dim(std::size_t(16 * 9)), bright(dim.size(), glm::vec4(0));
    for (auto& c : dim) {
        glm::dvec3 n(u(rng), u(rng), u(rng));
        c = lobe(1e-3 * pos(rng), glm::length(n) > 0.1 ? glm::normalize(n) : glm::dvec3(0, 1, 0));
    }
    bright[std::size_t((1 * 3 + 1) * 16 + 0)] = lobe(1e4, glm::dvec3(1, 0, 0));
    std::vector<glm::vec4> mixed = dim;
    for (std::size_t i = 0; i < mixed.size(); ++i) mixed[i] += bright[i];
    auto run = [&](const std::vector<glm::vec4>& light, GLenum format) {
        Lpv g(grid, format, false, false);
        g.setLight(light);
        g.propagate(iterations);
        return readR(g.v.accum);
    };
    std::vector<float> a32 = run(mixed, GL_RGBA32F), a16 = run(mixed, GL_RGBA16F), d32 = run(dim, GL_RGBA32F);
    REQUIRE(allFinite(a16));
    // Per x column: relative L2 error of fp16 against fp32 (mixed), and the dim part's share.
    double worstUnreached = 0, worstReachedRel = 0;
    bool identical = true;
    for (int x = 0; x < 16; ++x) {
        double num = 0, den = 0, dimNorm = 0;
        for (int yz = 0; yz < 9; ++yz)
            for (int k = 0; k < 4; ++k) {
                std::size_t i = std::size_t(yz * 16 + x) * 4 + std::size_t(k);
                num += std::pow(double(a16[i]) - a32[i], 2);
                den += std::pow(double(a32[i]), 2);
                dimNorm += std::pow(double(d32[i]), 2);
                if (x > iterations) identical = identical && a32[i] == d32[i];
            }
        double relTotal = std::sqrt(num / den), relDim = std::sqrt(num / dimNorm);
        if (x > iterations) worstUnreached = std::max(worstUnreached, relTotal);
        else worstReachedRel = std::max(worstReachedRel, relDim);
        MESSAGE("x = " << x << ": |fp16 - fp32| / |fp32| = " << relTotal << ", relative to the dim light alone = "
                       << relDim);
    }
    // Cells the bright light cannot reach in 8 iterations compute exactly as without it (fp32) ...
    CHECK(identical);
    // ... and fp16 keeps the dim light there: 8 stored steps and the stored sum, each truncated by
    // <= 2^-10 relative (2^-11 on average): 8 x 2^-11 = 3.9e-3 -> 5e-3.
    CHECK(worstUnreached <= 5e-3);
    // Where both mix, fp16 rounds relative to the total: the dim part's error is (bright/dim) x 2^-10 per
    // stored step and exceeds the dim light itself (measured ratio > 1 at ratio 1e7; documented).
    CHECK(worstReachedRel > 1.0);

    // Dim light alone below the fp16 normal range (flux 1e-6: coefficients ~3e-7, subnormal) and below
    // the smallest subnormal (flux 1e-9: ~3e-10, flushed to 0).
    for (double scale : {1e-3, 1e-6, 1e-9}) {
        std::vector<glm::vec4> d = dim;
        for (auto& c : d) c *= float(scale / 1e-3);
        std::vector<float> f32 = run(d, GL_RGBA32F), f16 = run(d, GL_RGBA16F);
        double num = 0, den = 0;
        for (std::size_t i = 0; i < f32.size(); ++i) {
            num += std::pow(double(f16[i]) - f32[i], 2);
            den += std::pow(double(f32[i]), 2);
        }
        double rel = std::sqrt(num / den);
        MESSAGE("dim light alone, flux " << scale << ": fp16 vs fp32 relative L2 = " << rel);
        if (scale == 1e-3) CHECK(rel <= 5e-3);  // as above
        if (scale == 1e-6) CHECK(rel > 3e-3);   // subnormal halves: precision lost
        if (scale == 1e-9) CHECK(rel >= 0.99);  // flushed: nothing left
    }
}
