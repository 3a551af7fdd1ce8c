// lpv.apply_resolution=half (docs/lpv.md, "Half-resolution apply"): the half-resolution apply
// plus lpv/upsample.comp against the full-resolution apply (whose own oracle tests are in
// test_lpv_scene.cpp and test_lpv_cascades.cpp) on analytic cases: a wall facing the camera
// under a linear field (bilinear upsampling reproduces it exactly), a second wall in front of
// half of it (a depth edge that must not bleed), and a floor meeting a wall (a concave crease whose
// half texels must shade points of the room).
#include "gpu_fixture.h"

#include "render/lpv/lpv_math.h"
#include "render/lpv/lpv_volumes.h"

#include <algorithm>
#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

// A wall at z = 0 facing +z (albedo 0.5), seen head-on from (0, 1, 3): every visible point has the
// same depth, so world positions, the lookup points and a field linear in them are linear in the
// pixel coordinates. `front`: a second wall at z = 1 over edgeX < x < edgeX2 (depth 2 instead of 3).
// An empty scene with one material, grey (albedo 0.5) and rough.
Scene greyScene(const char* name) {
    Scene s;
    s.name = name;
    Material m;
    m.baseColor = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
    m.roughness = 1.0f;
    s.materials.push_back(m);
    return s;
}

Scene wallScene(bool front, float edgeX, float edgeX2 = 4.0f) {
    Scene s = greyScene("test:wall");
    addQuad(s, {-4, -3, 0}, {4, -3, 0}, {4, 5, 0}, {-4, 5, 0}, 0);
    if (front) addQuad(s, {edgeX, -3, 1}, {edgeX2, -3, 1}, {edgeX2, 5, 1}, {edgeX, 5, 1}, 0);
    Camera c;
    c.position = {0, 1, 3};
    c.target = {0, 1, 0};
    c.fovY = glm::radians(60.0f);
    c.near = 0.1f;
    c.far = 50.0f;
    s.cameras.push_back(c);
    return s;
}

// R, G, B volumes whose Y00 coefficient is linear in the cell index, a + b . (i, j, k) (per
// colour scaled by k_c), band 1 a constant lobe: trilinear lookups inside the grid are exact.
lpv::Rgb linearVolume(gl::MemoryLedger& ledger, glm::ivec3 grid, double a, glm::dvec3 b) {
    const double kc[3] = {1.0, 0.7, 0.4};
    lpv::Rgb v;
    for (int c = 0; c < 3; ++c) {
        gl::Texture t(ledger, "t.volume", {GL_TEXTURE_3D, GL_RGBA32F, grid.x, grid.y, grid.z});
        t.setSampling(GL_LINEAR, GL_LINEAR);
        std::vector<glm::vec4> data;
        for (int z = 0; z < grid.z; ++z)
            for (int y = 0; y < grid.y; ++y)
                for (int x = 0; x < grid.x; ++x) {
                    double c00 = kc[c] * (a + glm::dot(b, glm::dvec3(x, y, z)));
                    data.push_back(glm::vec4(float(c00), 0.1f * float(kc[c]), -0.2f * float(kc[c]), 0.05f));
                }
        glTextureSubImage3D(t.id(), 0, 0, 0, 0, grid.x, grid.y, grid.z, GL_RGBA, GL_FLOAT, data.data());
        v[std::size_t(c)] = std::move(t);
    }
    return v;
}

struct Outputs {
    FloatImage full, half, depth, lowGeometry;
};

