// Cascaded LPV through the whole renderer (docs/lpv.md "Cascades"): the
// irradiance across a cascade border (seam) and the snapping of every
// cascade's volume to its own cells when the camera moves.
#include "gpu_fixture.h"
#include "render/lpv/lpv_math.h"
#include "render/lpv/lpv_volumes.h"
#include "scene/path.h"

#include <glm/gtx/component_wise.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

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

namespace {

// A sunlit 6 m floor of strips of unequal width and albedo along x, so the
// injected light varies along x (a uniform floor would hide a wrong shift).
Scene stripedFloor() {
    Scene s = floorScene(3.0f, glm::vec3(0.5f), true, glm::normalize(glm::vec3(0.3f, 1.0f, 0.4f)), 2.0f);
    s.vertices.clear();
    s.indices.clear();
    s.draws.clear();
    float x0 = -3.0f;
    for (int i = 0; x0 < 3.0f; ++i) {
        Material m;
        m.baseColor = glm::vec4(0.15f + 0.7f * float((i * 7) % 5) / 4.0f, 0.5f, 0.3f + 0.1f * float(i % 3), 1.0f);
        m.roughness = 1.0f;
        s.materials.push_back(m);
        float x1 = std::min(3.0f, x0 + 0.23f + 0.11f * float(i % 4));
        addQuad(s, {x0, 0, 3}, {x1, 0, 3}, {x1, 0, -3}, {x0, 0, -3}, int(s.materials.size()) - 1);
        x0 = x1;
    }
    return s;
}

struct CascadeVolumes {
    std::vector<std::vector<float>> rgb;  // per cascade: R, G, B volumes, RGBA each, concatenated
    glm::ivec3 grid{0};
};

// Every cascade's accumulated volume of the renderer's last frame.
CascadeVolumes readVolumes(Renderer& r, const Settings& s) {
    Pass* p = r.findPass("lpv.propagate");
    REQUIRE(p != nullptr);
    CascadeVolumes out;
    out.rgb.resize(std::size_t(s.lpv.cascades));
    for (const auto& o : r.checkedOutputs(*p)) {
        int cascade = -1;
        for (int i = 0; i < s.lpv.cascades; ++i) {
            std::string prefix = i == 0 ? "lpv.accum." : "lpv.accum.cascade" + std::to_string(i) + ".";
            if (o.name.find(prefix) != std::string::npos && o.name.size() == o.name.find(prefix) + prefix.size() + 1)
                cascade = i;
        }
        if (cascade < 0) continue;
        const gl::Texture& t = *o.tex;
        out.grid = {t.width(), t.height(), t.depth()};
        std::vector<float> v(std::size_t(4 * t.width() * t.height() * t.depth()));
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
        glGetTextureImage(t.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(v.size() * 4), v.data());
        auto& dst = out.rgb[std::size_t(cascade)];
        dst.insert(dst.end(), v.begin(), v.end());
    }
    for (auto& c : out.rgb) REQUIRE(c.size() == std::size_t(3 * 4 * out.grid.x * out.grid.y * out.grid.z));
    return out;
}

// Every cascade's accumulated volume after one frame with the camera at `pos` looking along `dir`.
CascadeVolumes renderVolumes(Scene scene, const Settings& s, glm::vec3 pos, glm::vec3 dir, gl::Profiler& prof) {
    scene.cameras[0].position = pos;
    scene.cameras[0].target = pos + dir;
    auto r = renderFrames(scene, s, {16, 16}, prof);
    return readVolumes(*r, s);
}

// Relative L2 difference of cascade volumes a and b over the cells of a with x index in
// [lo, hi), b read at x + shift (the same world cell after b's origin moved by `shift` cells).
double shiftedDifference(const CascadeVolumes& a, const CascadeVolumes& b, int cascade, int shift, int lo, int hi) {
    const glm::ivec3 g = a.grid;
    double num = 0, den = 0;
    for (int ch = 0; ch < 3; ++ch)
        for (int z = 0; z < g.z; ++z)
            for (int y = 0; y < g.y; ++y)
                for (int x = lo; x < hi; ++x)
                    for (int k = 0; k < 4; ++k) {
                        auto at = [&](int xx) {
                            return std::size_t(((ch * g.z + z) * g.y + y) * g.x + xx) * 4 + std::size_t(k);
                        };
                        double va = a.rgb[std::size_t(cascade)][at(x)];
                        double vb = b.rgb[std::size_t(cascade)][at(x - shift)];
                        num += (va - vb) * (va - vb);
                        den += va * va;
                    }
    return den > 0 ? std::sqrt(num / den) : (num > 0 ? 1.0 : 0.0);
}

}  // namespace

