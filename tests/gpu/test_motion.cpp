// Issue 23, motion: the G-buffer velocity holds camera and object motion on
// both raster paths (GpuScene keeps the last rendered frame's vertices),
// checked against a CPU ray cast in double; the temporal filter rejects
// disoccluded history (docs/temporal.md, "Disocclusion").
#include "gpu_fixture.h"

#include "render/filter.h"
#include "scene/path.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

// Floor y = 0 (half-size 5) and a vertical quad x in [-0.5, 0.5], y in [0.2, 1], z = 0 facing the camera.
constexpr double kQuadX0 = -0.5, kQuadX1 = 0.5, kQuadY0 = 0.2, kQuadY1 = 1.0, kFloor = 5.0;

Scene quadScene() {
    Scene s = floorScene(float(kFloor), glm::vec3(0.5f), false);
    addQuad(s, {float(kQuadX0), float(kQuadY0), 0}, {float(kQuadX1), float(kQuadY0), 0},
            {float(kQuadX1), float(kQuadY1), 0}, {float(kQuadX0), float(kQuadY1), 0}, 0);
    return s;
}

// The scene with the quad (the last 4 vertices) moved by d: its vertices
// rewritten (a re-upload), or `rigid`: as a rigid motion of the rest scene
// (GpuScene::setTransforms moves it by its matrix).
Scene moved(const Scene& s, glm::vec3 d, bool rigid = false) {
    Scene m = s;
    if (rigid) {
        const auto quad = std::uint32_t(m.vertices.size() - 4);
        transformVertices(m, s, {{quad, 4}}, glm::translate(glm::dmat4(1.0), glm::dvec3(d)));
        return m;
    }
    for (std::size_t i = m.vertices.size() - 4; i < m.vertices.size(); ++i) m.vertices[i].position += d;
    return m;
}

struct Hit {
    bool any = false, quad = false;
    glm::dvec3 p{0.0};
};

// The nearest surface through the centre of pixel (x, y) of a view, the quad displaced by q.
Hit castRay(const View& v, glm::ivec2 size, int x, int y, glm::dvec3 q) {
    glm::dmat4 invVp = glm::inverse(glm::dmat4(v.proj) * glm::dmat4(v.view));
    glm::dvec2 uv((x + 0.5) / size.x, (y + 0.5) / size.y);
    glm::dvec4 a = invVp * glm::dvec4(uv * 2.0 - 1.0, -1, 1), b = invVp * glm::dvec4(uv * 2.0 - 1.0, 1, 1);
    glm::dvec3 o = glm::dvec3(a) / a.w, dir = glm::dvec3(b) / b.w - o;
    Hit h;
    double best = 1e300;
    if (dir.y != 0) {  // floor
        double t = -o.y / dir.y;
        glm::dvec3 p = o + t * dir;
        if (t > 0 && std::abs(p.x) <= kFloor && std::abs(p.z) <= kFloor) best = t, h = {true, false, p};
    }
    if (dir.z != 0) {  // quad plane z = q.z
        double t = (q.z - o.z) / dir.z;
        glm::dvec3 p = o + t * dir;
        if (t > 0 && t < best && p.x >= kQuadX0 + q.x && p.x <= kQuadX1 + q.x && p.y >= kQuadY0 + q.y &&
            p.y <= kQuadY1 + q.y)
            best = t, h = {true, true, p};
    }
    return h;
}

struct VelocityCheck {
    int quadPixels = 0, floorPixels = 0, edgePixels = 0;
    double worstUv = 0;
};