// The full-resolution apply and the half-resolution apply + upsample of `volume` on the scene's
// G-buffer.
Outputs applyBoth(const Scene& scene, glm::ivec2 size, double a, glm::dvec3 b, lpv::Placement* placed = nullptr) {
    gl::Profiler prof(false);
    Settings s = smallLpvSettings();
    s.lpv.mode = Toggle::Off;  // no light in the scene: the frame is the G-buffer, the volume is made here
    s.lpv.format = LpvSettings::Format::Rgba32f;
    s.lpv.specular = Toggle::Off;
    s.lpv.occlusion = s.lpv.bounce = false;
    auto r = renderFrames(scene, s, size, prof);  // G-buffer + frame uniforms (binding 0 stays bound)
    FrameResources& res = r->resources();
    Camera cam = resolveCamera(scene, s);
    lpv::Placement pl = lpv::placeVolume(s.lpv, scene.bounds(), cam.position, glm::normalize(cam.target - cam.position));
    if (placed) *placed = pl;
    gl::MemoryLedger ledger;
    gl::ProgramCache programs;
    lpv::Rgb volume = linearVolume(ledger, pl.grid, a, b);
    lpv::UniformInputs in;
    in.placement = pl;
    gpu::LpvUniforms u = lpv::makeUniforms(s.lpv, in);
    gl::Buffer ubo(ledger, "t.lpv.uniforms", sizeof(u), &u);
    const lpv::GBufferView g{&res.gbuffer.linearDepth, &res.gbuffer.normal, &res.gbuffer.albedo, &res.gbuffer.material,
                             size};
    gl::Texture full(ledger, "t.indirect.full", {GL_TEXTURE_2D, GL_RGBA16F, size.x, size.y});
    gl::Texture half(ledger, "t.indirect.half", {GL_TEXTURE_2D, GL_RGBA16F, size.x, size.y});
    gl::Texture low(ledger, "t.low", lpv::applyLowDesc(size));
    gl::Texture lowGeometry(ledger, "t.low.geometry", lpv::applyLowGeometryDesc(size));
    lpv::ApplyInputs ai;
    ai.gbuffer = g;
    ai.volume = &volume;
    ai.indirect = &full;
    lpv::applyCompute(programs, ubo, ai);
    ai.indirect = &low;
    ai.lowGeometry = &lowGeometry;
    lpv::applyCompute(programs, ubo, ai);
    lpv::UpsampleInputs up;
    up.gbuffer = g;
    up.lowIndirect = &low;
    up.lowGeometry = &lowGeometry;
    up.indirect = &half;
    lpv::applyUpsample(programs, ubo, up);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    return {readTexture(full), readTexture(half), readTexture(res.gbuffer.linearDepth), readTexture(lowGeometry)};
}

// fp16 outputs: the full path rounds once, the half path twice (its low texels and the upsampled
// value), 2^-11 relative each; plus the sampler's fixed-point interpolation weights (2^-8 of the
// change per cell along each axis, as in the cascade apply test), for both paths.
double smoothBound(double value, double perCell) { return 3.0 * std::ldexp(std::abs(value), -11) + 2.0 * std::ldexp(perCell, -8); }

}  // namespace

TEST_CASE("LPV half-resolution apply: upsampled equals the full-resolution apply on a linear field") {
    GpuFixture gpu;
    const glm::ivec2 size{32, 24};
    Scene scene = wallScene(false, 0.0f);
    lpv::Placement pl;
    const double a = 2.0;
    const glm::dvec3 b(0.15, -0.1, 0.05);
    Outputs o = applyBoth(scene, size, a, b, &pl);
    // E = sqrt(pi)/2 c00 + band 1 (constant); outgoing albedo/pi E / s^2: the change per cell of
    // the output along each axis, summed (the sampler's weight rounding acts on all three).
    const double perCell = 0.5 / 3.14159265358979 * 0.886226925 * (std::abs(b.x) + std::abs(b.y) + std::abs(b.z)) / (pl.cell * pl.cell);
    int checked = 0;
    double worst = 0.0;
    for (int y = 1; y < size.y - 1; ++y)
        for (int x = 1; x < size.x - 1; ++x) {  // the outer pixels extrapolate: their taps are clamped
            REQUIRE(o.depth.at(x, y, 0) > 0.0f);
            for (int c = 0; c < 3; ++c) {
                double f = o.full.at(x, y, c), h = o.half.at(x, y, c);
                REQUIRE(f > 0.0);
                double bound = smoothBound(f, perCell);
                CHECK(std::abs(h - f) <= bound);
                worst = std::max(worst, std::abs(h - f) / bound);
            }
            ++checked;
        }
    MESSAGE("worst |half - full| / bound: " << worst);
    CHECK(checked == (size.x - 2) * (size.y - 2));
    // The field is not constant on the image (the comparison is not vacuous): the output spans
    // more than 20 times the bound between the corners.
    CHECK(std::abs(o.full.at(1, 1, 0) - o.full.at(size.x - 2, size.y - 2, 0)) > 20.0 * smoothBound(o.full.at(1, 1, 0), perCell));
}

