// Issue 23: keyframe sampling (glTF LINEAR / STEP / CUBICSPLINE, slerp),
// camera splines, path files, scene state at t, and the temporal metrics,
// against values computed by hand or by an independent formulation.
#include "bench/path_run.h"
#include "bench/temporal.h"
#include "render/lpv/lpv_math.h"
#include "render/settings.h"
#include "scene/animation.h"
#include "scene/path.h"
#include "scene/scene.h"

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <string>

using namespace rtgi;

namespace {

KeyTrack track(std::vector<double> times, std::vector<double> values, int components, Interpolation in,
               bool rotation = false) {
    KeyTrack k;
    k.times = std::move(times);
    k.values = std::move(values);
    k.components = components;
    k.interpolation = in;
    k.rotation = rotation;
    k.validate("test");
    return k;
}

}  // namespace

TEST_CASE("animation: LINEAR interpolates and clamps outside the keys") {
    KeyTrack k = track({0.0, 2.0}, {0, 0, 0, 2, 4, -6}, 3, Interpolation::Linear);
    auto v = k.sample(0.5);  // a quarter of the way: (0.5, 1, -1.5)
    CHECK(v[0] == doctest::Approx(0.5).epsilon(1e-15));
    CHECK(v[1] == doctest::Approx(1.0).epsilon(1e-15));
    CHECK(v[2] == doctest::Approx(-1.5).epsilon(1e-15));
    CHECK(k.sample(-1.0)[1] == 0.0);
    CHECK(k.sample(7.0)[2] == -6.0);
}

TEST_CASE("animation: STEP holds a key until the next key time") {
    KeyTrack k = track({0.0, 1.0, 2.0}, {1, 5, 9}, 1, Interpolation::Step);
    CHECK(k.sample(0.999)[0] == 1.0);
    CHECK(k.sample(1.0)[0] == 5.0);
    CHECK(k.sample(1.5)[0] == 5.0);
    CHECK(k.sample(2.5)[0] == 9.0);
}

TEST_CASE("animation: LINEAR rotations slerp on the shorter arc") {
    const double s45 = std::sqrt(0.5);
    // Identity to 90 degrees about z; halfway is 45 degrees: (0, 0, sin 22.5, cos 22.5).
    KeyTrack k = track({0.0, 1.0}, {0, 0, 0, 1, 0, 0, s45, s45}, 4, Interpolation::Linear, true);
    auto q = k.sample(0.5);
    CHECK(q[0] == doctest::Approx(0.0));
    CHECK(q[2] == doctest::Approx(0.38268343236508977).epsilon(1e-12));
    CHECK(q[3] == doctest::Approx(0.9238795325112867).epsilon(1e-12));
    // The same end rotation written as -q: the same (shorter) path.
    KeyTrack neg = track({0.0, 1.0}, {0, 0, 0, 1, 0, 0, -s45, -s45}, 4, Interpolation::Linear, true);
    auto qn = neg.sample(0.5);
    CHECK(qn[2] == doctest::Approx(0.38268343236508977).epsilon(1e-12));
    CHECK(qn[3] == doctest::Approx(0.9238795325112867).epsilon(1e-12));
    // A quarter: 22.5 degrees about z.
    auto q4 = k.sample(0.25);
    CHECK(q4[2] == doctest::Approx(std::sin(glm::radians(11.25))).epsilon(1e-12));
}

TEST_CASE("animation: CUBICSPLINE is the glTF Hermite with tangents scaled by the key interval") {
    // Key 0: in 0, value 1, out 3; key 1: in -1, value 2, out 0; keys 2 s apart.
    KeyTrack k = track({0.0, 2.0}, {0, 1, 3, -1, 2, 0}, 1, Interpolation::CubicSpline);
    // t = 0.5: s = 0.25; h00 = 0.84375, h10 = 0.140625, h01 = 0.15625, h11 = -0.046875:
    // 0.84375*1 + 0.140625*2*3 + 0.15625*2 + (-0.046875)*2*(-1) = 2.09375.
    CHECK(k.sample(0.5)[0] == doctest::Approx(2.09375).epsilon(1e-14));
    CHECK(k.sample(0.0)[0] == 1.0);
    CHECK(k.sample(2.0)[0] == 2.0);
}