// Compares the velocity of the frame just rendered (view v, the quad at qNow,
// at qPrev in the previous frame) with prev − current projected uv of the hit point.
VelocityCheck checkVelocity(const Renderer& r, const View& v, glm::ivec2 size, glm::dvec3 qNow, glm::dvec3 qPrev) {
    FloatImage vel = readTexture(r.resources().gbuffer.velocity);
    FloatImage depth = readTexture(r.resources().gbuffer.linearDepth);
    glm::dmat4 prevVp = glm::dmat4(v.prevProj) * glm::dmat4(v.prevView);
    glm::dmat4 view = glm::dmat4(v.view);
    VelocityCheck c;
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
            Hit h = castRay(v, size, x, y, qNow);
            if (!h.any) continue;
            // A pixel whose centre lies within rounding of a silhouette may see the other surface.
            double zCpu = -(view * glm::dvec4(h.p, 1)).z, zGpu = depth.at(x, y, 0);
            if (std::abs(zCpu - zGpu) > 1e-3 * zCpu) {
                ++c.edgePixels;
                continue;
            }
            glm::dvec3 prevP = h.quad ? h.p - qNow + qPrev : h.p;
            glm::dvec4 cp = prevVp * glm::dvec4(prevP, 1);
            glm::dvec2 uv((x + 0.5) / size.x, (y + 0.5) / size.y);
            glm::dvec2 expected = (glm::dvec2(cp) / cp.w * 0.5 + 0.5) - uv;
            glm::dvec2 got(vel.at(x, y, 0), vel.at(x, y, 1));
            // RG16F: 2^-11 relative rounding per component (2^-10 bound), plus fp32 clip interpolation.
            double bound = std::ldexp(1.0, -10) * (std::abs(expected.x) + std::abs(expected.y)) + 2e-5;
            double err = glm::length(got - expected);
            if (err > bound) {
                CAPTURE(x);
                CAPTURE(y);
                CAPTURE(h.quad);
                CAPTURE(expected.x);
                CAPTURE(expected.y);
                CAPTURE(got.x);
                CAPTURE(got.y);
                CHECK(err <= bound);
            }
            c.worstUv = std::max(c.worstUv, err);
            (h.quad ? c.quadPixels : c.floorPixels)++;
        }
    return c;
}

}  // namespace

TEST_CASE("motion: a quad moved by a known offset has the analytic velocity at every pixel, both raster paths, "
          "re-uploaded or by transforms") {
    GpuFixture gpu;
    const Scene rest = quadScene();
    const glm::vec3 d(0.25f, 0.1f, -0.3f);  // the quad's world offset between frames 0 and 1
    const glm::ivec2 size(64, 48);
    for (bool rigid : {false, true})
    for (auto path : {RasterSettings::Path::Hardware, RasterSettings::Path::Compute}) {
        CAPTURE(int(path));
        CAPTURE(rigid);
        Settings st;
        st.raster.path = path;
        st.ao.variant = AoSettings::Variant::Off;
        st.lpv.mode = Toggle::Off;
        gl::Profiler prof(false);
        Renderer r(rest, st, prof);
        Camera c0 = resolveCamera(rest, st), c1 = c0, c2 = c0;
        c1.position.x += 0.15f;  // the camera moves too: velocity = camera + object motion
        c2.position.x += 0.3f;
        c2.position.y -= 0.1f;
        View v0 = makeView(c0, size, nullptr, 0);
        r.render(v0);
        // Two states before the next frame: the previous positions are those frame 0 rendered.
        r.updateScene(moved(rest, 0.5f * d, rigid));
        r.updateScene(moved(rest, d, rigid));
        REQUIRE(r.lastSceneUpdate().geometry);
        CHECK(r.lastSceneUpdate().transforms == rigid);
        View v1 = makeView(c1, size, &v0, 1);
        r.render(v1);
        VelocityCheck m = checkVelocity(r, v1, size, glm::dvec3(d), glm::dvec3(0.0));
        MESSAGE("moving quad: " << m.quadPixels << " quad, " << m.floorPixels << " floor, " << m.edgePixels
                                << " silhouette pixels, worst " << m.worstUv << " uv");
        CHECK(m.quadPixels > 60);
        CHECK(m.floorPixels > 300);
        CHECK(m.edgePixels <= size.x * size.y / 50);
        // The quad stopped: frame 2 sees camera motion only, on the quad as on the floor.
        r.updateScene(moved(rest, d, rigid));
        CHECK_FALSE(r.lastSceneUpdate().geometry);
        View v2 = makeView(c2, size, &v1, 2);
        r.render(v2);
        VelocityCheck s = checkVelocity(r, v2, size, glm::dvec3(d), glm::dvec3(d));
        CHECK(s.quadPixels > 60);
        CHECK(s.edgePixels <= size.x * size.y / 50);
    }
}

