// Error metrics against hand-computed values on tiny images, SSIM
// invariants, the heat map's layout, and the reference's settings -> GPU
// constants function.
#include "render/reference/metrics.h"
#include "render/reference/reference_passes.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace rtgi;

namespace {
FloatImage grey(int w, int h, std::vector<float> v) {
    FloatImage img;
    img.width = w;
    img.height = h;
    for (float x : v) img.data.insert(img.data.end(), {x, x, x, 1.0f});
    return img;
}
}  // namespace

TEST_CASE("RMSE, MAE, bias and PSNR equal hand-computed values on a 2x2 image") {
    FloatImage t = grey(2, 2, {0.0f, 0.5f, 1.0f, 1.0f});
    FloatImage r = grey(2, 2, {0.0f, 0.0f, 1.0f, 0.5f});
    // Differences 0, .5, 0, .5: MSE = 0.5/4 = 0.125.
    ErrorMetrics m = compareImages(t, r, 1, 1.0);
    CHECK(m.rmse == doctest::Approx(std::sqrt(0.125)).epsilon(1e-12));
    CHECK(m.mae == doctest::Approx(0.25).epsilon(1e-12));
    CHECK(m.bias == doctest::Approx(0.25).epsilon(1e-12));
    CHECK(m.psnr == doctest::Approx(10.0 * std::log10(1.0 / 0.125)).epsilon(1e-12));  // 9.0309 dB
    CHECK(m.pixels == 4);
    // A mask without pixel 1 leaves differences 0, 0, .5: MSE = 0.25 / 3.
    ErrorMetrics k = compareImages(t, r, 1, 1.0, {1, 0, 1, 1});
    CHECK(k.rmse == doctest::Approx(std::sqrt(0.25 / 3.0)).epsilon(1e-12));
    CHECK(k.pixels == 3);
    // RGB: the same differences in every channel give the same RMSE.
    CHECK(compareImages(t, r, 3, 1.0).rmse == doctest::Approx(std::sqrt(0.125)).epsilon(1e-12));
    // PSNR with peak 2: +20·log10(2) dB.
    CHECK(compareImages(t, r, 1, 2.0).psnr == doctest::Approx(m.psnr + 20.0 * std::log10(2.0)).epsilon(1e-12));
}

TEST_CASE("Relative RMSE of HDR radiance") {
    FloatImage t = grey(1, 1, {1.1f}), r = grey(1, 1, {1.0f});
    double d = double(1.1f) - 1.0;
    CHECK(compareImages(t, r, 1, 1.0).relRmse == doctest::Approx(std::sqrt(d * d / (1.0 + 1e-4))).epsilon(1e-9));
}

TEST_CASE("SSIM: 1 for identical images, symmetric, below 1 for different ones") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> a(24 * 20), b(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        a[i] = u(rng);
        b[i] = std::clamp(a[i] + 0.2f * (u(rng) - 0.5f), 0.0f, 1.0f);
    }
    FloatImage x = grey(24, 20, a), y = grey(24, 20, b);
    CHECK(ssimLuminance(x, x, 1, 1.0) == doctest::Approx(1.0).epsilon(1e-12));
    CHECK(ssimLuminance(x, y, 3, 1.0) == doctest::Approx(ssimLuminance(y, x, 3, 1.0)).epsilon(1e-12));
    CHECK(ssimLuminance(x, y, 1, 1.0) < 0.99);
    // A constant offset keeps the structure and contrast terms at 1; the
    // luminance term of the flat images is (2μxμy + C1)/(μx² + μy² + C1).
    FloatImage c0 = grey(16, 16, std::vector<float>(256, 0.4f)), c1 = grey(16, 16, std::vector<float>(256, 0.6f));
    double C1 = 0.01 * 0.01;
    CHECK(ssimLuminance(c0, c1, 1, 1.0) == doctest::Approx((2 * 0.4 * 0.6 + C1) / (0.16 + 0.36 + C1)).epsilon(1e-6));
}

TEST_CASE("Error heat map: colour bar to the right, zero error black, the maximum at the top of the ramp") {
    FloatImage t = grey(8, 4, std::vector<float>(32, 0.0f)), r = t;
    r.data[0] = r.data[1] = r.data[2] = 0.5f;  // pixel (0,0) differs by 0.5
    double mx = errorQuantile(t, r, 1, 1.0);
    CHECK(mx == doctest::Approx(0.5));
    CHECK(errorQuantile(t, r, 1, 0.5) == 0.0);  // 31 of 32 pixels are equal
    FloatImage h = errorHeatmap(t, r, 1, mx);
    CHECK(h.width == 8 + 44);
    CHECK(h.height == 4);
    CHECK(h.at(0, 0, 0) > 0.9f);    // maximum: light yellow
    CHECK(h.at(0, 0, 1) > 0.9f);
    CHECK(h.at(1, 0, 1) < 0.05f);   // zero error: dark
    CHECK(h.at(8 + 6, 3, 1) > 0.9f);  // bar top = maximum colour
    CHECK(h.at(8 + 6, 0, 1) < 0.05f); // bar bottom = zero colour
}