TEST_CASE("animation: malformed samplers are SceneErrors") {
    KeyTrack k;
    k.times = {0.0, 0.0};
    k.values = {1, 2};
    k.components = 1;
    CHECK_THROWS_AS(k.validate("s"), SceneError);
    k.times = {0.0, 1.0};
    k.values = {1, 2, 3};
    CHECK_THROWS_AS(k.validate("s"), SceneError);
    k.interpolation = Interpolation::CubicSpline;
    k.values = {1, 2};
    CHECK_THROWS_AS(k.validate("s"), SceneError);  // 3 values per key
}

TEST_CASE("path: centripetal Catmull-Rom passes through its keys and matches the Hermite form") {
    CatmullRom c;
    c.points = {{0, 0, 0}, {1, 0, 0}, {1, 2, 0}, {4, 2, 1}};
    c.times = {0, 1, 2, 3};
    for (std::size_t i = 0; i < 4; ++i) CHECK(glm::length(c.at(c.times[i], false) - c.points[i]) < 1e-12);
    // Independent formulation of segment 1 (P1 -> P2): cubic Hermite with the
    // non-uniform Catmull-Rom tangents on the centripetal knots.
    const glm::dvec3 p0 = c.points[0], p1 = c.points[1], p2 = c.points[2], p3 = c.points[3];
    const double k0 = 0, k1 = std::sqrt(glm::length(p1 - p0)), k2 = k1 + std::sqrt(glm::length(p2 - p1)),
                 k3 = k2 + std::sqrt(glm::length(p3 - p2));
    const glm::dvec3 m1 = ((p1 - p0) / (k1 - k0) - (p2 - p0) / (k2 - k0) + (p2 - p1) / (k2 - k1)) * (k2 - k1);
    const glm::dvec3 m2 = ((p2 - p1) / (k2 - k1) - (p3 - p1) / (k3 - k1) + (p3 - p2) / (k3 - k2)) * (k2 - k1);
    for (double s : {0.1, 0.37, 0.5, 0.9}) {
        const double s2 = s * s, s3 = s2 * s;
        glm::dvec3 h = (2 * s3 - 3 * s2 + 1) * p1 + (s3 - 2 * s2 + s) * m1 + (-2 * s3 + 3 * s2) * p2 + (s3 - s2) * m2;
        CHECK(glm::length(c.segment(1, s) - h) < 1e-12);
    }
}

TEST_CASE("path: equally spaced collinear keys give a straight, uniform curve; constant speed is uniform") {
    CatmullRom line;
    line.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
    line.times = {0, 1, 2, 3};
    CHECK(glm::length(line.at(1.5, false) - glm::dvec3(1.5, 0, 0)) < 1e-12);
    CHECK(line.length() == doctest::Approx(3.0).epsilon(1e-9));
    // Keys at uneven times and distances: by time the speed varies, at constant speed it does not.
    CatmullRom c;
    c.points = {{0, 0, 0}, {0.5, 0, 0}, {4, 1, 0}, {5, 3, 0}};
    c.times = {0, 1, 1.5, 4};
    const int n = 100;
    std::vector<double> step;
    for (int i = 0; i < n; ++i)
        step.push_back(glm::length(c.at(4.0 * (i + 1) / n, true) - c.at(4.0 * i / n, true)));
    const double expected = c.length() / n;
    for (double s : step) CHECK(s == doctest::Approx(expected).epsilon(0.01));
    CHECK(glm::length(c.at(4.0, true) - c.points[3]) < 1e-9);
}

TEST_CASE("path: files are checked and name the problem") {
    CHECK_THROWS_WITH_AS(parsePath(R"({"camera": {"keys": [{"t": 0, "position": [0,0,0]}]}})", "p.json", ""),
                         doctest::Contains("needs t, position and target"), ConfigError);
    CHECK_THROWS_WITH_AS(parsePath(R"({"fps": 30, "camra": {}})", "p.json", ""), doctest::Contains("unknown key 'camra'"),
                         ConfigError);
    CHECK_THROWS_WITH_AS(parsePath(R"({"fps": 30})", "p.json", ""), doctest::Contains("moves nothing"), ConfigError);
    CHECK_THROWS_AS(parsePath("{", "p.json", ""), ConfigError);
    Scene gallery = loadBuiltin("gallery");
    Path p = parsePath(R"({"lights": [{"light": "lampe", "keys": [{"t": 0, "intensity": 1}]}]})", "p.json", "");
    CHECK_THROWS_WITH_AS(checkPathAgainst(p, gallery), doctest::Contains("light 'lampe' is not in scene"), ConfigError);
}

