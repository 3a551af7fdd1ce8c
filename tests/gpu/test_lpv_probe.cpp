// lpv.source=probe (issue 12, stage attribution; docs/lpv.md): the probe
// volume of every cascade against an independent oracle. Scene: a sunlit
// Lambert lobe of a glossy square (albedo rho, metallic 0.5, half-size h, sun irradiance E at cos theta_s)
// and nothing else, so the one-bounce radiance arriving at a point above it
// is L_f = rho (1 - metallic) E cos(theta_s) / pi from the directions that hit the square
// and 0 elsewhere (no sky at the first segment, as the matching-bounce
// reference). Its band-0/1 projection p_k = L_f * integral over the square
// of Y_k(w) dw, with dw = y dA / r^3, is a CPU double midpoint quadrature
// over the square; the volume must hold s^2 * mirror(p) (the intensity of
// the light flowing through the cell, lpv.apply's convention). Points below
// the square see its unlit underside: 0.
#include "gpu_fixture.h"

#include "render/lpv/lpv_math.h"

#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

constexpr double kPi = 3.14159265358979323846;
const double kY00 = 0.28209479177387814, kY1 = 0.48860251190291992;

glm::dvec4 basis(glm::dvec3 d) { return {kY00, -kY1 * d.y, kY1 * d.z, -kY1 * d.x}; }

struct Projection {
    glm::dvec4 p{0.0};   // integral of Y_k over the square's solid angle
    glm::dvec4 p2{0.0};  // integral of Y_k^2 (variance bound)
};

// Midpoint rule on n x n cells of the square [-h, h]^2 at y = 0, seen from x (x.y > 0).
Projection squareProjection(glm::dvec3 x, double h, int n) {
    Projection out;
    if (x.y <= 0.0) return out;
    double da = (2.0 * h / n) * (2.0 * h / n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            glm::dvec3 q(-h + (i + 0.5) * 2.0 * h / n, 0.0, -h + (j + 0.5) * 2.0 * h / n);
            glm::dvec3 d = q - x;
            double r = glm::length(d);
            double dw = x.y * da / (r * r * r);
            glm::dvec4 y = basis(d / r);
            out.p += y * dw;
            out.p2 += y * y * dw;
        }
    return out;
}

std::vector<glm::dvec4> readVolume(const gl::Texture& t) {
    std::vector<glm::dvec4> out;
    for (int z = 0; z < t.depth(); ++z) {
        FloatImage img = readTexture(t, z);
        for (int i = 0; i < img.width * img.height; ++i)
            out.emplace_back(img.data[std::size_t(i) * 4], img.data[std::size_t(i) * 4 + 1],
                             img.data[std::size_t(i) * 4 + 2], img.data[std::size_t(i) * 4 + 3]);
    }
    return out;
}

}  // namespace

