// LPV math without GL: SH cosine lobe and irradiance, propagation face
// constants, volume placement and RSM texel area, all against numerical
// integration or analytic values computed here in double precision.
#include "render/lpv/lpv_math.h"

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

using namespace rtgi;

namespace {

const double kPi = 3.14159265358979323846;

// Real SH basis (SPEC 3) in double, written out independently of sh.glsl.
glm::dvec4 basis(glm::dvec3 d) {
    const double y0 = 0.5 / std::sqrt(kPi), y1 = std::sqrt(3.0) / (2.0 * std::sqrt(kPi));
    return {y0, -y1 * d.y, y1 * d.z, -y1 * d.x};
}

// Midpoint rule over (cos theta, phi): area element is exact for this parametrization.
template <class F>
void integrateSphere(int n, F f) {
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < 2 * n; ++j) {
            double z = -1.0 + (i + 0.5) * 2.0 / n, phi = (j + 0.5) * kPi / n;
            double r = std::sqrt(1.0 - z * z);
            f(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z), (2.0 / n) * (kPi / n));
        }
}

// Solid angle and unnormalized mean direction of the square face spanning
// p0 + a*u + b*v (a, b in [-1/2, 1/2]) seen from the origin.
void integrateFace(glm::dvec3 p0, glm::dvec3 u, glm::dvec3 v, double& omega, glm::dvec3& dir) {
    const int n = 600;
    glm::dvec3 normal = glm::normalize(glm::cross(u, v));
    omega = 0;
    dir = glm::dvec3(0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            glm::dvec3 p = p0 + ((i + 0.5) / n - 0.5) * u + ((j + 0.5) / n - 0.5) * v;
            double r = glm::length(p);
            double w = std::abs(glm::dot(p, normal)) / (r * r * r) / (double(n) * n);
            omega += w;
            dir += p / r * w;
        }
}

}  // namespace

TEST_CASE("LPV SH: clamped-cosine lobe coefficients and pi*L irradiance by numerical integration") {
    for (glm::dvec3 n : {glm::dvec3(0, 0, 1), glm::normalize(glm::dvec3(0.3, -0.7, 0.2)), glm::dvec3(-1, 0, 0)}) {
        glm::dvec4 proj(0.0);
        integrateSphere(400, [&](glm::dvec3 w, double dw) { proj += std::max(0.0, glm::dot(n, w)) * basis(w) * dw; });
        glm::dvec4 lobe(RTGI_SH_COS_C0, -RTGI_SH_COS_C1 * n.y, RTGI_SH_COS_C1 * n.z, -RTGI_SH_COS_C1 * n.x);
        // Midpoint rule with 400x800 cells: error ~1e-5 (the kink of max(0, .) limits the order).
        for (int k = 0; k < 4; ++k) CHECK(proj[k] == doctest::Approx(lobe[k]).epsilon(1e-4).scale(1.0));
        // Irradiance of constant radiance L: <L sqrt(4 pi) Y00-projection, lobe> = pi L.
        const double L = 2.5;
        glm::dvec4 constant(0.0);
        integrateSphere(100, [&](glm::dvec3 w, double dw) { constant += L * basis(w) * dw; });
        CHECK(glm::dot(constant, lobe) == doctest::Approx(kPi * L).epsilon(1e-9));
    }
    CHECK(RTGI_SH_Y00 == doctest::Approx(basis({0, 0, 1}).x).epsilon(1e-15));
    CHECK(RTGI_SH_Y1 == doctest::Approx(basis({0, 0, 1}).z).epsilon(1e-15));
}

