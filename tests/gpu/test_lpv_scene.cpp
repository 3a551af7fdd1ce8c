// LPV end to end on scenes: raster baseline vs compute path, extremes of
// sun intensity and cell size, a volume that misses the scene, pruning.
#include "gpu_fixture.h"

#include <algorithm>
#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

Settings lpvSettings() {
    Settings s;
    s.lpv.mode = Toggle::On;
    s.lpv.grid = glm::ivec3(8);
    s.lpv.iterations = 4;
    s.lpv.rsm = 64;
    s.light.shadowSize = 256;
    return s;
}

// Accumulated LPV volume (R, G, B) as floats, through the pass's checked outputs.
std::vector<float> accumulated(const Renderer& r) {
    std::vector<float> out;
    Pass* p = r.findPass("lpv.propagate");
    REQUIRE(p != nullptr);
    for (auto& o : p->checkedOutputs(const_cast<Renderer&>(r).resources()))
        for (int z = 0; z < o.tex->depth(); ++z) {
            FloatImage img = readTexture(*o.tex, z);
            out.insert(out.end(), img.data.begin(), img.data.end());
        }
    return out;
}

double relL2(const std::vector<float>& a, const std::vector<float>& b) {
    double n = 0, d = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        n += double(a[i] - b[i]) * double(a[i] - b[i]);
        d += double(b[i]) * double(b[i]);
    }
    return d > 0 ? std::sqrt(n / d) : std::sqrt(n);
}

}  // namespace

TEST_CASE("LPV raster baseline produces the compute path's volumes on the cornell scene") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = loadBuiltin("cornell");
    for (auto format : {LpvSettings::Format::Rgba32f, LpvSettings::Format::Rgba16f}) {
        Settings s = lpvSettings();
        s.lpv.format = format;
        auto compute = renderFrames(scene, s, {32, 32}, prof);
        std::vector<float> a = accumulated(*compute);
        s.lpv.path = LpvSettings::Path::Raster;
        auto raster = renderFrames(scene, s, {32, 32}, prof);
        CHECK(raster->findPass("lpv.pack") == nullptr);
        std::vector<float> b = accumulated(*raster);
        REQUIRE(a.size() == b.size());
        double mx = 0;
        for (float x : a) mx = std::max(mx, double(std::abs(x)));
        CHECK(mx > 0.0);
        // Same math from the same GLSL. fp32: only the summation order of injected points
        // differs (blending vs atomics): 1e-5. fp16: the raster path blends every injected
        // point into a half partial sum (each add rounded, towards zero on llvmpipe, 2^-10
        // relative), the compute path sums in fp32 and rounds once; with tens of points per
        // cell and 4 iterations that bias reaches ~6e-3: 1e-2 (about ten half ulps).
        CHECK(relL2(b, a) <= (format == LpvSettings::Format::Rgba32f ? 1e-5 : 1e-2));
    }
}

TEST_CASE("LPV extremes: sun 1e-6..1e6 is linear in fp32 and finite in fp16; a volume off the scene gives no light") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = loadBuiltin("cornell");
    Settings s = lpvSettings();
    s.lpv.format = LpvSettings::Format::Rgba32f;
    s.light.sunIrradiance = 1.0f;
    std::vector<float> ref = accumulated(*renderFrames(scene, s, {16, 16}, prof));
    for (float e : {1e-6f, 1e6f}) {
        s.light.sunIrradiance = e;
        std::vector<float> v = accumulated(*renderFrames(scene, s, {16, 16}, prof));
        for (float& x : v) x /= e;
        // fp32 relative rounding, independent of the magnitude (no denormals at 1e-6 x flux).
        CHECK(relL2(v, ref) <= 1e-5);
    }
    // fp16: 1e6 saturates the volume at the largest half (documented clamp), never Inf/NaN.
    s.lpv.format = LpvSettings::Format::Rgba16f;
    s.light.sunIrradiance = 1e6f;
    auto r = renderFrames(scene, s, {16, 16}, prof);
    r->setCheck(true);
    r->render(makeView(resolveCamera(scene, s), {16, 16}, nullptr, 0));
    for (auto& f : r->finiteCounts()) {
        INFO(f.pass << " " << f.resource);
        CHECK(f.nan == 0);
        CHECK(f.inf == 0);
    }
    // A camera-following volume of 8 cells of 1 mm, 30 % ahead of the camera (in the air
    // in front of the box): the RSM fitted to it sees no surface, nothing is injected and
    // no pixel receives LPV light.
    s.lpv.cell = 1e-3f;
    s.light.sunIrradiance = 1.0f;
    auto off = renderFrames(scene, s, {16, 16}, prof);
    for (float x : accumulated(*off)) CHECK(x == 0.0f);
    FloatImage ind = readTexture(off->resources().indirectDiffuse);
    double sum = 0;
    for (float x : ind.data) sum += x;
    CHECK(sum == doctest::Approx(16.0 * 16.0).epsilon(1e-9));  // only the alpha channel (1) is non-zero
}

TEST_CASE("LPV radiance is invariant under scaling the scene by 1e-3 and 1e3 (auto-fitted cells)") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene base = loadBuiltin("cornell");
    Settings s = lpvSettings();
    s.lpv.format = LpvSettings::Format::Rgba32f;
    s.lpv.occlusion = s.lpv.bounce = false;  // the G-buffer blockers' areas depend on pixel footprints only
    auto render = [&](float k) {
        Scene sc = base;
        for (auto& v : sc.vertices) v.position *= k;
        for (auto& c : sc.cameras) {
            c.position *= k;
            c.target *= k;
            c.near *= k;
            c.far *= k;
        }
        return readTexture(renderFrames(sc, s, {24, 24}, prof)->resources().indirectDiffuse);
    };
    FloatImage ref = render(1.0f);
    double refSum = 0;
    for (float x : ref.data) refSum += x;
    CHECK(refSum > 24.0 * 24.0);  // some indirect light beyond the alpha channel
    for (float k : {1e-3f, 1e3f}) {
        FloatImage img = render(k);
        double num = 0, den = 0;
        for (std::size_t i = 0; i < img.data.size(); ++i) {
            num += std::pow(double(img.data[i] - ref.data[i]), 2);
            den += std::pow(double(ref.data[i]), 2);
        }
        // Radiance depends on E_perp and albedos only; scaling changes fp32 rounding of positions
        // (cell assignment of texels right on a boundary) and fp16 output rounding: 1 %.
        CHECK(std::sqrt(num / den) <= 1e-2);
    }
}

TEST_CASE("LPV pass pruning: no sun -> no LPV passes; occlusion/bounce off -> no geometry volume") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Settings s = lpvSettings();
    s.lpv.mode = Toggle::Auto;
    Scene dark = floorScene(2, glm::vec3(0.5f), false);
    Renderer r(dark, s, prof);
    for (auto& p : r.passes()) CHECK(p->name().rfind("lpv.", 0) != 0);
    Scene lit = floorScene(2, glm::vec3(0.5f), true);
    s.lpv.occlusion = s.lpv.bounce = false;
    Renderer r2(lit, s, prof);
    CHECK(r2.findPass("lpv.rsm") != nullptr);
    CHECK(r2.findPass("lpv.apply") != nullptr);
    CHECK(r2.findPass("lpv.inject_geometry") == nullptr);
    CHECK(r2.findPass("lpv.temporal") == nullptr);
}
