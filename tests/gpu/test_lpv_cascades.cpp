// Cascaded LPV through the whole renderer (docs/lpv.md "Cascades"): the
// irradiance across a cascade border (seam) and the snapping of every
// cascade's volume to its own cells when the camera moves.
#include "gpu_fixture.h"
#include "render/lpv/lpv_math.h"

#include <glm/gtx/component_wise.hpp>

#include <algorithm>
#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const double kPi = 3.14159265358979323846;

// A 6 m sunlit floor with a 2 m wall at its far end facing the camera, lit by
// the same sun: the wall's reflected light falls off along the floor.
Scene wallAndFloor() {
    Scene s = floorScene(3.0f, glm::vec3(0.6f), true, glm::normalize(glm::vec3(0.2f, 1.0f, 0.9f)), 3.0f);
    Material w;
    w.baseColor = glm::vec4(0.8f, 0.5f, 0.3f, 1.0f);
    w.roughness = 1.0f;
    s.materials.push_back(w);
    addQuad(s, {-3.0f, 0.0f, -2.5f}, {3.0f, 0.0f, -2.5f}, {3.0f, 2.0f, -2.5f}, {-3.0f, 2.0f, -2.5f}, 1);
    s.cameras[0].position = {0.0f, 2.5f, 3.5f};
    s.cameras[0].target = {0.0f, 0.0f, -1.5f};
    return s;
}

Settings cascadeSettings() {
    Settings s;
    s.ao.variant = AoSettings::Variant::Off;  // the lookup along the G-buffer normal
    s.lpv.mode = Toggle::On;
    s.lpv.grid = glm::ivec3(8);
    s.lpv.cell = 0.5f;  // cascade 0: 4 m, cascade 1: 8 m (holds the 6 m scene)
    s.lpv.rsm = 128;
    s.lpv.format = LpvSettings::Format::Rgba32f;
    s.light.shadowSize = 256;
    return s;  // the rest: the defaults (2 cascades, 8 iterations, flow, conserving, self-correction)
}

// Cells from the lookup point to the nearest face of placement p's box (< 0 outside).
double insideCells(const lpv::Placement& p, glm::dvec3 q) {
    glm::dvec3 c = (q - glm::dvec3(p.origin)) / double(p.cell);
    glm::dvec3 g(p.grid);
    return std::min(glm::compMin(c), glm::compMin(g - c));
}

}  // namespace

TEST_CASE("LPV cascades: irradiance along a line across a cascade border steps no more than inside a cascade") {
    // docs/lpv.md "Seam". Floor pixels of one image column form a line along z that crosses
    // cascade 0's border. E = indirect / (albedo/π) per pixel; the weight of cascade 0 at a
    // lookup point is w_0 = clamp((d − ½)/2, 0, 1), d its distance in cells to cascade 0's
    // faces. Steps |E(j+1) − E(j)| between neighbouring pixels are split into "inside" (both
    // pixels with w_0 = 1, or both with w_0 = 0) and "border" (any other pair). Bound: the
    // largest border step is at most the largest inside step (the issue's "no step larger
    // than the variation inside a cascade"). A hard switch between the cascades (blend width
    // → 0) puts their whole disagreement into one step and fails it (docs/lpv.md).
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = wallAndFloor();
    Settings s = cascadeSettings();
    const glm::ivec2 size{16, 160};
    auto r = renderFrames(scene, s, size, prof);
    FloatImage ind = readTexture(r->resources().indirectDiffuse), depth = readTexture(r->resources().gbuffer.linearDepth),
               albedo = readTexture(r->resources().gbuffer.albedo);
    Camera cam = resolveCamera(scene, s);
    std::vector<lpv::Placement> pl =
        lpv::placeCascades(s.lpv, s.lpv.cascades, scene.bounds(), cam.position, glm::normalize(cam.target - cam.position));
    REQUIRE(pl.size() == 2);
    const glm::dvec3 up(0, 1, 0);
    struct Sample {
        double e[3], w0;
    };
    std::vector<Sample> line;
    const int x = size.x / 2;
    for (int y = 0; y < size.y; ++y) {
        double d = depth.at(x, y, 0);
        if (!(d > 0)) continue;
        glm::dvec3 p = worldPosition(scene, s, size, depth, x, y);
        if (std::abs(p.y) > 1e-3 || p.z < -2.3) continue;  // floor pixels, not at the wall's foot
        // Not within half a cell of the coarsest cascade's own border (no light beyond it).
        if (insideCells(pl[1], p + 0.5 * double(pl[1].cell) * up) < 0.5) continue;
        Sample smp{};
        for (int c = 0; c < 3; ++c) smp.e[c] = ind.at(x, y, c) / (albedo.at(x, y, c) / kPi);
        double d0 = insideCells(pl[0], p + 0.5 * double(pl[0].cell) * up);
        smp.w0 = std::clamp((d0 - 0.5) / double(lpv::kCascadeBlendCells), 0.0, 1.0);
        line.push_back(smp);
    }
    REQUIRE(line.size() > 60);
    double inside = 0, border = 0, eMax = 0;
    int insideFine = 0, insideCoarse = 0, borderPairs = 0;
    for (std::size_t j = 0; j + 1 < line.size(); ++j) {
        const Sample &a = line[j], &b = line[j + 1];
        double step = 0;
        for (int c = 0; c < 3; ++c) {
            step = std::max(step, std::abs(b.e[c] - a.e[c]));
            eMax = std::max(eMax, a.e[c]);
        }
        if (a.w0 == 1.0 && b.w0 == 1.0) {
            inside = std::max(inside, step);
            ++insideFine;
        } else if (a.w0 == 0.0 && b.w0 == 0.0) {
            inside = std::max(inside, step);
            ++insideCoarse;
        } else {
            border = std::max(border, step);
            ++borderPairs;
        }
    }
    MESSAGE("seam: " << line.size() << " floor pixels, pairs inside cascade 0 " << insideFine << ", inside cascade 1 "
                     << insideCoarse << ", across the border " << borderPairs << "; largest step inside " << inside
                     << ", across " << border << " (max E " << eMax << ")");
    REQUIRE(insideFine > 5);
    REQUIRE(insideCoarse > 5);
    REQUIRE(borderPairs > 3);
    CHECK(eMax > 0.0);
    CHECK(border <= inside);
}