TEST_CASE("LPV cascades: a camera move by a fraction of a cell changes no volume; by one cell shifts it by one") {
    // docs/lpv.md "Snapping". 3 cascades of 8^3, cells 0.25 / 0.5 / 1 m, over a sunlit striped
    // floor; occlusion and bounce off (the geometry volume would read the camera's G-buffer),
    // 1 iteration. Cascades 0 and 1 (2 m, 4 m) follow the camera along x; cascade 2 (8 m) holds
    // the 6 m scene, is centred on it and never moves, so the RSM (fitted to it) is the same in
    // every run and each cascade injects the same texels. Camera x: 0.1 -> 0.15 (0.2 of cascade
    // 0's cell): every volume equal. 0.1 -> 0.6 (one cell of cascade 1): cascade 1's origin
    // moves by +1 cell, cascade 0's by +2, cascade 2's by 0, so the new volume at cell x equals
    // the old one at x + shift wherever neither run's border is within the iteration's reach (1
    // cell) along x. Bound: fp32 atomic injection adds in another order, 1e-5 relative L2.
    // Expected shifts from the documented placement: floor((x − extent/2)/s_i) for the cascade
    // centre x (camera x: the view looks along −z and the clamp into the bounds is inactive).
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = stripedFloor();
    Settings s;
    s.ao.variant = AoSettings::Variant::Off;
    s.lpv.mode = Toggle::On;
    s.lpv.cascades = 3;
    s.lpv.grid = glm::ivec3(8);
    s.lpv.cell = 0.25f;
    s.lpv.iterations = 1;
    s.lpv.occlusion = s.lpv.bounce = false;
    s.lpv.rsm = 128;
    s.lpv.format = LpvSettings::Format::Rgba32f;
    const glm::vec3 dir = glm::normalize(glm::vec3(0.0f, -0.5f, -1.0f));
    auto a = renderVolumes(scene, s, {0.1f, 1.2f, 2.0f}, dir, prof);
    auto frac = renderVolumes(scene, s, {0.15f, 1.2f, 2.0f}, dir, prof);
    auto moved = renderVolumes(scene, s, {0.6f, 1.2f, 2.0f}, dir, prof);
    const int g = a.grid.x;
    const int shift[3] = {2, 1, 0};
    for (int i = 0; i < 3; ++i) {
        INFO("cascade " << i);
        double f = shiftedDifference(frac, a, i, 0, 0, g);
        // A wrong shift must show: the same comparison one cell off.
        int lo = std::max(1, 1 - shift[i]), hi = std::min(g - 1, g - 1 - shift[i]);
        double m = shiftedDifference(moved, a, i, -shift[i], lo, hi);
        double wrong = shiftedDifference(moved, a, i, -shift[i] - 1, std::max(lo, 1), hi);
        MESSAGE("cascade " << i << ": fraction move rel. L2 " << f << ", one-cell move (shift " << shift[i]
                           << ") rel. L2 " << m << ", one cell off " << wrong);
        CHECK(f <= 1e-5);
        CHECK(m <= 1e-5);
        CHECK(wrong > 1e-2);
    }
}