TEST_CASE("LPV probe volume: sunlit square, every cascade's SH equals the CPU double projection within the MC bound") {
    GpuFixture fx;
    const double rho = 0.6, e = 2.0, half = 2.0;
    const glm::dvec3 towardSun = glm::normalize(glm::dvec3(0.3, 1.0, 0.2));
    Scene scene = floorScene(float(half), glm::vec3(float(rho)), true, glm::vec3(towardSun), float(e));
    // Glossy and half metallic: the probe must see only the Lambert lobe
    // diffuseAlbedo = rho (1 - metallic), as the matching-bounce reference.
    const double metallic = 0.5;
    scene.materials[0].roughness = 0.1f;
    scene.materials[0].metallic = float(metallic);
    const double lf = rho * (1.0 - metallic) * e * towardSun.y / kPi;  // radiance of the square, one bounce

    Settings s = smallLpvSettings();
    s.lpv.cascades = 2;
    s.lpv.cell = 0.25f;  // cascade 0: 8^3 of 0.25 (2 m), cascade 1: 0.5 (4 m)
    s.lpv.format = LpvSettings::Format::Rgba32f;
    s.lpv.bounce = false;  // one bounce
    s.lpv.source = LpvSettings::Source::Probe;
    const int n = 256;
    s.lpv.probeDirections = n;
    gl::Profiler prof(false);
    const glm::ivec2 size{32, 32};
    auto r = renderFrames(scene, s, size, prof);

    // The placement the renderer used (pure function of settings, bounds and view).
    Camera cam = resolveCamera(scene, s);
    View v = makeView(cam, size, nullptr, 0);
    auto placements = lpv::placeCascades(s.lpv, 2, scene.bounds(), v.position, v.forward());
    REQUIRE(placements.size() == 2);

    Pass* prop = r->findPass("lpv.propagate");
    REQUIRE(prop != nullptr);
    // Per cascade (finest first) and channel r, g, b (grey square: all equal).
    std::vector<const gl::Texture*> accum, nearPart;
    for (auto& o : r->checkedOutputs(*prop)) {
        if (o.name.find("lpv.accum.") != std::string::npos) accum.push_back(o.tex);
        if (o.name.find("lpv.near.") != std::string::npos) nearPart.push_back(o.tex);
    }
    REQUIRE(accum.size() == 6);
    REQUIRE(nearPart.size() == 3);  // cascade 1 only

    int checked = 0, lit = 0;
    double worst = 0;  // largest |error| / bound
    for (int vi = 0; vi < 6; ++vi) {
        const int ci = vi / 3;
        const lpv::Placement& pl = placements[std::size_t(ci)];
        std::vector<glm::dvec4> got = readVolume(*accum[std::size_t(vi)]);
        std::vector<glm::dvec4> gotNear = ci == 1 ? readVolume(*nearPart[std::size_t(vi - 3)]) : std::vector<glm::dvec4>{};
        REQUIRE(got.size() == std::size_t(pl.grid.x * pl.grid.y * pl.grid.z));
        const double s2 = double(pl.cell) * double(pl.cell);
        for (int z = 0; z < pl.grid.z; ++z)
            for (int y = 0; y < pl.grid.y; ++y)
                for (int x = 0; x < pl.grid.x; ++x) {
                    glm::dvec3 c = glm::dvec3(pl.origin) + (glm::dvec3(x, y, z) + 0.5) * double(pl.cell);
                    if (std::abs(c.y) < 0.05) continue;  // a centre on the square itself: no oracle
                    Projection pr = squareProjection(c, half, 400);
                    // Volume convention: I = s^2 mirror(p) (band 1 odd).
                    glm::dvec4 want = s2 * lf * glm::dvec4(pr.p.x, -pr.p.y, -pr.p.z, -pr.p.w);
                    std::size_t idx = std::size_t(x + pl.grid.x * (y + pl.grid.y * z));
                    for (int k = 0; k < 4; ++k) {
                        // Jittered strata never exceed the variance of N independent uniform
                        // directions: sigma_k^2 <= 4 pi L_f^2 int Y_k^2 dw / N. 4 sigma, plus
                        // float rounding.
                        double sigma = s2 * lf * std::sqrt(4.0 * kPi * pr.p2[k] / n);
                        double bound = 4.0 * sigma + 1e-5 * s2 * lf;
                        double err = std::abs(got[idx][k] - want[k]);
                        INFO("cascade " << ci << " channel " << vi % 3 << " cell " << x << "," << y << "," << z << " k " << k << " got "
                                        << got[idx][k] << " want " << want[k] << " bound " << bound);
                        CHECK(err <= bound);
                        worst = std::max(worst, err / bound);
                        if (ci == 1) CHECK(gotNear[idx][k] == doctest::Approx(got[idx][k]).epsilon(1e-6));
                    }
                    ++checked;
                    if (want.x > 0.05 * s2 * lf) ++lit;
                }
    }
    MESSAGE("cells checked " << checked << ", lit " << lit << ", worst error / bound " << worst);
    CHECK(checked > 1500);
    CHECK(lit > 600);
}