namespace {

// Two fronto-parallel rectangles seen by a camera looking down -z: a
// background (id 0) at z = -10 and a square (id 1) at z = -4, |x|,|y| <= 1.
struct PlaneHit {
    int id = -1;
    double depth = 0;
};
PlaneHit castPlanes(const View& v, glm::dvec2 uv) {
    glm::dmat4 invVp = glm::inverse(glm::dmat4(v.proj) * glm::dmat4(v.view));
    glm::dvec4 a = invVp * glm::dvec4(uv * 2.0 - 1.0, -1, 1), b = invVp * glm::dvec4(uv * 2.0 - 1.0, 1, 1);
    glm::dvec3 o = glm::dvec3(a) / a.w, dir = glm::dvec3(b) / b.w - o;
    auto at = [&](double z) { return o + dir * ((z - o.z) / dir.z); };
    glm::dvec3 p = at(-4.0);
    PlaneHit h;
    glm::dvec3 q = std::abs(p.x) <= 1 && std::abs(p.y) <= 1 ? p : at(-10.0);
    h.id = q.z > -5 ? 1 : 0;
    h.depth = -(glm::dmat4(v.view) * glm::dvec4(q, 1)).z;
    return h;
}

struct SyntheticFrame {
    std::vector<float> depth, velocity, value;
    std::vector<int> id;
    glm::dvec2 prevUv(int x, int y, glm::ivec2 s) const {
        std::size_t i = std::size_t(y * s.x + x);
        return glm::dvec2((x + 0.5) / s.x + velocity[2 * i], (y + 0.5) / s.y + velocity[2 * i + 1]);
    }
};

// G-buffer of view v in double: depth, velocity (prev - cur uv of the hit point:
// a static scene), and the value 0.2 on the background, 0.9 on the square.
SyntheticFrame synthesize(const View& v, glm::ivec2 s) {
    SyntheticFrame f;
    glm::dmat4 prevVp = glm::dmat4(v.prevProj) * glm::dmat4(v.prevView);
    glm::dmat4 invView = glm::inverse(glm::dmat4(v.view));
    for (int y = 0; y < s.y; ++y)
        for (int x = 0; x < s.x; ++x) {
            glm::dvec2 uv((x + 0.5) / s.x, (y + 0.5) / s.y);
            PlaneHit h = castPlanes(v, uv);
            // The hit point from its view-space position.
            glm::dmat4 invProj = glm::inverse(glm::dmat4(v.proj));
            glm::dvec4 n = invProj * glm::dvec4(uv * 2.0 - 1.0, 1, 1);
            glm::dvec3 dirView = glm::dvec3(n) / n.w;
            glm::dvec3 pv = dirView * (h.depth / -dirView.z);
            glm::dvec4 pw = invView * glm::dvec4(pv, 1);
            glm::dvec4 c = prevVp * pw;
            glm::dvec2 vel = (glm::dvec2(c) / c.w * 0.5 + 0.5) - uv;
            f.depth.push_back(float(h.depth));
            f.velocity.push_back(float(vel.x));
            f.velocity.push_back(float(vel.y));
            f.value.push_back(h.id == 1 ? 0.9f : 0.2f);
            f.id.push_back(h.id);
        }
    return f;
}

}  // namespace