TEST_CASE("LPV cascades along a camera path: snapped, sub-cell moves change no volume; lpv.snap=off moves them") {
    // docs/lpv.md "Snapping", issue 23. The scene and volumes of the single-move test above, rendered in one
    // renderer along a 6-frame path: the camera slides 0.1 m along x in steps of 0.02 m (0.08 of the finest cell),
    // inside one snapping interval of every cascade (cascade 0: floor((x - 1) / 0.25) = -4, cascade 1:
    // floor((x - 2) / 0.5) = -4 for x in [0.1, 0.2]); nothing but the placement depends on the camera here
    // (occlusion and bounce off, the RSM fitted to the coarsest cascade, which holds the scene and never moves).
    // Snapped: every cascade's placement is bit-identical over the path and its volume equal to the last frame's
    // up to the order of the injection's fp32 atomic adds (relative L2 1e-5, the bound of the single-move test;
    // llvmpipe's threads do not add in a fixed order, so the volumes are not bitwise equal). lpv.snap=off:
    // cascades 0 and 1 follow the camera by 0.02 m a frame and their volumes sample the light 0.08 / 0.04 of a
    // cell further along (the striped floor's light is not uniform), so consecutive frames differ by far more;
    // the scene-holding cascade 2 is centred on the scene in both modes and does not move.
    GpuFixture gpu;
    gl::Profiler prof(false);
    const Scene scene = stripedFloor();
    Settings s;
    s.ao.variant = AoSettings::Variant::Off;
    s.lpv.mode = Toggle::On;
    s.lpv.cascades = 3;
    s.lpv.grid = glm::ivec3(8);
    s.lpv.cell = 0.25f;
    s.lpv.iterations = 1;
    s.lpv.occlusion = s.lpv.bounce = false;
    s.lpv.rsm = 128;
    s.lpv.format = LpvSettings::Format::Rgba32f;
    const Path path = parsePath(R"({"fps": 10, "duration": 0.5, "camera": {"keys": [
        {"t": 0, "position": [0.1, 1.2, 2.0], "target": [0.1, 0.7527864, 1.1055728]},
        {"t": 0.5, "position": [0.2, 1.2, 2.0], "target": [0.2, 0.7527864, 1.1055728]}]}})", "test", "slide");
    REQUIRE(path.frameCount() == 6);
    for (bool snap : {true, false}) {
        CAPTURE(snap);
        s.lpv.snap = snap;
        Renderer r(scene, s, prof);
        const Camera fallback = resolveCamera(scene, s);
        std::vector<CascadeVolumes> frames;
        std::vector<std::vector<lpv::Placement>> placed;
        View prev;
        for (int f = 0; f < path.frameCount(); ++f) {
            const Camera cam = pathCamera(&path, path.timeOfFrame(f), fallback);
            View v = makeView(cam, {16, 16}, f ? &prev : nullptr, unsigned(f));
            r.render(v);
            prev = v;
            frames.push_back(readVolumes(r, s));
            placed.push_back(lpv::placeCascades(s.lpv, 3, scene.bounds(), v.position, v.forward()));
        }
        for (int f = 1; f < path.frameCount(); ++f) {
            CAPTURE(f);
            for (int i = 0; i < 3; ++i) {
                CAPTURE(i);
                // Relative L2 between consecutive frames' volumes, cell for cell.
                const double rel = shiftedDifference(frames[std::size_t(f)], frames[std::size_t(f - 1)], i, 0, 0, 8);
                const glm::vec3 step = placed[std::size_t(f)][std::size_t(i)].origin - placed[std::size_t(f - 1)][std::size_t(i)].origin;
                if (f == path.frameCount() - 1) MESSAGE("snap " << snap << ", cascade " << i << ": frame-to-frame rel. L2 " << rel);
                if (snap || i == 2) {
                    CHECK(step == glm::vec3(0.0f));  // the placement is bit-identical
                    CHECK(rel <= 1e-5);              // the volume: up to the order of fp32 atomic adds
                } else {
                    // The placement moved by the camera's step (0.02 m along x), not by a whole cell.
                    CHECK(double(step.x) == doctest::Approx(0.02).epsilon(1e-3));
                    CHECK(rel > 1e-3);
                }
            }
        }
    }
}

