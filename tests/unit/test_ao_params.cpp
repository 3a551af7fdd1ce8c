// AO settings -> GPU constants and the generated sample sets, against
// independent oracles (analytic volumes, distributions, seed tables).
#include "render/ao/ao_params.h"
#include "render/noise.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

using namespace rtgi;

TEST_CASE("AO sample counts map to directions x steps as in seed 003 table 6.2") {
    CHECK(horizonSampling(8) == glm::ivec2(4, 2));
    CHECK(horizonSampling(16) == glm::ivec2(4, 4));
    CHECK(horizonSampling(24) == glm::ivec2(6, 4));
    for (int n = 1; n <= 64; ++n) {
        glm::ivec2 m = horizonSampling(n);
        CHECK(m.x >= 1);
        CHECK(m.y >= 1);
        CHECK(m.x * m.y <= std::max(n, 1));
    }
}

TEST_CASE("VO line-sample volumes sum to the unit sphere volume 4/3 pi") {
    for (int pairs : {4, 8, 12}) {
        auto s = voSamplePairs(pairs);
        REQUIRE(int(s.size()) == pairs);
        double sum = 0;
        for (auto& v : s) {
            sum += 2.0 * v.w;  // both partners of the pair
            // z_s is the half-length of the line inside the unit sphere.
            CHECK(v.z == doctest::Approx(std::sqrt(1.0 - v.x * v.x - v.y * v.y)).epsilon(1e-5));
        }
        // Grid integration of 2 sqrt(1 - r^2) over 384^2 cells: the rim cells
        // cost ~0.3 %; 1 % tolerance.
        CHECK(sum == doctest::Approx(4.0 * M_PI / 3.0).epsilon(0.01));
    }
}

static double radiusOf(const glm::vec4& v) { return std::sqrt(double(v.x * v.x + v.y * v.y + v.z * v.z)); }

TEST_CASE("sphere-kernel radii follow d(x) = 3/2 (1 - x^2) (Kolmogorov-Smirnov)") {
    // The inverse CDF solves (3x - x^3)/2 = u.
    for (double u : {0.0, 0.1, 0.5, 0.9, 1.0}) {
        double x = sphereKernelRadius(u);
        CHECK((3 * x - x * x * x) / 2 == doctest::Approx(u).epsilon(1e-9));
    }
    const int n = 64;
    auto k = sphereKernel(n);
    std::vector<double> r;
    for (auto& v : k) {
        r.push_back(std::sqrt(double(v.x * v.x + v.y * v.y + v.z * v.z)));
        CHECK(r.back() <= 1.0 + 1e-6);
    }
    std::sort(r.begin(), r.end());
    double dMax = 0;
    for (int i = 0; i < n; ++i) {
        double F = (3 * r[std::size_t(i)] - std::pow(r[std::size_t(i)], 3)) / 2;
        dMax = std::max({dMax, std::abs(F - double(i) / n), std::abs(F - double(i + 1) / n)});
    }
    // KS critical value at alpha = 0.05 for n = 64: 1.36 / sqrt(64) = 0.17.
    CHECK(dMax < 1.36 / std::sqrt(double(n)));
    // Antithetic pairs: k[2i+1] = -k[2i] exactly (the plane normalization relies on it).
    for (int i = 0; i + 1 < n; i += 2) CHECK(k[std::size_t(i + 1)] == -k[std::size_t(i)]);
    // Directions are isotropic: over the 32 independent pair directions the mean
    // |z| of a uniform direction is 1/2 (standard error 0.29/sqrt(32) = 0.05; 3 sigma).
    double meanAbsCos = 0;
    for (int i = 0; i < n; i += 2) meanAbsCos += std::abs(k[std::size_t(i)].z) / radiusOf(k[std::size_t(i)]) / (n / 2);
    CHECK(std::abs(meanAbsCos - 0.5) < 0.15);
}

TEST_CASE("Poisson-disk probe keeps K points inside the unit disk, well separated") {
    for (int k : {4, 9, 20, 328}) {
        auto p = poissonDisk(k);
        REQUIRE(int(p.size()) == k);
        float minD = 10;
        for (std::size_t i = 0; i < p.size(); ++i) {
            CHECK(glm::length(p[i]) <= 1.0f);
            for (std::size_t j = 0; j < i; ++j) minD = std::min(minD, glm::distance(p[i], p[j]));
        }
        // Poisson property: spacing at least a third of the ideal sqrt(pi/K) packing distance.
        CHECK(minD > std::sqrt(float(M_PI) / float(k)) / 3.0f);
    }
}

TEST_CASE("makeAoParams carries settings into the GPU block") {
    AoSettings s;
    s.samples = 24;
    s.radius = 2.0f;
    s.angleBiasDeg = 30.0f;
    s.variant = AoSettings::Variant::Hbao;
    gpu::AoParams p = makeAoParams(s, {32, 18}, {64, 36}, glm::radians(60.0f));
    CHECK(p.counts == glm::ivec4(24, 6, 4, int(AoSettings::Variant::Hbao)));
    CHECK(p.radius.x == 2.0f);
    CHECK(p.radius.z == 4.0f);  // VO maximum occlusion distance 2R
    CHECK(p.radius.w == doctest::Approx(std::tan(M_PI / 6)));
    CHECK(p.focal.y == doctest::Approx(1.0 / std::tan(M_PI / 6)));
    CHECK(p.focal.x == doctest::Approx(p.focal.y * 36.0 / 64.0));
    double w = 0;
    for (int i = 0; i < int(p.misc.z); ++i) w += p.voSamples[i].w;
    CHECK(w == doctest::Approx(1.0));  // normalized volume weights
}

TEST_CASE("blue noise is exactly uniform and has little low-frequency energy") {
    auto t = blueNoiseTile(kBlueNoiseSize, 3);
    REQUIRE(int(t.size()) == kBlueNoiseSize * kBlueNoiseSize);
    std::vector<int> hist(16, 0);
    for (float v : t) {
        CHECK(v > 0.0f);
        CHECK(v < 1.0f);
        ++hist[std::size_t(v * 16)];
    }
    for (int h : hist) CHECK(h == kBlueNoiseSize * kBlueNoiseSize / 16);  // rank remap: exactly uniform
    // Low-pass energy: variance of 4x4 block means. White noise: var(U)/16 =
    // 1/192; blue noise must be well below (high-pass filtered), use half.
    double m = 0, v = 0;
    int blocks = 0;
    for (int by = 0; by < kBlueNoiseSize; by += 4)
        for (int bx = 0; bx < kBlueNoiseSize; bx += 4) {
            double s = 0;
            for (int y = 0; y < 4; ++y)
                for (int x = 0; x < 4; ++x) s += t[std::size_t((by + y) * kBlueNoiseSize + bx + x)];
            s /= 16;
            m += s;
            v += s * s;
            ++blocks;
        }
    m /= blocks;
    v = v / blocks - m * m;
    CHECK(v < 0.5 / 192.0);
}
