// Radiometric calibration of LPV against the path tracer (issue 3: "LPV
// indirect light radiometrically comparable to a path-traced one-bounce
// indirect irradiance"): a sunlit white floor lights a perpendicular white
// wall; LPV's res.indirectDiffuse on the wall against ref.path with
// reference=indirect, reference.bounces=1 (light that bounced once, at the
// floor). The expected band of the ratio is derived in docs/lpv.md
// ("Calibration against the path tracer").
#include "gpu_fixture.h"

#include "render/reference/reference_passes.h"

#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const glm::ivec2 kSize{48, 32};

// Floor [-2,2]^2 at y = 0 (albedo 0.6), wall z = 0, x in [-2,2], y in [0,1.5] facing +z
// (the floor continues behind it); sun straight down: the floor is lit
// uniformly, the wall (edge-on to the sun) only indirectly.
Scene wallScene() {
    Scene s = floorScene(2.0f, glm::vec3(0.6f), true, {0, 1, 0}, 1.0f);
    s.name = "test:lpv-calibration";
    addQuad(s, {-2, 0, 0}, {2, 0, 0}, {2, 1.5f, 0}, {-2, 1.5f, 0}, 0);
    s.cameras[0].position = {0, 0.8f, 2.2f};
    s.cameras[0].target = {0, 0.6f, 0};
    return s;
}

// One volume of 16^3 auto-fit cells (4 m / 16 = 0.25 m, the floor on a cell boundary), fp32,
// occlusion and bounce off (one bounce, as the reference), KD10's face re-emission.
Settings wallLpv(int iterations) {
    Settings ls;
    ls.lpv.mode = Toggle::On;
    ls.lpv.grid = glm::ivec3(16);
    ls.lpv.iterations = iterations;
    ls.lpv.rsm = 64;
    ls.lpv.format = LpvSettings::Format::Rgba32f;
    ls.lpv.cascades = 1;
    ls.lpv.reemit = LpvSettings::Reemit::Face;
    ls.lpv.occlusion = ls.lpv.bounce = false;
    ls.lpv.specular = Toggle::Off;
    ls.light.shadowSize = 256;
    return ls;
}

}  // namespace

TEST_CASE("LPV calibration: wall lit by a sunlit floor, LPV indirect vs path-traced one-bounce indirect") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = wallScene();

    Settings ls = wallLpv(16);  // 16 iterations: light crosses the whole grid; the derivation below is for
                                // one volume and KD10's face re-emission

    Settings rs = oneBounceReference(Settings{}, 64);

    auto ref = renderFrames(scene, rs, kSize, prof);
    auto* out = dynamic_cast<ReferenceOutput*>(ref->findPass("ref.path"));
    REQUIRE(out != nullptr);
    FloatImage refMean = readTexture(out->mean()), refSe = readTexture(out->standardError());
    FloatImage depth = readTexture(ref->resources().gbuffer.linearDepth);

    for (bool conserving : {false, true}) {
        ls.lpv.energyConserving = conserving;
        auto lpvRun = renderFrames(scene, ls, kSize, prof);
        FloatImage lpvImg = readTexture(lpvRun->resources().indirectDiffuse);
        // Receivers: wall pixels between one cell above the floor and 1.2 m, |x| <= 1.
        double sumLpv = 0, sumRef = 0, var = 0;
        int n = 0;
        for (int y = 0; y < kSize.y; ++y)
            for (int x = 0; x < kSize.x; ++x) {
                if (!(depth.at(x, y, 0) > 0)) continue;
                glm::dvec3 p = worldPosition(scene, rs, kSize, depth, x, y);
                if (std::abs(p.z) > 1e-2 || p.y < 0.25 || p.y > 1.2 || std::abs(p.x) > 1.0) continue;
                sumLpv += lpvImg.at(x, y, 0);
                sumRef += refMean.at(x, y, 0);
                var += double(refSe.at(x, y, 0)) * refSe.at(x, y, 0);
                ++n;
            }
        REQUIRE(n > 100);
        double ratio = sumLpv / sumRef;
        double relSe = std::sqrt(var) / sumRef;
        std::string mode = conserving ? "on" : "off";
        MESSAGE("LPV / path-traced (one bounce) on the wall, lpv.energy_conserving=" << mode << ": " << ratio
                                                                                 << " (reference rel. SE " << relSe
                                                                                 << ", " << n << " pixels)");
        CHECK(relSe < 0.02);  // 64 paths x ~300 pixels: the reference mean is good to ~1 %
        // docs/lpv.md, "Calibration": the normalization makes a cosine stream crossing a layer
        // count 2 cell lengths, as the true one does; the scheme moves light one cell per step but
        // only 0.402 of the flux upwards in the first step (the rest sideways, none down), less
        // for the broadened lobes after, so a layer is visited >= 1/0.402 = 2.49 times per
        // crossing: derived lower bound 2.49 / 2 = 1.24. The upper bound is a margin, not
        // derived (measured 1.66 conserving, 1.89 classic): 2.0 conserving, 2.3 classic.
        CHECK(ratio >= 1.24);
        CHECK(ratio <= (conserving ? 2.0 : 2.3));
    }
}

TEST_CASE("LPV self-illumination: the sunlit floor receives no one-bounce light from itself once corrected") {
    // One bounce: the wall is edge-on to the sun and the floor cannot see itself, so the
    // path-traced indirect light on the floor is 0. Every bit of LPV light there is the
    // scheme lighting the floor with its own injection (docs/lpv.md, "Self-illumination").
    // lpv::planeSelfIrradiance models exactly that for an infinite uniformly lit plane
    // lying on a cell boundary (as the floor does here), so away from the floor's edges
    // the correction must remove nearly all of it; the residual comes from the floor's
    // finite extent (2 m = 8 cells from the probed region to an edge, light spreads 8
    // cells in 8 steps) and from the wall's cells.
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = wallScene();
    Settings ls = wallLpv(8);
    Settings depthOnly = ls;
    auto probe = renderFrames(scene, depthOnly, kSize, prof);
    FloatImage depth = readTexture(probe->resources().gbuffer.linearDepth);
    for (auto reemit : {LpvSettings::Reemit::Face, LpvSettings::Reemit::Flow}) {
        double mean[2] = {0, 0};
        for (int corrected = 0; corrected < 2; ++corrected) {
            ls.lpv.reemit = reemit;
            ls.lpv.selfCorrection = corrected == 1;
            auto run = renderFrames(scene, ls, kSize, prof);
            FloatImage img = readTexture(run->resources().indirectDiffuse);
            double sum = 0;
            int n = 0;
            for (int y = 0; y < kSize.y; ++y)
                for (int x = 0; x < kSize.x; ++x) {
                    if (!(depth.at(x, y, 0) > 0)) continue;
                    glm::dvec3 p = worldPosition(scene, ls, kSize, depth, x, y);
                    if (std::abs(p.y) > 1e-2 || p.z < 0.5 || p.z > 1.5 || std::abs(p.x) > 1.0) continue;
                    sum += img.at(x, y, 0);
                    ++n;
                }
            REQUIRE(n > 50);
            mean[corrected] = sum / n;
        }
        MESSAGE("floor LPV indirect (truth 0), reemit " << (reemit == LpvSettings::Reemit::Flow ? "flow" : "face")
                                                        << ": " << mean[0] << " uncorrected, " << mean[1]
                                                        << " corrected");
        // The sun's floor radiance is 0.6 / pi * 1: self-illumination is a sizeable fraction of it.
        CHECK(mean[0] > 0.02);
        CHECK(mean[1] <= 0.2 * mean[0]);
    }
}