TEST_CASE("Reference settings -> GPU constants") {
    Settings s;
    Aabb box;
    box.grow({0, 0, 0});
    box.grow({3, 4, 0});  // diagonal 5
    s.reference.kind = ReferenceSettings::Kind::Ao;
    s.reference.spp = 40;
    s.ao.radius = 2.5f;
    ReferenceConstants c = referenceConstants(s, box);
    CHECK(c.rayLength == 2.5f);  // AO rays as long as the compared configuration's radius
    CHECK(c.samplesPerDispatch == 16);
    CHECK(c.defines().empty());
    s.reference.spp = 3;
    CHECK(referenceConstants(s, box).samplesPerDispatch == 3);
    s.reference.kind = ReferenceSettings::Kind::Full;
    s.reference.specular = false;
    s.reference.spp = 256;
    c = referenceConstants(s, box);
    CHECK(c.samplesPerDispatch == 4);
    CHECK(c.diffuseOnly);
    REQUIRE(c.defines().size() == 2);
    CHECK(c.defines()[0].name == "RTGI_REF_FULL");
    CHECK(c.defines()[1].name == "RTGI_REF_DIFFUSE_ONLY");
    // Caustic paths: regularized by default (with the roughness floor as a
    // define), removed with off, untouched with on; no glossy lobe, no define.
    s.reference.specular = true;
    c = referenceConstants(s, box);
    REQUIRE(c.defines().size() == 3);
    CHECK(c.defines()[1].name == "RTGI_REF_CAUSTICS_REGULARIZED");
    CHECK(c.defines()[2].name == "RTGI_REF_CAUSTIC_ROUGHNESS");
    CHECK(std::stod(c.defines()[2].value) == doctest::Approx(0.3));
    applySetting(s, "reference.caustics", "off");
    applySetting(s, "reference.caustic_roughness", "0.5");
    c = referenceConstants(s, box);
    CHECK(c.defines()[1].name == "RTGI_REF_CAUSTICS_OFF");
    CHECK(std::stod(c.defines()[2].value) == doctest::Approx(0.5));
    applySetting(s, "reference.caustics", "on");
    CHECK(referenceConstants(s, box).defines().size() == 1);
    CHECK_THROWS_AS(applySetting(s, "reference.caustics", "maybe"), ConfigError);
    CHECK_THROWS_AS(applySetting(s, "reference.target_noise", "2"), ConfigError);
    CHECK_THROWS_AS(applySetting(s, "reference.seed", "-1"), ConfigError);
    CHECK_THROWS_AS(applySetting(s, "reference.specular", "maybe"), ConfigError);
}

TEST_CASE("depthInteriorMask drops sky and every pixel whose 3x3 neighbourhood jumps in depth by more than 10 %") {
    // 5x1 row pattern stacked 3 high: depths 1, 1, 1.05, 2, 2 (a 5 % step, then a 90 % step).
    // A sky column would be 0; the middle row checks the vertical neighbours too.
    FloatImage d = grey(5, 3, {1.0f, 1.0f, 1.05f, 2.0f, 2.0f,  //
                               1.0f, 1.0f, 1.05f, 2.0f, 0.0f,  //
                               1.0f, 1.0f, 1.05f, 2.0f, 2.0f});
    d.channels = 4;
    std::vector<std::uint8_t> m = depthInteriorMask(d, 0.1);
    REQUIRE(m.size() == 15u);
    // Columns 0, 1: only 5 % steps at most (1 -> 1.05 is within 10 % of 1): interior.
    for (int y = 0; y < 3; ++y) {
        CHECK(m[std::size_t(y * 5 + 0)] == 1);
        CHECK(m[std::size_t(y * 5 + 1)] == 1);
        // Column 2 neighbours depth 2 (|2 - 1.05| > 0.105): edge; column 3 neighbours 1.05: edge.
        CHECK(m[std::size_t(y * 5 + 2)] == 0);
        CHECK(m[std::size_t(y * 5 + 3)] == 0);
    }
    // Column 4: the sky pixel itself and both its vertical neighbours are excluded.
    CHECK(m[4] == 0);
    CHECK(m[9] == 0);
    CHECK(m[14] == 0);
}