TEST_CASE("LPV faces: solid angles and mean directions by integration over the face; 6 x 5 faces cover 4 pi") {
    // Unit cells; source at the origin, destination centred at (0, 0, 1).
    double front, side;
    glm::dvec3 dFront, dSide;
    integrateFace({0, 0, 1.5}, {1, 0, 0}, {0, 1, 0}, front, dFront);
    integrateFace({0.5, 0, 1.0}, {0, 1, 0}, {0, 0, 1}, side, dSide);
    // 600^2 midpoint samples of a smooth integrand: relative error < 1e-6.
    CHECK(front == doctest::Approx(RTGI_LPV_FRONT_SOLID_ANGLE).epsilon(1e-6));
    CHECK(side == doctest::Approx(RTGI_LPV_SIDE_SOLID_ANGLE).epsilon(1e-6));
    CHECK(6.0 * (RTGI_LPV_FRONT_SOLID_ANGLE + 4.0 * RTGI_LPV_SIDE_SOLID_ANGLE) == doctest::Approx(4.0 * kPi).epsilon(1e-12));
    glm::dvec3 ms = glm::normalize(dSide);
    // The constants carry 7 digits.
    CHECK(ms.x == doctest::Approx(RTGI_LPV_SIDE_DIR_T).epsilon(1e-6));
    CHECK(ms.z == doctest::Approx(RTGI_LPV_SIDE_DIR_D).epsilon(1e-6));
    CHECK(std::abs(ms.y) < 1e-12);
    glm::dvec3 mf = glm::normalize(dFront);
    CHECK(mf.z == doctest::Approx(1.0).epsilon(1e-12));
}

TEST_CASE("LPV placement: whole-cell snapping, centre 30 % of the extent ahead, auto-fit holds the scene") {
    LpvSettings s;
    s.grid = {8, 4, 16};
    s.cell = 0.5f;
    Aabb scene;
    scene.grow({-10, -10, -10});
    scene.grow({10, 10, 10});
    glm::vec3 fwd(0, 0, -1);
    lpv::Placement a = lpv::placeVolume(s, scene, {1.1f, 2.2f, 3.3f}, fwd);
    lpv::Placement b = lpv::placeVolume(s, scene, {1.1f + 0.2f, 2.2f, 3.3f}, fwd);  // moved less than a cell
    for (const auto& p : {a, b})
        for (int k = 0; k < 3; ++k) CHECK(std::fmod(double(p.origin[k]) / 0.5, 1.0) == doctest::Approx(0.0).epsilon(1e-6));
    CHECK(glm::length(b.origin - a.origin) <= 0.5f + 1e-6f);
    glm::vec3 centre = a.origin + 0.5f * glm::vec3(a.grid) * a.cell;
    // Centre 30 % of the z extent (16 cells x 0.5 = 8) ahead: z = 3.3 - 2.4, within one cell of snapping.
    CHECK(std::abs(centre.z - (3.3f - 2.4f)) <= 0.5f);
    CHECK(std::abs(centre.x - 1.1f) <= 0.5f);
    // 80/20: the camera sits 20 % from the back face of the extent along the view.
    CHECK((a.origin.z + 8.0f - 3.3f) / 8.0f == doctest::Approx(0.2).epsilon(0.07));

    s.cell = 0.0f;
    Aabb bunny;
    bunny.grow({-0.09f, 0.03f, -0.06f});
    bunny.grow({0.06f, 0.18f, 0.06f});
    lpv::Placement f = lpv::placeVolume(s, bunny, {5, 5, 5}, fwd);
    Aabb box = f.box();
    for (int k = 0; k < 3; ++k) {
        CHECK(box.lo[k] <= bunny.lo[k]);
        CHECK(box.hi[k] >= bunny.hi[k]);
    }
    // The tightest axis (y: 0.15 over 4 cells) decides the cell.
    CHECK(f.cell == doctest::Approx(0.15 / 4).epsilon(2e-3));
    CHECK(lpv::historyCompatible(f, lpv::placeVolume(s, bunny, {-3, 0, 1}, {1, 0, 0})));
}

TEST_CASE("LPV uniforms: RSM texel area of an orthographic light and the constant block") {
    Aabb box;
    box.grow({0, 0, 0});
    box.grow({4, 2, 3});
    // Light straight down: the x/z footprint of the box is 4 x 3 (plus the padding of orthoLightViewProj, 1e-4 r).
    glm::mat4 vp = glm::ortho(-2.0f, 2.0f, -1.5f, 1.5f, 0.1f, 10.0f) *
                   glm::lookAt(glm::vec3(2, 5, 1.5f), glm::vec3(2, 0, 1.5f), glm::vec3(0, 0, 1));
    CHECK(lpv::rsmTexelArea(vp, 64) == doctest::Approx(12.0 / (64.0 * 64.0)).epsilon(1e-5));
    LpvSettings s;
    s.rsm = 64;
    s.strength = 2.0f;
    s.temporal = 0.5f;
    lpv::UniformInputs in;
    in.placement.cell = 0.25f;
    in.placement.grid = {3, 5, 7};
    in.rsmViewProj = vp;
    in.historyValid = true;
    in.shift = {1, -2, 0};
    gpu::LpvUniforms u = lpv::makeUniforms(s, in);
    CHECK(u.grid == glm::ivec4(3, 5, 7, 64));
    CHECK(u.rsm.y == doctest::Approx(16.0));
    CHECK(u.rsm.z == 2.0f);
    CHECK(u.temporalShift == glm::ivec4(1, -2, 0, 1));
    glm::mat4 id = u.rsmViewProj * u.rsmInvViewProj;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) CHECK(id[i][j] == doctest::Approx(i == j ? 1.0 : 0.0).epsilon(1e-5).scale(1.0));
}