TEST_CASE("LPV half-resolution apply: no bleeding across a depth edge (full-resolution apply on either side)") {
    // The near wall's lookups read light 1 cell further along z than the far wall's: with the
    // field's strong z gradient the two sides differ by a factor of ~4. Bound of the bleed (docs/lpv.md,
    // "Half-resolution apply"): along a straight edge a pixel's same-side taps carry >= 1/4 of the
    // bilinear weight, at relative depth difference 0 (planes), the other side's at r >= 1/3
    // (depths 2 and 3): a weight share <= (3/4) / (1e-3 + 1/3) / ((1/4) / 1e-3) = 0.009 of the
    // difference between the sides; plain bilinear upsampling would take 1/4 to 3/4 of it.
    GpuFixture gpu;
    const glm::ivec2 size{32, 24};
    for (float edgeX : {0.0f, 0.07f}) {  // the edge between two low texels, and through one
        CAPTURE(edgeX);
        Scene scene = wallScene(true, edgeX);
        lpv::Placement pl;
        const double a = -9.5;  // far wall: Y00 ~ 1 (lookup at cell coordinate z = 4), near wall ~ 4 (z = 5)
        const glm::dvec3 b(0.05, -0.03, 3.0);
        Outputs o = applyBoth(scene, size, a, b, &pl);
        const double perCell = 0.5 / 3.14159265358979 * 0.886226925 * (std::abs(b.x) + std::abs(b.y) + std::abs(b.z)) / (pl.cell * pl.cell);
        // Next to the edge the renormalized weights take the same side's taps alone: a one-sided
        // interpolation whose taps lie up to 1.5 pixels away, so the field's change over 1.5 pixels
        // (the far wall's pixels, the larger, at depth 3) is added.
        const double pixelCells = 3.0 * 2.0 * std::tan(glm::radians(30.0)) / double(size.y) / pl.cell;
        const double oneSided =
            1.5 * pixelCells * 0.5 / 3.14159265358979 * 0.886226925 * (std::abs(b.x) + std::abs(b.y)) / (pl.cell * pl.cell);
        int edgePixels = 0, checked = 0;
        for (int y = 1; y < size.y - 1; ++y)
            for (int x = 1; x < size.x - 1; ++x) {
                // The difference between the sides near this pixel (full resolution): the largest
                // |full(q) - full(p)| over the 5x5 neighbours on the other side (a pixel's taps are the
                // half texels of the pixels within 2 of it).
                const float dp = o.depth.at(x, y, 0);
                REQUIRE(dp > 0.0f);
                double contrast[3] = {0, 0, 0};
                bool nearEdge = false;
                for (int j = -2; j <= 2; ++j)
                    for (int i = -2; i <= 2; ++i) {
                        if (x + i < 0 || y + j < 0 || x + i >= size.x || y + j >= size.y) continue;
                        const float dq = o.depth.at(x + i, y + j, 0);
                        if (std::abs(dq - dp) < 0.1f * dp) continue;
                        nearEdge = true;
                        for (int c = 0; c < 3; ++c)
                            contrast[c] = std::max(contrast[c], double(std::abs(o.full.at(x + i, y + j, c) - o.full.at(x, y, c))));
                    }
                for (int c = 0; c < 3; ++c) {
                    double f = o.full.at(x, y, c), h = o.half.at(x, y, c);
                    CHECK(std::abs(h - f) <= smoothBound(f, perCell) + (nearEdge ? oneSided + 0.009 * contrast[c] : 0.0));
                    if (nearEdge) CHECK(contrast[c] > 0.5 * f);  // the sides differ: bleeding would show
                }
                edgePixels += nearEdge ? 1 : 0;
                ++checked;
            }
        CHECK(edgePixels >= 2 * (size.y - 2));  // both sides of the edge in every inner row
        CHECK(checked == (size.x - 2) * (size.y - 2));
    }
}

TEST_CASE("LPV half-resolution apply: wall pixels between two thin columns keep their own light (upsampleWiden)") {
    // Two columns 0.8 pixels wide at depth 2 in front of the wall at depth 3, on pixels 14 and 17, under
    // the field of the depth-edge test (the columns ~4x brighter). Each takes the half texel of its 2x2
    // block (the nearer pixel), so the wall pixels 15 and 16 between them have only column texels
    // among their four taps and would get the columns' light, 4x too much (the nearest-depth tap). With
    // the wider search they take a wall texel up to 2.5 pixels away: |half - full| <= the smooth bound
    // + the field's change over 3.5 pixels.
    GpuFixture gpu;
    const glm::ivec2 size{32, 24};
    const double a = -9.5;
    const glm::dvec3 b(0.05, -0.03, 3.0);
    const float pitch = float(2.0 * 2.0 * std::tan(glm::radians(30.0)) / double(size.y));  // a pixel at depth 2
    Scene scene = wallScene(false, 0.0f);
    for (int px : {14, 17}) {
        float cx = (float(px) - 16.0f + 0.5f) * pitch;
        addQuad(scene, {cx - 0.4f * pitch, -3, 1}, {cx + 0.4f * pitch, -3, 1}, {cx + 0.4f * pitch, 5, 1}, {cx - 0.4f * pitch, 5, 1}, 0);
    }
    lpv::Placement pl;
    Outputs o = applyBoth(scene, size, a, b, &pl);
    const double perCell = 0.5 / 3.14159265358979 * 0.886226925 * (std::abs(b.x) + std::abs(b.y) + std::abs(b.z)) / (pl.cell * pl.cell);
    const double pixelCells = 3.0 * 2.0 * std::tan(glm::radians(30.0)) / double(size.y) / pl.cell;
    const double far = 3.5 * pixelCells * 0.5 / 3.14159265358979 * 0.886226925 * (std::abs(b.x) + std::abs(b.y)) / (pl.cell * pl.cell);
    int between = 0;
    for (int y = 1; y < size.y - 1; ++y) {
        // The columns are where they should be: pixels 14 and 17 near, 15 and 16 the wall.
        REQUIRE(o.depth.at(14, y, 0) < 2.5f);
        REQUIRE(o.depth.at(17, y, 0) < 2.5f);
        REQUIRE(o.depth.at(15, y, 0) > 2.5f);
        REQUIRE(o.depth.at(16, y, 0) > 2.5f);
        CHECK(o.full.at(14, y, 0) > 2.0 * o.full.at(15, y, 0));  // brighter: bleeding would show
        for (int x = 1; x < size.x - 1; ++x) {
            if (o.depth.at(x, y, 0) < 2.5f) continue;  // the columns: the depth-edge test's case
            const bool nearColumn = x >= 12 && x <= 19;
            between += (x == 15 || x == 16) ? 1 : 0;
            for (int c = 0; c < 3; ++c) {
                double f = o.full.at(x, y, c), h = o.half.at(x, y, c);
                CAPTURE(x);
                CAPTURE(y);
                CHECK(std::abs(h - f) <= smoothBound(f, perCell) + (nearColumn ? far : 0.0));
            }
        }
    }
    CHECK(between == 2 * (size.y - 2));
}

