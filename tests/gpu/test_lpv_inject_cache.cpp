// The local lights' injection cache (lpv.inject_cache, docs/lights.md "Injection cache"): with the
// scene static the cascades' local-light injection is re-used (nothing injected), and after every
// change it depends on — a light moved, a light's intensity, the geometry (its version), a
// cascade's placement — the frame re-injects what changed and equals the frame of a renderer
// that injects every face every frame (lpv.inject_cache=off), to the float tolerance of the
// atomics' summation order. The cache is not allocated without local lights.
#include "gpu_fixture.h"

#include "gl/image_io.h"
#include "render/lights.h"
#include "render/lpv/lpv_math.h"

#include <algorithm>
#include <cmath>
#include <string>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const glm::ivec2 kSize{48, 32};

// A floor with a box on it, three point lights above.
Scene cacheScene() {
    Scene s = floorScene(4.0f, glm::vec3(0.7f), false);
    addQuad(s, {-0.4f, 0.6f, 0.4f}, {0.4f, 0.6f, 0.4f}, {0.4f, 0.6f, -0.4f}, {-0.4f, 0.6f, -0.4f}, 0);
    addQuad(s, {-0.4f, 0, 0.4f}, {0.4f, 0, 0.4f}, {0.4f, 0.6f, 0.4f}, {-0.4f, 0.6f, 0.4f}, 0);
    for (int i = 0; i < 3; ++i) {
        Light l;
        l.type = LightType::Point;
        l.name = "p" + std::to_string(i);
        l.position = {float(i) - 1.0f, 1.2f, -0.3f + 0.3f * float(i)};
        l.intensity = 2.0f + float(i);
        s.lights.push_back(l);
    }
    s.cameras[0].position = {0.0f, 2.0f, 3.5f};
    s.cameras[0].target = {0.0f, 0.3f, 0.0f};
    return s;
}

Settings cacheSettings(bool cache) {
    Settings s;
    for (auto a : {"lpv=on", "lpv.grid=8", "lpv.rsm=16", "lpv.temporal=0", "shadow.local_size=32", "ao=off", "ssr=off",
                   "light.budget=1000"})
        applyAssignment(s, a);
    applyAssignment(s, cache ? "lpv.inject_cache=on" : "lpv.inject_cache=off");
    return s;
}

double stat(Renderer& r, const std::string& pass, const std::string& key) {
    for (auto& [k, v] : r.findPass(pass)->stats())
        if (k == key) return v;
    FAIL("no stat " << pass << "." << key);
    return 0;
}

// Largest |a - b| relative to the largest |b| (every channel).
double relDiff(const FloatImage& a, const FloatImage& b) {
    REQUIRE(a.data.size() == b.data.size());
    double d = 0, m = 1e-30;
    for (std::size_t i = 0; i < a.data.size(); ++i) {
        REQUIRE(std::isfinite(a.data[i]));
        d = std::max(d, double(std::abs(a.data[i] - b.data[i])));
        m = std::max(m, double(std::abs(b.data[i])));
    }
    return d / m;
}

std::int64_t ledgerBytes(Renderer& r, const std::string& prefix) {
    std::int64_t b = 0;
    for (auto& [name, bytes] : r.ledger().entries())
        if (name.rfind(prefix, 0) == 0) b += bytes;
    return b;
}

// Two renderers, the cache on and off (or the settings given), fed the same scene states and cameras.
struct Pair {
    gl::Profiler p0{false}, p1{false};
    Renderer cached, plain;
    Camera cam;
    View prev;
    unsigned frame = 0;
    FloatImage last;  // the cached renderer's previous indirect image
    explicit Pair(const Scene& s, const Settings& on = cacheSettings(true), const Settings& off = cacheSettings(false))
        : cached(s, on, p0), plain(s, off, p1), cam(resolveCamera(s, on)) {}
    void update(const Scene& state) {
        cached.updateScene(state);
        plain.updateScene(state);
    }
    // Renders both; the cached frame must equal the uncached one. Returns the indirect image.
    FloatImage render() {
        View v = makeView(cam, kSize, frame ? &prev : nullptr, frame);
        cached.render(v);
        plain.render(v);
        prev = v;
        ++frame;
        FloatImage a = readTexture(cached.resources().indirectDiffuse), b = readTexture(plain.resources().indirectDiffuse);
        double lit = 0;
        for (float x : b.data) lit = std::max(lit, double(x));
        REQUIRE(lit > 0.0);
        CHECK(relDiff(a, b) < 1e-4);  // float atomics: summation order
        CHECK(stat(plain, "lpv.inject", "local_faces_from_cache") == 0.0);
        return a;
    }
    double injected() { return stat(cached, "lpv.inject", "local_faces_injected"); }
    double fromCache() { return stat(cached, "lpv.inject", "local_faces_from_cache"); }
    double rebuilds() { return stat(cached, "lpv.inject", "cache_rebuilds"); }
};

}  // namespace