TEST_CASE("temporal filter: disoccluded history is rejected and counted, no other (pan and dolly, CPU G-buffer)") {
    GpuFixture gpu;
    gl::MemoryLedger ledger;
    gl::ProgramCache programs;
    const glm::ivec2 s(64, 48);
    const FilterFormat fmt{GL_R16F, "r16f"};
    struct Motion {
        std::string name;
        glm::vec3 step;  // camera translation per frame
    };
    // 0.3 px per frame of parallax on the square, 0.03 px, 3 px (the only one that leaves pixels with
    // no tap on their own surface), and a dolly of 1 % of the square's depth per frame.
    for (Motion m : {Motion{"pan", {0.03f, 0.012f, 0}}, Motion{"slow pan", {0.003f, 0.0012f, 0}},
                     Motion{"fast pan", {0.3f, 0.12f, 0}}, Motion{"dolly", {0.004f, 0, -0.04f}}}) {
        CAPTURE(m.name);
        Camera cam;
        cam.position = {0, 0, 0};
        cam.target = {0, 0, -1};
        cam.fovY = glm::radians(60.0f);
        cam.near = 0.1f;
        cam.far = 50.0f;
        TemporalFilter filter;
        View prev;
        SyntheticFrame last;
        const int frames = 20;
        for (int f = 0; f < frames; ++f) {
            View v = makeView(cam, s, f ? &prev : nullptr, unsigned(f));
            SyntheticFrame g = synthesize(v, s);
            gl::Texture depth = floatTexture(ledger, "t.depth", GL_R32F, s.x, s.y, 1, g.depth);
            gl::Texture velocity = floatTexture(ledger, "t.velocity", GL_RG16F, s.x, s.y, 2, g.velocity);
            gl::Texture current = floatTexture(ledger, "t.current", GL_R16F, s.x, s.y, 1, g.value);
            const gl::Texture& out =
                filter.run(programs, ledger, "t.temporal", fmt, current, depth, velocity, f == 0, temporalCamera(v));
            FloatImage o = readTexture(out);
            // CPU bounds on the disoccluded count: at least the pixels whose four bilinear taps all lie on
            // another surface (or off-screen); at most those with any tap on another surface.
            int lower = 0, upper = 0;
            double worst = 0;
            for (int y = 0; y < s.y; ++y)
                for (int x = 0; x < s.x; ++x) {
                    const int id = g.id[std::size_t(y * s.x + x)];
                    worst = std::max(worst, std::abs(double(o.at(x, y, 0)) - g.value[std::size_t(y * s.x + x)]));
                    if (f == 0) continue;
                    glm::dvec2 uvp = g.prevUv(x, y, s);
                    if (uvp.x < 0.0001 || uvp.y < 0.0001 || uvp.x >= 0.9999 || uvp.y >= 0.9999) {
                        ++lower, ++upper;
                        continue;
                    }
                    glm::dvec2 t = uvp * glm::dvec2(s) - 0.5;
                    glm::ivec2 t0 = glm::ivec2(glm::floor(t));
                    int other = 0;
                    for (int k = 0; k < 4; ++k) {
                        glm::ivec2 q = glm::clamp(t0 + glm::ivec2(k & 1, k >> 1), glm::ivec2(0), s - 1);
                        other += last.id[std::size_t(q.y * s.x + q.x)] != id;
                    }
                    lower += other == 4;
                    upper += other > 0;
                }
            const std::uint32_t counted = filter.disoccludedPixels();
            CAPTURE(f);
            CHECK(counted >= std::uint32_t(lower));
            CHECK(counted <= std::uint32_t(upper));
            // No ghosting: every pixel shows its own surface's value. A tap on the other surface is never
            // accepted (depth gap 6 against a tolerance of 2^-12 of the depth: the planes have slope 0), and the
            // kept taps hold the pixel's own value: exact up to R16F storage, which may truncate (llvmpipe): one
            // ulp of the input (2^-11 in [0.5, 1)) and one of the renormalized blend, which the 5 % pull towards
            // the current value keeps from drifting further.
            CHECK(worst <= std::ldexp(1.0, -10));
            if (f == frames - 1) MESSAGE(m.name << ": disoccluded " << counted << " in [" << lower << ", " << upper << "], worst |out - value| " << worst);
            last = g;
            prev = v;
            cam.position += m.step;
            cam.target += m.step;
        }
    }
}