namespace {

struct CpuField {  // one cascade's R, G, B SH volumes in double, x fastest
    glm::ivec3 n{0};
    std::vector<glm::dvec4> c[3];
    glm::dvec4 at(int ch, glm::ivec3 p) const {
        p = glm::clamp(p, glm::ivec3(0), n - 1);  // GL_CLAMP_TO_EDGE
        return c[ch][std::size_t((p.z * n.y + p.y) * n.x + p.x)];
    }
    // GL_LINEAR at continuous cell coordinate q (texel centres at i + 1/2).
    glm::dvec4 trilinear(int ch, glm::dvec3 q) const {
        glm::dvec3 t = q - 0.5, f = glm::floor(t), w = t - f;
        glm::ivec3 b(f);
        glm::dvec4 r(0.0);
        for (int k = 0; k < 8; ++k) {
            glm::ivec3 o((k & 1) != 0, (k & 2) != 0, (k & 4) != 0);
            double wt = (o.x ? w.x : 1 - w.x) * (o.y ? w.y : 1 - w.y) * (o.z ? w.z : 1 - w.z);
            r += wt * at(ch, b + o);
        }
        return r;
    }
    // The largest difference between neighbouring texels around q (bounds the error of
    // the sampler's fixed-point weights).
    double localRange(int ch, glm::dvec3 q) const {
        glm::ivec3 b(glm::floor(q - 0.5));
        double lo = 1e300, hi = -1e300;
        for (int k = 0; k < 8; ++k)
            for (int j = 0; j < 4; ++j) {
                double v = at(ch, b + glm::ivec3((k & 1) != 0, (k & 2) != 0, (k & 4) != 0))[j];
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
        return hi - lo;
    }
};

CpuField randomField(glm::ivec3 n, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.2, 1.0);
    CpuField f;
    f.n = n;
    for (auto& ch : f.c)
        for (int i = 0; i < n.x * n.y * n.z; ++i)
            ch.push_back(glm::dvec4(pos(rng), 0.5 * u(rng), 0.5 * u(rng), 0.5 * u(rng)));
    return f;
}

void uploadField(lpv::Rgb& t, gl::MemoryLedger& ledger, const CpuField& f, const char* label) {
    for (int c = 0; c < 3; ++c) {
        t[std::size_t(c)] = gl::Texture(ledger, label, {GL_TEXTURE_3D, GL_RGBA32F, f.n.x, f.n.y, f.n.z});
        t[std::size_t(c)].setSampling(GL_LINEAR, GL_LINEAR);
        std::vector<float> d;
        for (auto& v : f.c[c])
            for (int k = 0; k < 4; ++k) d.push_back(float(v[k]));
        glTextureSubImage3D(t[std::size_t(c)].id(), 0, 0, 0, 0, f.n.x, f.n.y, f.n.z, GL_RGBA, GL_FLOAT, d.data());
    }
}

// w_j of docs/lpv.md at world point q: 0 half a cell inside cascade j's border, 1 from
// kCascadeBlendCells further in; the coarsest cascade 1 wherever inside.
double insideWeight(const std::vector<lpv::Placement>& pl, int j, glm::dvec3 q) {
    double d = insideCells(pl[std::size_t(j)], q);
    if (j + 1 == int(pl.size())) return d >= 0.0 ? 1.0 : 0.0;
    return std::clamp((d - 0.5) / 2.0, 0.0, 1.0);
}

}  // namespace