TEST_CASE("LPV cascades: cells double, snapping per cascade, the coarsest holds the scene, path-length split") {
    LpvSettings s;
    s.grid = {8, 8, 8};
    s.cell = 0.25f;
    glm::vec3 fwd(0.3f, -0.2f, -1.0f);
    const int C = 3;
    // No scene bounds: nothing clamps, each cascade follows the camera.
    auto a = lpv::placeCascades(s, C, Aabb{}, {1.3f, 2.1f, -0.7f}, fwd);
    REQUIRE(a.size() == std::size_t(C));
    for (int i = 0; i < C; ++i) {
        CHECK(a[std::size_t(i)].cell == doctest::Approx(0.25 * double(1 << i)));
        for (int k = 0; k < 3; ++k)
            CHECK(double(a[std::size_t(i)].origin[k]) ==
                  doctest::Approx(double(a[std::size_t(i)].originCells[k]) * a[std::size_t(i)].cell).epsilon(1e-6));
    }
    // A camera move smaller than a fraction of the finest cell, away from any snapping boundary,
    // changes no cascade; a move by exactly one cell of cascade i shifts cascade i by one cell.
    for (int i = 0; i < C; ++i) {
        float si = a[std::size_t(i)].cell;
        // Put the camera in the middle of a finest-cell snapping interval first.
        glm::vec3 cam(1.3f, 2.1f, -0.7f);
        auto base = lpv::placeCascades(s, C, Aabb{}, cam, fwd);
        auto small = lpv::placeCascades(s, C, Aabb{}, cam + glm::vec3(1e-4f, 0, 0), fwd);
        auto moved = lpv::placeCascades(s, C, Aabb{}, cam + glm::vec3(si, 0, 0), fwd);
        for (int j = 0; j < C; ++j) CHECK(small[std::size_t(j)].originCells == base[std::size_t(j)].originCells);
        glm::ivec3 d = moved[std::size_t(i)].originCells - base[std::size_t(i)].originCells;
        CHECK(d == glm::ivec3(1, 0, 0));
    }
    // lpv.cell = 0: the coarsest cascade holds the scene bounds wherever the camera is.
    s.cell = 0.0f;
    Aabb scene;
    scene.grow({-3, 0, -2});
    scene.grow({4, 5, 6});
    for (glm::vec3 cam : {glm::vec3(0, 2, 20), glm::vec3(-2.9f, 0.1f, -1.9f), glm::vec3(100, -50, 3)}) {
        auto p = lpv::placeCascades(s, C, scene, cam, fwd);
        Aabb box = p.back().box();
        for (int k = 0; k < 3; ++k) {
            CHECK(box.lo[k] <= scene.lo[k]);
            CHECK(box.hi[k] >= scene.hi[k]);
        }
        CHECK(p[1].cell == doctest::Approx(2.0 * p[0].cell));
    }
    // Path-length split (docs/lpv.md): cascade i - 1 covers paths [0, (n + 1) s_{i-1}) =
    // [0, t s_i) with t = (n + 1) / 2; the near weights of cascade i's steps cover exactly
    // that length (in units of s_i), and each step is fully near or far except one.
    for (int n : {1, 2, 3, 8, 9, 16, 64}) {
        double covered = 0;
        int partial = 0;
        for (int k = 0; k <= n; ++k) {
            double w = lpv::cascadeNearWeight(k, n);
            covered += w;
            partial += w > 0 && w < 1;
        }
        CHECK(covered == doctest::Approx(0.5 * (n + 1)));
        CHECK(partial == (n % 2 == 0 ? 1 : 0));
    }
}