TEST_CASE("path: the named paths load for their scenes") {
    for (auto [scene, name] : std::vector<std::pair<const char*, const char*>>{{"atrium", "atrium-flythrough"},
                                                                              {"atrium", "atrium-sun-sweep"},
                                                                              {"atrium", "atrium-fast-pan"},
                                                                              {"restaurant", "restaurant-walk"},
                                                                              {"gallery", "gallery-lamp-switch"},
                                                                              {"gallery", "gallery-sphere-move"},
                                                                              {"cornell", "cornell-moving-box"}}) {
        CAPTURE(name);
        Scene s = loadBuiltin(scene);
        s.name = std::string("builtin:") + scene;
        Path p = loadPath(name, s);
        CHECK(p.frameCount() == int(std::llround(p.duration * p.fps)) + 1);
    }
}

TEST_CASE("path: the scene state at t (light switch, sun, rigid object)") {
    Scene gallery = loadBuiltin("gallery");
    Path p = parsePath(R"({"duration": 3, "lights": [{"light": "lamp", "interpolation": "step",
        "keys": [{"t": 0, "intensity": 12}, {"t": 1, "intensity": 0}, {"t": 2, "intensity": 12}]}]})", "p.json", "");
    REQUIRE(p.events == std::vector<double>{1.0, 2.0});
    auto lamp = [](const Scene& s) {
        for (auto& l : s.lights)
            if (l.name == "lamp") return l.intensity;
        return -1.0f;
    };
    Scene st = gallery;
    SceneChange ch = evaluateScene(st, gallery, &p, 1.5);
    CHECK(lamp(st) == 0.0f);
    CHECK(ch.lights);
    CHECK_FALSE(ch.geometry);
    st = gallery;
    evaluateScene(st, gallery, &p, 2.0);
    CHECK(lamp(st) == 12.0f);

    Scene atrium = loadBuiltin("atrium");
    Path sun = parsePath(R"({"sun": {"keys": [{"t": 0, "elevation": 90, "azimuth": 0}, {"t": 1, "elevation": 30, "azimuth": 90}]}})",
                         "p.json", "");
    st = atrium;
    evaluateScene(st, atrium, &sun, 0.0);
    CHECK(glm::length(st.sun()->direction - glm::vec3(0, -1, 0)) < 1e-6f);
    st = atrium;
    evaluateScene(st, atrium, &sun, 1.0);  // toward the sun: (cos30 sin90, sin30, cos30 cos90)
    CHECK(glm::length(st.sun()->direction + glm::vec3(0.8660254f, 0.5f, 0.0f)) < 1e-6f);

    Scene cornell = loadBuiltin("cornell");
    Path box = parsePath(R"({"objects": [{"select": {"min": [0.0, -0.001, -0.15], "max": [2.2, 1.66, 2.05]},
        "keys": [{"t": 0, "translate": [0, 0, 0], "rotate_y": 0}, {"t": 2, "translate": [-1, 0, 2], "rotate_y": 90}]}]})",
                         "p.json", "");
    st = cornell;
    ch = evaluateScene(st, cornell, &box, 1.0);  // half way: translate (-0.5, 0, 1), 45 degrees about the box centre
    CHECK(ch.geometry);
    const glm::dvec3 c(1.1, 0.8295, 0.95);  // centre of the selection box
    int moved = 0, kept = 0;
    const double a = glm::radians(45.0);
    for (std::size_t i = 0; i < cornell.vertices.size(); ++i) {
        const glm::dvec3 r(cornell.vertices[i].position), q(st.vertices[i].position);
        const bool inside = r.x >= 0.0 && r.x <= 2.2 && r.y >= -0.001 && r.y <= 1.66 && r.z >= -0.15 && r.z <= 2.05;
        if (!inside) {
            kept += glm::length(q - r) == 0.0;
            continue;
        }
        // y-rotation by a: x' = x cos a + z sin a, z' = -x sin a + z cos a (right-handed, about +y).
        const glm::dvec3 d = r - c;
        const glm::dvec3 e = c + glm::dvec3(-0.5, 0, 1) + glm::dvec3(d.x * std::cos(a) + d.z * std::sin(a), d.y,
                                                                    -d.x * std::sin(a) + d.z * std::cos(a));
        CHECK(glm::length(q - e) < 1e-5);
        ++moved;
    }
    CHECK(moved == 24);  // the short box: 6 faces x 4 vertices
    CHECK(kept == int(cornell.vertices.size()) - moved);
    // The state records the motion (what the GPU scene moves by its matrix): the
    // selected vertices and the matrix that takes each rest vertex where it is.
    REQUIRE(st.motions.size() == 1);
    std::uint32_t recorded = 0;
    for (auto [first, count] : st.motions[0].ranges) {
        recorded += count;
        for (std::uint32_t i = first; i < first + count; ++i) {
            const glm::dvec3 at = glm::dvec3(st.motions[0].delta * glm::dvec4(glm::dvec3(cornell.vertices[i].position), 1.0));
            CHECK(glm::length(at - glm::dvec3(st.vertices[i].position)) < 1e-6);
        }
    }
    CHECK(recorded == 24);
    st = cornell;
    evaluateScene(st, cornell, &box, 0.0);  // at rest: no motion
    CHECK(st.motions.empty());
    st = cornell;
    evaluateScene(st, cornell, &box, 1.0);
    evaluateScene(st, cornell, &box, 1.5);  // a state evaluated again starts its motions afresh
    CHECK(st.motions.size() == 1);
}