TEST_CASE("LPV cascades: the apply's blend of near and far parts equals the documented scheme in double") {
    // docs/lpv.md "Apply: finest cascade first, blended": E(p) = Σ_i [u_i N_i + U_i F_i](q_i)/s_i²
    // band-1 irradiance of the mirrored lookup, q_i = p + ½ s_i n, u_i = w_i Π_{j<i}(1 − w_j),
    // U_i = 1 − Π_{j≤i}(1 − w_j), F_i = T_i − N_i, cascade 0: w_0 T_0; output albedo/π·max(E, 0).
    // Random T_i, N_i (c00 > 0, band 1 up to half of it) in 2 cascades of 4³ and 3 cascades of
    // 3×5×7 placed by lpv::placeCascades around a camera over a floor; every floor pixel of a
    // 48×32 G-buffer against the CPU double evaluation. Bound: fp16 output (2^-11 relative) plus
    // the sampler's fixed-point interpolation weights (llvmpipe: 8 bits), at most 2^-8 of the
    // local texel range per cascade: |GPU − CPU| ≤ 2e-3·|CPU| + albedo/π Σ_i 2^-8·range_i/s_i².
    GpuFixture gpu;
    gl::Profiler prof(false);
    std::mt19937 rng(31);
    const glm::ivec2 size{48, 32};
    struct Case {
        glm::ivec3 grid;
        int cascades;
        float cell;
    };
    for (const Case& k : {Case{{4, 4, 4}, 2, 0.6f}, Case{{3, 5, 7}, 3, 0.35f}}) {
        INFO(k.cascades << " cascades of " << k.grid.x << "x" << k.grid.y << "x" << k.grid.z);
        Scene scene = floorScene(2.0f, glm::vec3(0.6f, 0.5f, 0.4f), true);
        scene.cameras[0].position = {0.3f, 0.9f, 1.2f};
        scene.cameras[0].target = {-0.2f, 0.0f, -0.6f};
        Settings s;
        s.ao.variant = AoSettings::Variant::Off;
        s.lpv.mode = Toggle::On;
        s.lpv.grid = k.grid;
        s.lpv.cascades = k.cascades;
        s.lpv.cell = k.cell;
        s.lpv.selfCorrection = false;
        s.lpv.format = LpvSettings::Format::Rgba32f;
        auto r = renderFrames(scene, s, size, prof);  // G-buffer + frame uniforms (binding 0 stays bound)
        FrameResources& res = r->resources();
        Camera cam = resolveCamera(scene, s);
        std::vector<lpv::Placement> pl =
            lpv::placeCascades(s.lpv, k.cascades, scene.bounds(), cam.position, glm::normalize(cam.target - cam.position));
        gl::MemoryLedger ledger;
        gl::ProgramCache programs;
        std::vector<CpuField> total, near;
        std::vector<lpv::Rgb> tTex(std::size_t(k.cascades)), nTex(std::size_t(k.cascades));
        std::vector<gl::Buffer> ubos;
        for (int i = 0; i < k.cascades; ++i) {
            total.push_back(randomField(k.grid, rng));
            near.push_back(randomField(k.grid, rng));
            uploadField(tTex[std::size_t(i)], ledger, total.back(), "t.total");
            uploadField(nTex[std::size_t(i)], ledger, near.back(), "t.near");
            lpv::UniformInputs in;
            in.placement = pl[std::size_t(i)];
            in.cascade = i;
            in.cascades = pl;
            // The CPU double oracle is the seed's scheme: the leak remedies (docs/lpv.md, "Leaks") are off.
            s.lpv.injectSide = LpvSettings::InjectSide::Offset;
            s.lpv.firstStepBlocked = false;
            s.lpv.blocking = LpvSettings::Blocking::Oriented;
            s.lpv.reflect = LpvSettings::Reflect::Destination;
            gpu::LpvUniforms u = lpv::makeUniforms(s.lpv, in);
            ubos.emplace_back(ledger, "t.lpv.uniforms", sizeof(u), &u);
        }
        gl::Texture indirect(ledger, "t.indirect", {GL_TEXTURE_2D, GL_RGBA16F, size.x, size.y});
        gl::Texture sumE(ledger, "t.sumE", {GL_TEXTURE_2D, GL_RGBA32F, size.x, size.y});
        gl::Texture sumS(ledger, "t.sumS", {GL_TEXTURE_2D, GL_RGBA32F, size.x, size.y});
        for (int i = 0; i < k.cascades; ++i) {
            lpv::ApplyInputs ai;
            ai.gbuffer = {&res.gbuffer.linearDepth, &res.gbuffer.normal, &res.gbuffer.albedo, &res.gbuffer.material, size};
            ai.volume = &tTex[std::size_t(i)];
            ai.near = i > 0 ? &nTex[std::size_t(i)] : nullptr;
            ai.cascade = i;
            ai.cascades = k.cascades;
            ai.sumE = &sumE;
            ai.sumS = &sumS;
            ai.indirect = &indirect;
            lpv::applyCompute(programs, ubos[std::size_t(i)], ai);
        }
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
        FloatImage out = readTexture(indirect), depth = readTexture(res.gbuffer.linearDepth),
                   albedo = readTexture(res.gbuffer.albedo);
        const glm::dvec3 n(0, 1, 0);
        const glm::dvec4 cosLobe(std::sqrt(kPi) / 2.0, -std::sqrt(kPi / 3.0) * n.y, std::sqrt(kPi / 3.0) * n.z,
                                 -std::sqrt(kPi / 3.0) * n.x);
        int checked = 0, blended = 0, perCascade[3] = {0, 0, 0};
        double worst = 0;
        for (int y = 0; y < size.y; ++y)
            for (int x = 0; x < size.x; ++x) {
                if (!(depth.at(x, y, 0) > 0)) continue;
                glm::dvec3 p = worldPosition(scene, s, size, depth, x, y);
                double e[3] = {0, 0, 0}, slack[3] = {0, 0, 0};
                bool onEdge = false;
                for (int i = 0; i < k.cascades; ++i) {
                    const lpv::Placement& c = pl[std::size_t(i)];
                    glm::dvec3 q = p + 0.5 * double(c.cell) * n;
                    double d = insideCells(c, q);
                    onEdge = onEdge || std::abs(d) < 1e-3 || std::abs(d - 0.5) < 1e-3 || std::abs(d - 2.5) < 1e-3;
                    if (d < 0.0) continue;  // outside the grid: no light from this cascade
                    double outside = 1.0;
                    for (int j = 0; j < i; ++j) outside *= 1.0 - insideWeight(pl, j, q);
                    double w = insideWeight(pl, i, q);
                    double ui = w * outside, Ui = 1.0 - outside * (1.0 - w);
                    if (ui > 0.0 && ui < 1.0) ++blended;
                    if (ui == 1.0) ++perCascade[i];
                    glm::dvec3 cq = (q - glm::dvec3(c.origin)) / double(c.cell);
                    for (int ch = 0; ch < 3; ++ch) {
                        glm::dvec4 T = total[std::size_t(i)].trilinear(ch, cq);
                        glm::dvec4 v = i == 0 ? ui * T : ui * near[std::size_t(i)].trilinear(ch, cq) +
                                                             Ui * (T - near[std::size_t(i)].trilinear(ch, cq));
                        glm::dvec4 mirrored(v.x, -v.y, -v.z, -v.w);
                        double inv = 1.0 / (double(c.cell) * double(c.cell));
                        e[ch] += glm::dot(mirrored, cosLobe) * inv;
                        double range = std::max(total[std::size_t(i)].localRange(ch, cq),
                                                near[std::size_t(i)].localRange(ch, cq));
                        slack[ch] += std::pow(2.0, -8) * range * 4.0 * inv;  // 4 coefficients of the lobe, each ≤ 1
                    }
                }
                if (onEdge) continue;  // float positions may put a weight's kink on either side
                for (int ch = 0; ch < 3; ++ch) {
                    double a = albedo.at(x, y, ch) / kPi;
                    double expected = a * std::max(e[ch], 0.0);
                    double tol = 2e-3 * std::abs(expected) + a * slack[ch];
                    double err = std::abs(out.at(x, y, ch) - expected);
                    worst = std::max(worst, err / std::max(tol, 1e-12));
                    CHECK(err <= tol);
                }
                ++checked;
            }
        MESSAGE(k.cascades << " cascades of " << k.grid.x << "x" << k.grid.y << "x" << k.grid.z << ": " << checked
                           << " pixels, finest used alone by cascade: " << perCascade[0] << " / " << perCascade[1] << " / "
                           << perCascade[2] << ", blended lookups " << blended << ", worst error / bound " << worst);
        CHECK(checked > size.x * size.y / 3);
        CHECK(blended > 10);
    }
}