TEST_CASE_FIXTURE(GpuFixture, "LPV injection cache: re-used while static, re-injected after each change, equal to the uncached frame") {
    Scene scene = cacheScene();
    Pair p(scene);
    const int faces = 18, cascades = p.cached.settings().lpv.cascades;
    REQUIRE(cascades == 2);
    // Frame 0 draws every face (dynamic: injected into the volumes), frame 1 adds them to the
    // caches, frame 2 and later take everything from the caches.
    FloatImage img = p.render();
    CHECK(p.injected() == double(faces * cascades));
    CHECK(p.fromCache() == 0.0);
    img = p.render();
    CHECK(p.injected() == double(faces * cascades));
    CHECK(p.fromCache() == 0.0);
    img = p.render();
    CHECK(p.injected() == 0.0);
    CHECK(p.fromCache() == double(faces * cascades));
    CHECK(p.rebuilds() == 0.0);
    CHECK(stat(p.cached, "lpv.inject", "dropped_texels") == stat(p.plain, "lpv.inject", "dropped_texels"));
    CHECK(ledgerBytes(p.cached, "lpv.inject_cache") > 0);
    CHECK(ledgerBytes(p.plain, "lpv.inject_cache") == 0);

    // Each change must show in the indirect light (else the comparison with the uncached frame
    // could not catch a stale cache): relative change > 100x the tolerance.
    auto changed = [](const FloatImage& before, const FloatImage& after) { return relDiff(after, before) > 1e-2; };
    SUBCASE("moving one light") {
        Scene s = scene;
        s.lights[1].position += glm::vec3(0.5f, 0.0f, 0.4f);
        p.update(s);
        FloatImage moved = p.render();
        CHECK(changed(img, moved));
        CHECK(p.rebuilds() == double(cascades));  // its cached faces were drawn again
        CHECK(p.fromCache() == 0.0);
        CHECK(p.injected() == double((faces - 6) * cascades + 6 * cascades));  // the others again, the light's on top
        p.render();
        CHECK(p.injected() == double(6 * cascades));  // now up to date: added to the caches
        CHECK(p.rebuilds() == 0.0);
        p.render();
        CHECK(p.injected() == 0.0);
    }
    SUBCASE("changing a light's intensity") {
        Scene s = scene;
        s.lights[0].intensity *= 4.0f;
        p.update(s);
        FloatImage brighter = p.render();
        CHECK(changed(img, brighter));
        CHECK(p.rebuilds() == double(cascades));
        p.render();
        CHECK(p.injected() == double(6 * cascades));
        p.render();
        CHECK(p.injected() == 0.0);
    }
    SUBCASE("moving geometry (the geometry version)") {
        Scene s = scene;
        for (std::size_t i = 4; i < s.vertices.size(); ++i) s.vertices[i].position += glm::vec3(0.6f, 0.3f, 0.0f);  // the box
        p.update(s);
        REQUIRE(p.cached.lastSceneUpdate().geometry);
        FloatImage moved = p.render();
        CHECK(changed(img, moved));
        CHECK(p.rebuilds() == 0.0);  // every face drawn again: nothing cacheable, the caches are dropped
        CHECK(p.fromCache() == 0.0);
        CHECK(p.injected() == double(faces * cascades));
        p.render();
        CHECK(p.rebuilds() == double(cascades));  // the caches were dropped: filled again from every face
        CHECK(p.injected() == double(faces * cascades));
        p.render();
        CHECK(p.injected() == 0.0);
    }
    SUBCASE("moving a cascade") {
        // 1.5 m along x: cascade 0 (8 cells of ~0.67 m, following the camera) is placed elsewhere.
        const Camera before = p.cam;
        p.cam.position.x += 1.5f;
        p.cam.target.x += 1.5f;
        const auto& ls = p.cached.settings().lpv;
        auto place = [&](const Camera& c) {
            return lpv::placeCascades(ls, cascades, scene.bounds(), c.position, glm::normalize(c.target - c.position));
        };
        const auto a = place(before), b = place(p.cam);
        REQUIRE(a[0].originCells != b[0].originCells);
        const int moved = (a[0].originCells != b[0].originCells) + (a[1].originCells != b[1].originCells);
        p.render();
        CHECK(p.rebuilds() == double(moved));
        CHECK(p.fromCache() == double(faces * (cascades - moved)));
        CHECK(p.injected() == double(faces * moved));
        p.render();
        CHECK(p.injected() == 0.0);
        CHECK(p.rebuilds() == 0.0);
    }
}

TEST_CASE_FIXTURE(GpuFixture, "LPV injection cache: no cache volume without local lights, or with light.budget=0") {
    Scene sunOnly = floorScene(2.0f, glm::vec3(0.5f), true);
    gl::Profiler p0(false), p1(false);
    Renderer sun(sunOnly, cacheSettings(true), p0);
    Settings unbudgeted = cacheSettings(true);
    applyAssignment(unbudgeted, "light.budget=0");
    Scene lights = cacheScene();
    Renderer every(lights, unbudgeted, p1);
    View prev;
    for (unsigned f = 0; f < 3; ++f) {
        View vs = makeView(resolveCamera(sunOnly, sun.settings()), kSize, f ? &prev : nullptr, f);
        sun.render(vs);
        every.render(makeView(resolveCamera(lights, every.settings()), kSize, nullptr, f));
        prev = vs;
    }
    CHECK(ledgerBytes(sun, "lpv.inject_cache") == 0);
    CHECK(ledgerBytes(sun, "lpv.rsm.local") == 0);
    CHECK(ledgerBytes(every, "lpv.inject_cache") == 0);
    CHECK(stat(every, "lpv.inject", "local_faces_injected") == 18.0 * 2.0);  // every face, every frame
    CHECK(ledgerBytes(every, "lpv.rsm.local") > 0);
}

