// The split-sum BRDF LUT against a CPU double-precision quadrature of the
// two split-sum integrals (SPEC 9), over the half-vector hemisphere.
#include "gpu_fixture.h"

#include "render/passes/core_passes.h"

#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

// A = ∫ f/F·(1 − Fc)·cos dl and B = ∫ f/F·Fc·cos dl with Fc = (1 − v·h)^5,
// f/F = D·V (GGX, Smith height-correlated as in compute/lib/brdf.glsl),
// integrated over the half vector h (dω_l = 4 (v·h) dω_h) by the midpoint
// rule in (θ_h, φ_h). Independent of the GPU's importance sampling.
std::pair<double, double> splitSumQuadrature(double NdotV, double roughness) {
    const double pi = 3.14159265358979323846;
    double alpha = std::max(roughness * roughness, 1e-3), a2 = alpha * alpha;
    double vx = std::sqrt(1 - NdotV * NdotV), vz = NdotV;
    const int nt = 3000, np = 360;
    double A = 0, B = 0, dt = 0.5 * pi / nt, dp = 2 * pi / np;
    for (int i = 0; i < nt; ++i) {
        double th = (i + 0.5) * dt, ct = std::cos(th), st = std::sin(th);
        double t = ct * ct * (a2 - 1) + 1, D = a2 / (pi * t * t);
        for (int j = 0; j < np; ++j) {
            double ph = (j + 0.5) * dp;
            double hx = st * std::cos(ph), hy = st * std::sin(ph), hz = ct;
            double vh = vx * hx + vz * hz;
            if (vh <= 0) continue;
            double lz = 2 * vh * hz - vz;
            (void)hy;
            if (lz <= 0) continue;
            double gv = lz * std::sqrt(vz * vz * (1 - a2) + a2), gl = vz * std::sqrt(lz * lz * (1 - a2) + a2);
            double V = 0.5 / (gv + gl);
            double w = D * V * lz * 4 * vh * st * dt * dp;
            double fc = std::pow(1 - vh, 5);
            A += (1 - fc) * w;
            B += fc * w;
        }
    }
    return {A, B};
}

}  // namespace

TEST_CASE("split-sum BRDF LUT matches a CPU quadrature of the split-sum integrals") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene s = floorScene(5, glm::vec3(0.5f), false);
    Settings st;
    st.floorRoughness = 0.1f;  // glossy: SSR runs, so the LUT pass does
    auto r = renderFrames(s, st, {8, 8}, prof, 1);
    const gl::Texture& lut = r->resources().brdfLut;
    REQUIRE(lut);
    CHECK(lut.format() == GLenum(GL_RG16F));
    FloatImage img = readTexture(lut);
    REQUIRE(img.width == kBrdfLutSize);
    for (int i : {6, 20, 40, 60})          // n·v = (i + 0.5) / size
        for (int j : {12, 26, 45, 62}) {   // roughness = (j + 0.5) / size
            double nv = (i + 0.5) / kBrdfLutSize, rough = (j + 0.5) / kBrdfLutSize;
            auto [A, B] = splitSumQuadrature(nv, rough);
            INFO("n.v " << nv << " roughness " << rough);
            // 0.01 absolute: 4096-point Hammersley QMC (error ~ log N / N of the
            // integrand's variation) + fp16 storage (~1e-3 at values <= 1).
            CHECK(std::abs(img.at(i, j, 0) - A) < 0.01);
            CHECK(std::abs(img.at(i, j, 1) - B) < 0.01);
            CHECK(A + B <= 1.0 + 1e-6);  // the quadrature itself conserves energy (sanity of the oracle)
        }
}