TEST_CASE("LPV cascades with lpv.temporal: every cascade blends, and a static view converges to the unblended frame") {
    GpuFixture fx;
    gl::Profiler prof(false);
    const Scene scene = wallAndFloor();
    const glm::ivec2 size(48, 32);
    Settings off = cascadeSettings();
    Settings on = off;
    on.lpv.temporal = 0.75f;
    REQUIRE(off.lpv.cascades >= 2);
    auto a = renderFrames(scene, off, size, prof, 1);
    REQUIRE(a->findPass("lpv.temporal") == nullptr);
    FloatImage ia = readTexture(a->resources().indirectDiffuse);
    a.reset();
    // The first frame has no history (the blend takes the current volume); a
    // static view then blends a volume with itself, so the frame equals the
    // unblended one up to rounding. A cascade or near part blended with an
    // uninitialized or mis-indexed history would not.
    for (int frames : {1, 2, 6}) {
        auto b = renderFrames(scene, on, size, prof, frames);
        REQUIRE(b->findPass("lpv.temporal") != nullptr);
        FloatImage ib = readTexture(b->resources().indirectDiffuse);
        double num = 0, den = 0;
        for (std::size_t i = 0; i < ia.data.size(); i += 4)
            for (std::size_t c = 0; c < 3; ++c) {
                double d = double(ib.data[i + c]) - double(ia.data[i + c]);
                num += d * d;
                den += double(ia.data[i + c]) * double(ia.data[i + c]);
            }
        INFO(frames << " frames: relative L2 difference " << std::sqrt(num / std::max(den, 1e-30)));
        REQUIRE(den > 0);
        CHECK(std::sqrt(num / den) <= 1e-4);  // fp32 volumes (cascadeSettings)
    }
}