TEST_CASE("motion: an object moving away reveals background whose temporal AO has no trace of the object") {
    GpuFixture gpu;
    // Floor and wall (a corner: occluded AO) with a standing panel in front of the wall.
    Scene rest = floorAndWallScene();
    addQuad(rest, {-0.5f, 0, -0.5f}, {0.5f, 0, -0.5f}, {0.5f, 0.6f, -0.5f}, {-0.5f, 0.6f, -0.5f}, 0);
    Settings st;
    st.lpv.mode = Toggle::Off;
    st.ao.variant = AoSettings::Variant::Gtao;
    st.ao.halfResolution = false;
    st.ao.blur = true;
    st.ao.temporal = true;
    const glm::ivec2 size(48, 32);
    gl::Profiler prof(false);
    Renderer r(rest, st, prof);
    const Camera cam = resolveCamera(rest, st);
    View prev;
    auto frame = [&](int f) {
        View v = makeView(cam, size, f ? &prev : nullptr, unsigned(f));
        r.render(v);
        prev = v;
    };
    const Pass* blur = r.findPass("ao.blur");
    const Pass* temporal = r.findPass("ao.temporal");
    REQUIRE(blur);
    REQUIRE(temporal);
    for (int f = 0; f < 8; ++f) frame(f);  // the history is warm on the panel
    FloatImage depthBefore = readTexture(r.resources().gbuffer.linearDepth);
    FloatImage aoBefore = readTexture(*r.debugImages(*temporal).at(0).tex);
    r.updateScene(moved(rest, {40, 0, 0}));  // the panel leaves the view in one frame
    frame(8);
    FloatImage depth = readTexture(r.resources().gbuffer.linearDepth);
    FloatImage current = readTexture(*r.debugImages(*blur).at(0).tex);  // the no-history AO of this frame
    FloatImage out = readTexture(*r.debugImages(*temporal).at(0).tex);
    int revealed = 0;
    double worst = 0, historyGap = 0;
    for (int y = 1; y + 1 < size.y; ++y)
        for (int x = 1; x + 1 < size.x; ++x) {
            // Revealed: the panel covered the pixel and its 3x3 neighbourhood (no silhouette), the background is
            // now 5 % or more farther.
            bool inside = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    inside = inside && depthBefore.at(x + dx, y + dy, 0) > 0 &&
                             depth.at(x + dx, y + dy, 0) > 1.05f * depthBefore.at(x + dx, y + dy, 0);
            if (!inside) continue;
            ++revealed;
            worst = std::max(worst, double(std::abs(out.at(x, y, 0) - current.at(x, y, 0))));
            historyGap = std::max(historyGap, double(std::abs(aoBefore.at(x, y, 0) - current.at(x, y, 0))));
        }
    MESSAGE("revealed " << revealed << " pixels; the panel's AO differed by up to " << historyGap
                        << "; temporal vs no-history AO: " << worst);
    REQUIRE(revealed > 20);
    CHECK(historyGap > 0.05);  // a ghost would be visible: the panel's AO is not the background's
    CHECK(worst <= std::ldexp(1.0, -11));  // rejected history: the output is the current value (R16F copy)
    double counted = 0;
    for (auto& [k, v] : r.findPass("ao.temporal")->stats())
        if (k == "disoccluded_pixels") counted = v;
    CHECK(counted >= revealed);
}

namespace {

// Where the surface point seen at pixel q of a frame (linear depth d, view v) lay in the previous frame, in
// pixels of that frame (st = uv * size - 0.5, the bilinear tap coordinate), from the camera matrices in double.
glm::dvec2 reprojectPixel(const View& v, glm::ivec2 size, int x, int y, double d, bool& onScreen) {
    const glm::dmat4 invProj = glm::inverse(glm::dmat4(v.proj)), invView = glm::inverse(glm::dmat4(v.view));
    glm::dvec2 uv((x + 0.5) / size.x, (y + 0.5) / size.y);
    glm::dvec4 n = invProj * glm::dvec4(uv * 2.0 - 1.0, 1, 1);
    glm::dvec3 dir = glm::dvec3(n) / n.w;
    glm::dvec4 world = invView * glm::dvec4(dir * (d / -dir.z), 1);
    glm::dvec4 c = glm::dmat4(v.prevProj) * glm::dmat4(v.prevView) * world;
    glm::dvec2 uvPrev = glm::dvec2(c) / c.w * 0.5 + 0.5;
    // The filter takes the current value beyond [0.0001, 0.9999); near that border either may happen.
    onScreen = uvPrev.x >= 0.0001 - 1e-4 && uvPrev.y >= 0.0001 - 1e-4 && uvPrev.x < 0.9999 + 1e-4 &&
               uvPrev.y < 0.9999 + 1e-4;
    return uvPrev * glm::dvec2(size) - 0.5;
}

// The previous frame's pixels the filter may read for st: the 2x2 bilinear taps, clamped to the edge, widened by
// one where st lies within 0.01 px of a texel boundary (fp32 reconstruction and the RG16F velocity's rounding
// may put the GPU's position on the other side).
void tapsAround(glm::dvec2 st, glm::ivec2 size, std::vector<int>& out) {
    int lo[2], hi[2];
    for (int a = 0; a < 2; ++a) {
        double f = std::floor(st[a]), frac = st[a] - f;
        lo[a] = int(f) - (frac < 0.01 ? 1 : 0);
        hi[a] = int(f) + 1 + (frac > 0.99 ? 1 : 0);
    }
    for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x)
            out.push_back(std::clamp(y, 0, size.y - 1) * size.x + std::clamp(x, 0, size.x - 1));
}

}  // namespace

