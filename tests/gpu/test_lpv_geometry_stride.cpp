// lpv.geometry_stride (docs/lpv.md, "Geometry injection stride"): the blocking potential injected
// from the G-buffer with every fourth pixel in x and y (each sample's surfel 16 pixels) against
// every second one (4 pixels), on a plane seen head-on, both against its analytic visible area.
#include "lpv_test_util.h"

#include "render/lpv/lpv_volumes.h"

#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

TEST_CASE("LPV geometry injection stride 4 equals stride 2 on a head-on plane within the documented bound") {
    GpuFixture gpu;
    // A wall at z = 0 facing +z (albedo 0.5) filling the view from (0, 1, 3): linear depth 3 everywhere.
    Scene scene = headOnWallScene(0.5f);
    const Camera cam = scene.cameras[0];
    const glm::ivec2 size(192, 128);  // multiples of 4: both strides cover the image exactly
    gl::Profiler prof(false);
    Settings s = smallLpvSettings();
    s.lpv.mode = Toggle::Off;  // the frame is the G-buffer; the injection runs here
    auto r = renderFrames(scene, s, size, prof);
    FrameResources& res = r->resources();
    // A 6 x 4 x 2 grid of unit cells whose corner lattice holds the visible part of the wall (x in
    // +-2.6, y in 1 +- 1.73; corners take [-3.5, 3.5] x [-1.5, 3.5]), the wall on the corner plane z = 1.
    const glm::ivec3 grid(6, 4, 2);
    const double cell = 1.0;
    gpu::LpvUniforms u = placedUniforms(s.lpv, grid, float(cell), {-3.0f, -1.0f, -1.0f});
    gl::MemoryLedger ledger;
    gl::ProgramCache programs;
    gl::Buffer ubo(ledger, "t.lpv.uniforms", sizeof(u), &u);
    lpv::Rsm noRsm;
    auto inject = [&](int stride) {
        lpv::Volumes v;
        v.ensureLight(ledger, grid, GL_RGBA32F);
        v.ensureGeometry(ledger, false);
        lpv::GBufferView g{&res.gbuffer.linearDepth, &res.gbuffer.normal, &res.gbuffer.albedo, &res.gbuffer.material,
                           size, stride};
        lpv::injectGeometry(programs, ubo, noRsm, 0, g, v);
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
        glm::ivec3 d = grid + 1;
        std::vector<glm::vec4> px(std::size_t(d.x * d.y * d.z));
        glGetTextureImage(v.geometry.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(px.size() * sizeof(glm::vec4)), px.data());
        std::vector<double> a;  // Y00 of the blocking SH / (c0 / s^2): the surfel area at each corner
        const double c0 = std::sqrt(M_PI) / 2.0, s2 = cell * cell;
        for (auto& p : px) a.push_back(double(p.x) * s2 / c0);
        return a;
    };
    const std::vector<double> a2 = inject(2), a4 = inject(4);
    // Oracle: the visible part of the wall, (2 d tan(fov/2))^2 * aspect (a plane facing the camera at
    // linear depth d; docs/lpv.md, "Sky bounce": a pixel covers p^2 cos(theta) / cos(V) of a surface, and
    // for a head-on plane cos(V) = cos(theta)); the strides sample this smooth field on 2x2 and 4x4 blocks.
    const double d = 3.0, t = std::tan(double(cam.fovY) / 2.0), p = 2.0 * d * t / size.y, aspect = double(size.x) / size.y;
    const double total = (2.0 * d * t) * (2.0 * d * t) * aspect;
    double cosMin = 1.0;
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
            double nx = ((x + 0.5) / size.x * 2.0 - 1.0) * t * aspect, ny = ((y + 0.5) / size.y * 2.0 - 1.0) * t;
            cosMin = std::min(cosMin, 1.0 / std::sqrt(1.0 + nx * nx + ny * ny));
        }
    double sum2 = 0.0, sum4 = 0.0, l1 = 0.0;
    for (std::size_t i = 0; i < a2.size(); ++i) {
        sum2 += a2[i];
        sum4 += a4[i];
        l1 += std::abs(a4[i] - a2[i]);
    }
    // Totals: every pixel's footprint is p^2 exactly here, so both strides sum to the visible area.
    MESSAGE("surfel area: CPU " << total << ", stride 2 " << sum2 << ", stride 4 " << sum4 << ", L1 over corners "
                                << l1);
    CHECK(sum2 == doctest::Approx(total).epsilon(0.01));
    CHECK(sum4 == doctest::Approx(total).epsilon(0.01));
    // Per corner: a sample's whole block goes to the corner of its first pixel, so area within s - 1
    // pixels of a corner-cell border (lines at half-cell offsets, L_total long in the view) can move
    // to the neighbour: sum |a4 - a2| <= (3 + 1) p L_total / cos_min + |sum4 - sum2|.
    const double wv = 2.0 * d * t * aspect, hv = 2.0 * d * t;
    const double lTotal = (std::floor(wv / cell) + 1.0) * hv + (std::floor(hv / cell) + 1.0) * wv;
    const double bound = 4.0 * p * lTotal / cosMin + std::abs(sum4 - sum2);
    MESSAGE("L1 bound " << bound << " (" << bound / total << " of the total)");
    CHECK(l1 <= bound);
    CHECK(l1 > 0.0);  // the strides do sample differently (a test that cannot fail would not)
}
