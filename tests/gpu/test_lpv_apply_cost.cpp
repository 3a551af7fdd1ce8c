// lpv.apply's exact shortcuts and merged stencil fetches (docs/lpv.md, "Apply cost"): the frame's
// indirect diffuse and LPV specular outputs equal those of the apply before them (its source kept
// only for this test, tests/gpu/shaders/compute/lpv/apply.comp, loaded through RTGI_DATA_DIR) with the
// defaults that exercise every shortcut: two cascades (pixels outside the finer one, inside it, and
// in the blend), the visibility-moment lookup, sky visibility, the self-illumination correction,
// LPV specular. The independent oracles of the apply (CPU double) are in test_lpv_cascades.cpp and
// test_lpv_leaks.cpp.
#include "gpu_fixture.h"

#include <cstdlib>

using namespace rtgi;
using namespace rtgi::test;

namespace {
// The floor and wall under an oblique sun; the LPV on at 8^3 with the other defaults, no AO.
Scene sunlitCorner() {
    Scene scene = floorAndWallScene();
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = -glm::normalize(glm::vec3(0.4f, 1.0f, 0.7f));
    sun.intensity = 3.0f;
    scene.lights.push_back(sun);
    return scene;
}
Settings smallLpv() {
    Settings s;
    s.ao.variant = AoSettings::Variant::Off;
    s.lpv.mode = Toggle::On;
    s.lpv.grid = glm::ivec3(8);
    s.lpv.rsm = 64;
    s.light.shadowSize = 256;
    return s;
}
}  // namespace

TEST_CASE("LPV apply: the optimized apply equals the apply before the shortcuts on a two-cascade frame") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    // The floor and wall under an oblique sun, a camera that sees both near and far floor.
    Scene scene = sunlitCorner();
    scene.cameras[0].position = {0.6f, 0.8f, 1.9f};
    scene.cameras[0].target = {-0.4f, 0.2f, -0.9f};
    Settings s = smallLpv();  // the defaults: 2 cascades, lookup=visibility, sky=visibility, self-correction on
    s.lpv.specular = Toggle::On;
    REQUIRE(s.lpv.cascades == 2);
    REQUIRE(s.lpv.lookup == LpvSettings::Lookup::Visibility);
    REQUIRE(s.lpv.sky == LpvSettings::Sky::Visibility);
    REQUIRE(s.lpv.selfCorrection);
    const glm::ivec2 size{64, 40};
    auto frame = [&](bool before) {
        const std::string dir = std::string(RTGI_SOURCE_DIR) + "/tests/gpu/shaders";
        if (before) setenv("RTGI_DATA_DIR", dir.c_str(), 1);
        auto r = renderFrames(scene, s, size, prof);
        if (before) unsetenv("RTGI_DATA_DIR");
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
        return std::make_pair(readTexture(r->resources().indirectDiffuse), readTexture(r->resources().specular));
    };
    auto [diffuseNew, specularNew] = frame(false);
    auto [diffuseOld, specularOld] = frame(true);
    // fp16 outputs (2^-11 relative each) of sums that may round differently in the last float bit
    // (U T instead of u N + U (T - N) where u = U; float atomics of the injection in another
    // order between the two frames): 2^-10 relative plus 1e-6 of the image's peak.
    auto compare = [&](const FloatImage& a, const FloatImage& b, const char* what) {
        double peak = 0.0, worst = 0.0;
        int nonZero = 0;
        for (int y = 0; y < size.y; ++y)
            for (int x = 0; x < size.x; ++x)
                for (int c = 0; c < 3; ++c) peak = std::max(peak, double(std::abs(b.at(x, y, c))));
        for (int y = 0; y < size.y; ++y)
            for (int x = 0; x < size.x; ++x)
                for (int c = 0; c < 4; ++c) {
                    double u = a.at(x, y, c), v = b.at(x, y, c);
                    double tol = std::ldexp(std::abs(v), -10) + 1e-6 * peak;
                    worst = std::max(worst, std::abs(u - v) / tol);
                    if (c < 3 && v > 0.0) ++nonZero;
                    CHECK(std::abs(u - v) <= tol);
                }
        MESSAGE(std::string(what) << ": peak " << peak << ", " << nonZero << " lit channels, worst difference / bound " << worst);
        CHECK(peak > 0.0);
        CHECK(nonZero > size.x * size.y / 4);
    };
    compare(diffuseNew, diffuseOld, "indirect diffuse (rgb, alpha: sky visibility)");
    compare(specularNew, specularOld, "LPV specular");
}

TEST_CASE("LPV frame: joint cascade propagation gives the frame of one propagation dispatch per cascade") {
    // The composed passes (inject, pack, geometry, propagate, apply) with the defaults, once with
    // lpv.propagate_cascades=joint and once separate: the same indirect light (docs/lpv.md, "Joint
    // cascade propagation"; the volumes' own equality test is in test_lpv_volumes.cpp). fp16 volumes
    // and outputs: 2^-9 relative (a half-precision ulp of a step may differ) plus 1e-6 of the peak.
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = sunlitCorner();
    Settings s = smallLpv();
    REQUIRE_FALSE(s.lpv.jointCascades);  // the default (separate: joint measured slower on the device)
    const glm::ivec2 size{64, 40};
    auto frame = [&](bool joint) {
        Settings t = s;
        t.lpv.jointCascades = joint;
        auto r = renderFrames(scene, t, size, prof);
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
        return readTexture(r->resources().indirectDiffuse);
    };
    FloatImage a = frame(true), b = frame(false);
    double peak = 0.0;
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x)
            for (int c = 0; c < 3; ++c) peak = std::max(peak, double(b.at(x, y, c)));
    REQUIRE(peak > 0.0);
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x)
            for (int c = 0; c < 4; ++c)
                CHECK(std::abs(a.at(x, y, c) - b.at(x, y, c)) <= std::ldexp(std::abs(b.at(x, y, c)), -9) + 1e-6 * peak);
}