// lpv.sun_cache (docs/lpv.md, "Sun injection cache"): with the sun the only injection, its RSM and packed
// volume are kept while the sun, the geometry and the cascades stay; every change the frame depends on
// redraws them, and every frame equals the frame of a renderer that draws and injects every frame.
TEST_CASE_FIXTURE(GpuFixture, "LPV sun injection cache: kept while static, redrawn after each change, equal to the uncached frame") {
    Scene scene = floorScene(4.0f, glm::vec3(0.7f), true, glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f)), 2.0f);
    addQuad(scene, {-0.4f, 0.6f, 0.4f}, {0.4f, 0.6f, 0.4f}, {0.4f, 0.6f, -0.4f}, {-0.4f, 0.6f, -0.4f}, 0);
    addQuad(scene, {-0.4f, 0, 0.4f}, {0.4f, 0, 0.4f}, {0.4f, 0.6f, 0.4f}, {-0.4f, 0.6f, 0.4f}, 0);
    scene.cameras[0].position = {0.0f, 2.0f, 3.5f};
    scene.cameras[0].target = {0.0f, 0.3f, 0.0f};
    Settings on = cacheSettings(true), off = cacheSettings(true);
    applyAssignment(off, "lpv.sun_cache=off");
    Pair p(scene, on, off);
    auto kept = [&](Renderer& r) { return stat(r, "lpv.pack", "sun_cached"); };
    FloatImage img = p.render();
    CHECK(kept(p.cached) == 0.0);  // frame 0 draws and injects, and keeps the packed volume
    p.render();
    CHECK(kept(p.cached) == 1.0);
    img = p.render();
    CHECK(kept(p.cached) == 1.0);
    CHECK(kept(p.plain) == 0.0);
    CHECK(stat(p.cached, "lpv.rsm", "rsms") == 1.0);
    CHECK(stat(p.cached, "lpv.inject", "dropped_texels") == stat(p.plain, "lpv.inject", "dropped_texels"));
    CHECK(ledgerBytes(p.cached, "lpv.sun_cache") > 0);
    CHECK(ledgerBytes(p.plain, "lpv.sun_cache") == 0);

    auto changed = [](const FloatImage& before, const FloatImage& after) { return relDiff(after, before) > 1e-2; };
    auto again = [&](const FloatImage& before) {
        FloatImage now = p.render();  // Pair::render: equal to the uncached frame
        CHECK(changed(before, now));
        CHECK(kept(p.cached) == 0.0);
        p.render();
        CHECK(kept(p.cached) == 1.0);
    };
    SUBCASE("moving the sun") {
        Scene s = scene;
        s.lights[0].direction = -glm::normalize(glm::vec3(-0.5f, 1.0f, 0.2f));
        p.update(s);
        again(img);
    }
    SUBCASE("changing the sun's intensity") {
        Scene s = scene;
        s.lights[0].intensity *= 3.0f;
        p.update(s);
        again(img);
    }
    SUBCASE("moving geometry (the geometry version)") {
        Scene s = scene;
        for (std::size_t i = 4; i < s.vertices.size(); ++i) s.vertices[i].position += glm::vec3(0.6f, 0.3f, 0.0f);  // the box
        p.update(s);
        REQUIRE(p.cached.lastSceneUpdate().geometry);
        again(img);
    }
    SUBCASE("moving a cascade (the camera-following finer cascade)") {
        p.cam.position.x += 1.5f;
        p.cam.target.x += 1.5f;
        FloatImage now = p.render();
        CHECK(kept(p.cached) == 0.0);
        p.render();
        CHECK(kept(p.cached) == 1.0);
    }
}

TEST_CASE_FIXTURE(GpuFixture, "LPV injection cache with band 2 (lpv.sh_order=2): the frames taken from the cache equal the uncached ones") {
    // Band 2 copies four more volumes out of the cache (hi r, g, b in one dispatch, last in another).
    Settings on = cacheSettings(true), off = cacheSettings(false);
    applyAssignment(on, "lpv.sh_order=2");
    applyAssignment(off, "lpv.sh_order=2");
    Pair p(cacheScene(), on, off);
    for (int f = 0; f < 3; ++f) p.render();  // each render checks the cached frame against the uncached one
    CHECK(p.injected() == 0.0);
    CHECK(p.fromCache() > 0.0);
    CHECK(ledgerBytes(p.cached, "lpv.inject_cache_hi") > 0);
}
