// The per-frame light budget (render/lights.h LightSchedule, docs/lights.md
// "Light budget") on the GPU: with a budget that covers every light the frame
// equals the unbudgeted one; with a smaller budget the lights whose maps are
// not drawn yet contribute nothing (the frame equals the unbudgeted frame of
// a scene holding only the lights drawn so far: nothing uninitialized is read),
// and once every map is drawn the cached maps are reused (nothing is drawn and
// the frame equals the unbudgeted frame of the full scene).
#include "gpu_fixture.h"

#include "gl/image_io.h"
#include "render/lights.h"

#include <algorithm>
#include <cmath>
#include <string>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const glm::ivec2 kSize{48, 32};

// A floor with a box on it, lit by four point lights of intensities 1..4 on a
// row above (equal distance to the camera: the budget draws the brightest first).
Scene budgetScene(int lights) {
    Scene s = floorScene(4.0f, glm::vec3(0.7f), false);
    addQuad(s, {-0.4f, 0.6f, 0.4f}, {0.4f, 0.6f, 0.4f}, {0.4f, 0.6f, -0.4f}, {-0.4f, 0.6f, -0.4f}, 0);
    addQuad(s, {-0.4f, 0, 0.4f}, {0.4f, 0, 0.4f}, {0.4f, 0.6f, 0.4f}, {-0.4f, 0.6f, 0.4f}, 0);
    for (int i = 4 - lights; i < 4; ++i) {
        Light l;
        l.type = LightType::Point;
        l.name = "p" + std::to_string(i);
        l.position = {float(i) - 1.5f, 1.5f, -0.5f};
        l.intensity = float(i + 1);
        s.lights.push_back(l);
    }
    return s;
}

Settings budgetSettings(int budget) {
    Settings s;
    // lpv.rsm = 16: the local RSM side cannot shrink (localRsmSize), so the
    // budgeted and unbudgeted frames inject the same RSMs.
    for (auto a : {"lpv=on", "lpv.grid=8", "lpv.rsm=16", "lpv.temporal=0", "shadow.local_size=64", "ao=off",
                   "ssr=off"})
        applyAssignment(s, a);
    s.light.budget = budget;
    return s;
}

struct Frame {
    FloatImage direct, indirect;
};

Frame renderFrames(Renderer& r, const Scene& scene, int frames) {
    View prev;
    for (int f = 0; f < frames; ++f) {
        View v = makeView(resolveCamera(scene, r.settings()), kSize, f > 0 ? &prev : nullptr, unsigned(f));
        r.render(v);
        prev = v;
    }
    return {readTexture(r.resources().direct), readTexture(r.resources().indirectDiffuse)};
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

double stat(Renderer& r, const std::string& pass, const std::string& key) {
    for (auto& [k, v] : r.findPass(pass)->stats())
        if (k == key) return v;
    FAIL("no stat " << pass << "." << key);
    return 0;
}

}  // namespace

TEST_CASE_FIXTURE(GpuFixture, "light budget: a budget covering every light gives the unbudgeted frame, also from the cache") {
    Scene scene = budgetScene(4);
    gl::Profiler p0(info().timerQuery), p1(info().timerQuery);
    Renderer unbudgeted(scene, budgetSettings(0), p0), covered(scene, budgetSettings(1000), p1);
    for (int frames : {1, 3}) {
        CAPTURE(frames);
        Frame a = renderFrames(unbudgeted, scene, frames == 1 ? 1 : 2);
        Frame b = renderFrames(covered, scene, frames == 1 ? 1 : 2);
        double lit = 0;
        for (float v : a.direct.data) lit = std::max(lit, double(v));
        REQUIRE(lit > 0.0);
        CHECK(relDiff(b.direct, a.direct) < 1e-5);
        CHECK(relDiff(b.indirect, a.indirect) < 1e-4);  // float atomics: summation order
    }
    // From the second frame on the covered run draws nothing (static scene).
    CHECK(stat(covered, "shadow.local", "layers") == 0.0);
    CHECK(stat(covered, "shadow.local", "faces_cached") > 0.0);
    CHECK(stat(unbudgeted, "shadow.local", "layers") == 24.0);
}

TEST_CASE_FIXTURE(GpuFixture, "light budget: lights without maps wait, then the cached maps are reused") {
    Scene scene = budgetScene(4);
    gl::Profiler prof(info().timerQuery);
    // 12 faces a frame: one light's shadow faces in view and its six RSMs.
    Renderer r(scene, budgetSettings(12), prof);
    View prev;
    for (int frame = 0; frame < 6; ++frame) {
        CAPTURE(frame);
        View v = makeView(resolveCamera(scene, r.settings()), kSize, frame > 0 ? &prev : nullptr, unsigned(frame));
        r.render(v);
        prev = v;
        Frame got{readTexture(r.resources().direct), readTexture(r.resources().indirectDiffuse)};
        // The oracle: the unbudgeted frame of the scene with the lights drawn so far
        // (brightest first: p3, p2, p1, p0).
        const int drawn = std::min(frame + 1, 4);
        Scene part = budgetScene(drawn);
        gl::Profiler pp(info().timerQuery);
        Renderer ref(part, budgetSettings(0), pp);
        Frame want = renderFrames(ref, part, 1);
        CHECK(relDiff(got.direct, want.direct) < 1e-5);
        CHECK(relDiff(got.indirect, want.indirect) < 1e-4);
        CHECK(stat(r, "shadow.local", "lights_waiting") == double(4 - drawn));
        if (frame >= 4) {  // every map drawn: the cached ones are reused, nothing is drawn
            CHECK(stat(r, "shadow.local", "layers") == 0.0);
            CHECK(stat(r, "lpv.rsm", "local_injected") == 24.0);
        } else {
            CHECK(stat(r, "shadow.local", "layers") >= 1.0);
            CHECK(stat(r, "shadow.local", "layers") <= 6.0);
        }
    }
    // The hook for moving lights: a changed light is redrawn (alone) and stays lit.
    r.lightChanged(0);
    r.render(makeView(resolveCamera(scene, r.settings()), kSize, &prev, 6));
    CHECK(stat(r, "shadow.local", "layers") >= 1.0);
    CHECK(stat(r, "shadow.local", "lights_waiting") == 0.0);
}