TEST_CASE("temporal: flicker is the RMS change of the error between frames") {
    FloatImage R{2, 1, 4, {0.5f, 0.5f, 0.5f, 1, 0.2f, 0.3f, 0.4f, 1}};
    std::vector<std::int32_t> same = {0, 1};
    // Identical frames, and frames that differ from the reference by the same error: exactly 0.
    CHECK(*flickerRms(R, R, R, R, same, 3) == 0.0);
    FloatImage I = R, Ip = R;
    for (std::size_t i = 0; i < 8; ++i)
        if (i % 4 != 3) {
            I.data[i] += 0.25f;
            Ip.data[i] += 0.25f;
        }
    CHECK(*flickerRms(I, R, Ip, R, same, 3) == 0.0);
    // Error +a now, -a before: the change is 2a on every pixel and channel.
    for (std::size_t i = 0; i < 8; ++i)
        if (i % 4 != 3) Ip.data[i] = R.data[i] - 0.25f;
    CHECK(*flickerRms(I, R, Ip, R, same, 3) == doctest::Approx(0.5).epsilon(1e-6));
    // Pixels not visible in the previous frame do not count; none visible: no value.
    CHECK_FALSE(flickerRms(I, R, Ip, R, {-1, -2}, 3).has_value());
}

TEST_CASE("temporal: reprojection follows the camera and finds disocclusions") {
    // A fronto-parallel wall at distance D; the camera moves right by dx:
    // the wall moves left in the image by dx / (2 D tan(fov/2) aspect) of its width.
    const int w = 64, h = 32;
    const double D = 4.0, tanHalf = std::tan(glm::radians(30.0)), aspect = double(w) / h, dx = 0.5;
    FrameGeometry g;
    g.depth = FloatImage{w, h, 4, std::vector<float>(std::size_t(w * h * 4), float(D))};
    g.view = glm::lookAt(glm::dvec3(dx, 0, 0), glm::dvec3(dx, 0, -1), glm::dvec3(0, 1, 0));
    g.prevView = glm::lookAt(glm::dvec3(0, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
    g.prevProj = glm::perspective(glm::radians(60.0), aspect, 0.1, 100.0);
    g.tanHalfFovY = tanHalf;
    g.aspect = aspect;
    std::vector<std::int32_t> m = reprojectPixels(g, g.depth);
    const double shift = dx / (2 * D * tanHalf * aspect) * w;  // pixels
    int checked = 0;
    for (int x = 0; x < w; ++x) {
        const double px = x + 0.5 + shift;
        const std::int32_t got = m[std::size_t(10 * w + x)];
        if (px >= w) CHECK(got == -1);  // came into view: disoccluded
        else if (std::abs(px - std::round(px)) > 0.01) {
            CHECK(got == 10 * w + int(px));
            ++checked;
        }
    }
    CHECK(checked > w / 2);
    // A wall that was nearer last frame (something in front): disoccluded everywhere.
    FloatImage nearer = g.depth;
    for (float& v : nearer.data) v = float(D / 2);
    for (std::int32_t p : reprojectPixels(g, nearer)) CHECK(p == -1);
}

TEST_CASE("temporal: lag, summaries and reference frames") {
    std::vector<std::optional<double>> e = {1.0, 1.0, 5.0, 3.0, std::nullopt, 1.05, 1.0};
    Lag l = lagAfter(e, 2);
    REQUIRE(l.frames.has_value());
    CHECK(*l.frames == 3);  // frame 5: 1.05 <= 1.1
    CHECK(l.peak == 5.0);
    CHECK_FALSE(lagAfter({1.0, 3.0, 3.0}, 1).frames.has_value());
    Summary s = summarize({1.0, 2.0, std::nullopt, 3.0, 4.0});
    CHECK(s.mean == 2.5);
    CHECK(s.max == 4.0);
    CHECK(s.p95 == 4.0);
    CHECK(s.count == 4);
    auto r = referenceFrames(10, 4, {});
    CHECK(r == std::vector<bool>{true, false, false, true, true, false, false, true, true, true});
}

TEST_CASE("path: LPV cascades stay put along a path that moves less than a cell, and step one cell at a time") {
    LpvSettings s;
    s.grid = {8, 8, 8};
    s.cell = 0.25f;
    const int C = 3;
    const glm::vec3 fwd(0.3f, -0.2f, -1.0f);
    auto play = [&](const std::string& json) {
        Path p = parsePath(json, "test", "p");
        std::vector<std::vector<lpv::Placement>> out;
        for (int f = 0; f < p.frameCount(); ++f) {
            Camera c = pathCamera(&p, p.timeOfFrame(f), Camera{});
            out.push_back(lpv::placeCascades(s, C, Aabb{}, c.position, fwd));
        }
        return out;
    };
    // A dolly of 0.05 m (a fifth of the finest cell) whose two ends snap alike (found by a scan):
    // every frame in between snaps alike too (no cascade jitters back and forth).
    double x0 = 1.30;
    for (; x0 < 2.0; x0 += 0.01) {
        auto a = lpv::placeCascades(s, C, Aabb{}, {float(x0), 2.1f, -0.7f}, fwd);
        auto b = lpv::placeCascades(s, C, Aabb{}, {float(x0 + 0.05), 2.1f, -0.7f}, fwd);
        bool same = true;
        for (int i = 0; i < C; ++i) same = same && a[std::size_t(i)].originCells == b[std::size_t(i)].originCells;
        if (same) break;
    }
    REQUIRE(x0 < 2.0);
    const std::string x0s = std::to_string(x0), x1s = std::to_string(x0 + 0.05);
    auto still = play(("{\"fps\": 30, \"camera\": {\"keys\": [{\"t\": 0, \"position\": [" + x0s +
                       ", 2.1, -0.7], \"target\": [" + x0s + ", 2.1, -5]}, {\"t\": 1, \"position\": [" + x1s +
                       ", 2.1, -0.7], \"target\": [" + x1s + ", 2.1, -5]}]}}")
                          .c_str());
    REQUIRE(still.size() == 31);
    for (auto& f : still)
        for (int i = 0; i < C; ++i) CHECK(f[std::size_t(i)].originCells == still[0][std::size_t(i)].originCells);
    // 3.5 finest cells along +x in 31 frames (0.028 m per frame): cascade i moves by whole cells, never more
    // than one per frame, and in total by the number of its cell boundaries the camera crossed.
    auto moving = play(R"({"fps": 30, "camera": {"keys": [{"t": 0, "position": [1.31, 2.1, -0.7], "target": [1.31, 2.1, -5]},
                                                           {"t": 1, "position": [2.185, 2.1, -0.7], "target": [2.185, 2.1, -5]}]}})");
    for (int i = 0; i < C; ++i) {
        for (std::size_t f = 1; f < moving.size(); ++f) {
            glm::ivec3 d = moving[f][std::size_t(i)].originCells - moving[f - 1][std::size_t(i)].originCells;
            CHECK((d == glm::ivec3(0) || d == glm::ivec3(1, 0, 0)));
        }
        const double cell = moving[0][std::size_t(i)].cell;
        const glm::ivec3 total = moving.back()[std::size_t(i)].originCells - moving[0][std::size_t(i)].originCells;
        // The snapped anchor is the camera plus a fixed offset: boundaries crossed = floor(b/cell) - floor(a/cell)
        // for the anchor's x, which moved by 0.875 m; between floor(0.875/cell) and that plus one.
        CHECK(total.x >= int(std::floor(0.875 / cell)));
        CHECK(total.x <= int(std::floor(0.875 / cell)) + 1);
        CHECK(total.y == 0);
        CHECK(total.z == 0);
    }
}