TEST_CASE("temporal AO on a camera path (static scene, real frame): the warm history is the no-history AO of the "
          "same surface points, no ghosting, few disocclusions") {
    // docs/temporal.md, "Warm history on a moving camera". Oracle: the camera matrices in double. The filter's
    // output at pixel p is a convex combination of this frame's no-history AO at p and the history at the taps
    // around p's reprojected position that it kept, stored in R16F. Unrolled over the path, it lies in the
    // range of the no-history AO C_s over the footprint F_s of p in every earlier frame s of the path (the taps
    // of the taps, all four of them: the depth test only removes taps) and the warm history H_0 over F_0, up to
    // one R16F rounding per frame. Disoccluded pixels take C_t(p), which is in that range: the bound holds on
    // every pixel. A filter that reads history of other points (a wrong reprojection matrix) leaves it, or
    // rejects far more history than the silhouettes explain.
    GpuFixture gpu;
    const Scene scene = loadBuiltin("cornell");
    Settings st;
    st.lpv.mode = Toggle::Off;
    st.ao.variant = AoSettings::Variant::Gtao;
    st.ao.halfResolution = false;  // the filter at the G-buffer's resolution: its depth is the G-buffer's
    st.ao.blur = true;
    st.ao.temporal = true;
    const glm::ivec2 size(96, 64);
    const int n = size.x * size.y;
    // A pan to the right with a dolly and a turn: 1.5-2.5 px per frame, parallax at the short box's edges.
    const Path path = parsePath(R"({"fps": 10, "duration": 0.6, "camera": {"keys": [
        {"t": 0, "position": [0.0, 2.75, 10.6], "target": [0.0, 2.75, 0.0], "fov": 40},
        {"t": 0.6, "position": [1.5, 2.6, 9.8], "target": [0.6, 2.3, 0.0], "fov": 40}]}})", "test", "pan");
    const int warm = 8, moves = path.frameCount() - 1;
    REQUIRE(moves == 6);
    gl::Profiler prof(false);
    Renderer r(scene, st, prof);
    const Pass* blur = r.findPass("ao.blur");
    const Pass* temporal = r.findPass("ao.temporal");
    REQUIRE(blur);
    REQUIRE(temporal);
    auto flagged = [&] {
        for (auto& [k, val] : r.findPass("ao.temporal")->stats())
            if (k == "disoccluded_pixels") return val;
        FAIL("ao.temporal has no disoccluded_pixels stat");
        return 0.0;
    };
    const Camera fallback = resolveCamera(scene, st);
    std::vector<View> views;
    std::vector<FloatImage> depth, current, out;  // per path frame s = 0..moves (s = 0: the warm frame)
    View prev;
    for (int f = 0; f < warm + moves; ++f) {
        const int s = std::max(0, f - warm + 1);  // warm-up frames at t = 0 (the history settles there)
        View v = makeView(pathCamera(&path, path.timeOfFrame(s), fallback), size, f ? &prev : nullptr, unsigned(f));
        r.render(v);
        prev = v;
        if (f < warm - 1) continue;
        views.push_back(v);
        depth.push_back(readTexture(r.resources().gbuffer.linearDepth));
        current.push_back(readTexture(*r.debugImages(*blur).at(0).tex));
        out.push_back(readTexture(*r.debugImages(*temporal).at(0).tex));
        if (s == 0) {
            CHECK(flagged() == 0);  // a still camera keeps all of its history
            continue;
        }
        // Footprints and the CPU's disocclusion bounds of this frame.
        int lower = 0, upper = 0, outside = 0, geometry = 0;
        double worst = 0, maxDiff = 0;
        for (int p = 0; p < n; ++p) {
            const int px = p % size.x, py = p / size.x;
            const double zNow = depth[std::size_t(s)].at(px, py, 0);
            const double h = out[std::size_t(s)].at(px, py, 0), c = current[std::size_t(s)].at(px, py, 0);
            double lo = c, hi = c;
            std::vector<int> fp{p}, next;
            for (int k = s; k >= 1; --k) {  // footprint in frame k-1 of the footprint in frame k
                next.clear();
                for (int q : fp) {
                    const double d = depth[std::size_t(k)].at(q % size.x, q / size.x, 0);
                    if (!(d > 0)) continue;  // sky: the current value, no history
                    bool on = false;
                    glm::dvec2 stq = reprojectPixel(views[std::size_t(k)], size, q % size.x, q / size.x, d, on);
                    if (on) tapsAround(stq, size, next);
                }
                std::sort(next.begin(), next.end());
                next.erase(std::unique(next.begin(), next.end()), next.end());
                const FloatImage& src = k - 1 == 0 ? out[0] : current[std::size_t(k - 1)];  // H_0, or C_{k-1}
                for (int q : next) {
                    lo = std::min(lo, double(src.at(q % size.x, q / size.x, 0)));
                    hi = std::max(hi, double(src.at(q % size.x, q / size.x, 0)));
                }
                fp.swap(next);
            }
            const double slack = s * std::ldexp(1.0, -11);  // one R16F rounding per frame of the path
            const double miss = std::max(lo - slack - h, h - hi - slack);
            worst = std::max(worst, miss);
            maxDiff = std::max(maxDiff, std::abs(h - c));
            if (miss > 0) {
                ++outside;
                if (outside <= 5) {
                    CAPTURE(s);
                    CAPTURE(px);
                    CAPTURE(py);
                    CAPTURE(h);
                    CAPTURE(c);
                    CAPTURE(lo);
                    CAPTURE(hi);
                    CHECK(miss <= 0);
                }
            }
            // Disocclusion of this frame's history: the four taps around the reprojected point against the
            // point's depth in the previous view (5 %: another surface). At least the pixels with no tap on
            // their surface (or off-screen) are flagged, at most those with a tap off it or beside a sky pixel.
            if (!(zNow > 0)) continue;
            ++geometry;
            bool on = false;
            const View& vs = views[std::size_t(s)];
            glm::dvec2 stp = reprojectPixel(vs, size, px, py, zNow, on);
            if (!on) {
                ++lower, ++upper;
                continue;
            }
            glm::dmat4 invProj = glm::inverse(glm::dmat4(vs.proj));
            glm::dvec2 uv((px + 0.5) / size.x, (py + 0.5) / size.y);
            glm::dvec4 nv = invProj * glm::dvec4(uv * 2.0 - 1.0, 1, 1);
            glm::dvec3 dir = glm::dvec3(nv) / nv.w;
            glm::dvec4 prevViewPos = glm::dmat4(vs.prevView) * glm::inverse(glm::dmat4(vs.view)) *
                                     glm::dvec4(dir * (zNow / -dir.z), 1);
            const double expected = -prevViewPos.z;
            std::vector<int> taps;
            tapsAround(stp, size, taps);
            int other = 0;
            for (int q : taps) {
                const double hd = depth[std::size_t(s - 1)].at(q % size.x, q / size.x, 0);
                other += !(hd > 0) || std::abs(hd - expected) > 0.05 * expected;
            }
            lower += other == int(taps.size());
            upper += other > 0;
        }
        const double counted = flagged();
        MESSAGE("frame " << s << ": " << counted << " disoccluded of " << geometry << " in [" << lower << ", " << upper
                         << "]; |temporal - no-history AO| up to " << maxDiff << "; outside the bound: " << outside
                         << " pixels (worst by " << worst << ")");
        CHECK(outside == 0);
        CHECK(counted >= lower);
        CHECK(counted <= upper);
        CHECK(counted * 20 <= geometry);  // few: the path reveals little (silhouettes of the short box, the edges)
    }
    // The history mattered: the warm AO differs from the no-history AO somewhere (else the bound is vacuous).
    double historyEffect = 0;
    for (int p = 0; p < n; ++p)
        historyEffect = std::max(historyEffect, double(std::abs(out.back().at(p % size.x, p / size.x, 0) -
                                                                current.back().at(p % size.x, p / size.x, 0))));
    CHECK(historyEffect > 0.02);
    // The no-history AO is the frame rendered with a reset history: the last view again as a cut.
    View reset = views.back();
    reset.cut = true;
    reset.prevView = reset.view;
    reset.prevProj = reset.proj;
    r.render(reset);
    FloatImage again = readTexture(*r.debugImages(*temporal).at(0).tex);
    int same = 0;
    for (int p = 0; p < n; ++p)
        same += again.at(p % size.x, p / size.x, 0) == current.back().at(p % size.x, p / size.x, 0);
    CHECK(same == n);
    CHECK(flagged() == 0);  // a reset counts nothing
}