TEST_CASE("LPV half-resolution apply: at a concave crease every half texel shades a point within its pixels' depths") {
    // A floor (y = 0) meeting a back wall at z = -6, seen at a grazing angle, with
    // the camera rolled so that the crease crosses the half texels at every sub-pixel offset. The
    // half texel's surface is its nearest pixel's plane continued to the texel centre; at the crease
    // the floor continued passes behind the wall (outside the room), where a volume holds the outside's
    // light (the restaurant's back wall: 0.22 against 0.03). Invariant: the depth a half texel shades
    // (low geometry .r) lies within the depths of its 2x2 pixels (1e-3 margin, plus 2.5e-3 of the ramp of
    // aoHalfTexelPoint): on a plane it does exactly (1/z is linear across the block); at the crease the
    // point moves to the pixel's own point.
    GpuFixture gpu;
    const glm::ivec2 size{48, 36};
    Scene s = greyScene("test:crease");
    addQuad(s, {-6, 0, -6}, {-6, 0, 2}, {6, 0, 2}, {6, 0, -6}, 0);  // floor, facing +y
    addQuad(s, {-6, 0, -6}, {6, 0, -6}, {6, 6, -6}, {-6, 6, -6}, 0);  // back wall, facing +z
    Camera c;
    c.position = {0.3f, 0.35f, 1.5f};
    c.target = {0.0f, 0.55f, -6.0f};
    c.up = glm::normalize(glm::vec3(0.12f, 1.0f, 0.0f));  // rolled: the crease is not a pixel row
    c.fovY = glm::radians(50.0f);
    c.near = 0.05f;
    c.far = 50.0f;
    s.cameras.push_back(c);
    Outputs o = applyBoth(s, size, 1.0, glm::dvec3(0.0));
    const glm::ivec2 low = {(size.x + 1) / 2, (size.y + 1) / 2};
    int checked = 0, mixed = 0;
    for (int y = 0; y < low.y; ++y)
        for (int x = 0; x < low.x; ++x) {
            float lo = 3.4e38f, hi = 0.0f;
            for (int i = 0; i < 4; ++i) {
                glm::ivec2 q = glm::min(2 * glm::ivec2(x, y) + glm::ivec2(i & 1, i >> 1), size - 1);
                float dq = o.depth.at(q.x, q.y, 0);
                if (!(dq > 0.0f)) continue;
                lo = std::min(lo, dq), hi = std::max(hi, dq);
            }
            float d = o.lowGeometry.at(x, y, 0);
            if (!(hi > 0.0f)) continue;
            CAPTURE(x);
            CAPTURE(y);
            // Outside the 1e-3 margin by e (relative), the point moves the share min(e / 1e-2, 1) of the
            // way to the pixel's own point: what stays outside is (1 - e / 1e-2) e <= 2.5e-3 of d.
            CHECK(lo * (1.0f - 1e-3f) - d <= 2.51e-3f * d);
            CHECK(d - hi * (1.0f + 1e-3f) <= 2.51e-3f * d);
            mixed += hi > lo * 1.01f ? 1 : 0;
            ++checked;
        }
    MESSAGE(checked << " half texels, " << mixed << " with more than 1 % depth range");
    CHECK(checked == low.x * low.y);
    CHECK(mixed > low.x);  // the crease crosses the image
}
