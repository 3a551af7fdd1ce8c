// Issue 23: a scene that changes over time. A light switched off at frame k
// (the LPV's indirect light is 0 at frame k without temporal blending, and
// decays by the blend factor per frame with it: closed form), a moving
// object (vertex buffer and the reference's BVH follow), and the temporal
// error of a still path (flicker exactly 0).
#include "bench/path_run.h"
#include "gpu_fixture.h"
#include "render/reference/reference_passes.h"
#include "scene/path.h"

#include <cmath>
#include <filesystem>

using namespace rtgi;
using namespace rtgi::test;

namespace {

// Floor and wall lit by one point light (no sun): every bit of indirect light comes from it.
Scene lampScene() {
    Scene s = floorAndWallScene();
    Light l;
    l.type = LightType::Point;
    l.name = "lamp";
    l.position = {0.3f, 0.8f, -0.4f};
    l.intensity = 4.0f;
    s.lights.push_back(l);
    return s;
}

// Renders frames 0..n-1 of `path` (frame i at t = i / fps) and returns the indirect light of each.
std::vector<FloatImage> playIndirect(const Scene& rest, const Settings& st, const Path& path, int n, glm::ivec2 size) {
    gl::Profiler prof(false);
    Renderer r(rest, st, prof);
    Scene state = rest;
    View prev;
    std::vector<FloatImage> out;
    for (int f = 0; f < n; ++f) {
        state = rest;
        evaluateScene(state, rest, &path, path.timeOfFrame(f));
        r.updateScene(state);
        View v = makeView(pathCamera(&path, path.timeOfFrame(f), resolveCamera(state, st)), size, f ? &prev : nullptr,
                          unsigned(f));
        r.render(v);
        prev = v;
        REQUIRE(r.resources().indirectDiffuse);
        out.push_back(readTexture(r.resources().indirectDiffuse));
    }
    return out;
}

double maxAbs(const FloatImage& img) {
    double m = 0;
    for (std::size_t i = 0; i < img.data.size(); ++i)
        if (i % 4 != 3) m = std::max(m, std::abs(double(img.data[i])));
    return m;
}

}  // namespace

TEST_CASE("dynamic: a light switched off at frame k leaves no LPV light at k, or decays by lpv.temporal per frame") {
    GpuFixture gpu;
    const Scene scene = lampScene();
    // Switched off at t = 0.3 s: frame 3 at 10 fps.
    const Path path = parsePath(R"({"fps": 10, "duration": 0.7, "lights": [{"light": "lamp", "interpolation": "step",
        "keys": [{"t": 0, "intensity": 4}, {"t": 0.3, "intensity": 0}]}]})", "test", "switch");
    REQUIRE(path.events == std::vector<double>{0.3});
    const glm::ivec2 size(48, 32);
    Settings st = smallLpvSettings();
    st.lpv.temporal = 0.0f;
    auto off = playIndirect(scene, st, path, 5, size);
    REQUIRE(maxAbs(off[2]) > 1e-3);  // lit before the switch
    for (int f = 3; f < 5; ++f) {
        CAPTURE(f);
        CHECK(maxAbs(off[std::size_t(f)]) == 0.0);
    }
    // With blending t the volume after the switch is t^(j+1) times the last lit one
    // (temporal.comp: mix(current, previous, t) with current = 0), and the
    // lookup is linear in the volume: the indirect light decays the same way.
    st.lpv.temporal = 0.5f;
    auto blend = playIndirect(scene, st, path, 6, size);
    const FloatImage& lit = blend[2];
    REQUIRE(maxAbs(lit) > 1e-3);
    for (int j = 0; j < 3; ++j) {
        const FloatImage& img = blend[std::size_t(3 + j)];
        const double factor = std::pow(0.5, j + 1);
        double worst = 0;
        for (std::size_t i = 0; i < img.data.size(); ++i) {
            if (i % 4 == 3) continue;
            const double expected = factor * lit.data[i];
            // fp16 storage of the indirect image: ~1e-3 relative.
            worst = std::max(worst, std::abs(img.data[i] - expected) / (2e-3 * std::abs(expected) + 1e-6));
        }
        CAPTURE(j);
        CHECK(worst <= 1.0);
    }
}

TEST_CASE("dynamic: a moved object renders as a scene built in its new place (vertex buffer and reference BVH)") {
    GpuFixture gpu;
    // A small box lid (two quads) above the floor slides by +1 in x.
    Scene s = floorScene(2.0f, glm::vec3(0.5f), false);
    addQuad(s, {-0.6f, 0.3f, -0.2f}, {-0.2f, 0.3f, -0.2f}, {-0.2f, 0.3f, 0.2f}, {-0.6f, 0.3f, 0.2f}, 0);
    addQuad(s, {-0.6f, 0.3f, 0.2f}, {-0.2f, 0.3f, 0.2f}, {-0.2f, 0.3f, -0.2f}, {-0.6f, 0.3f, -0.2f}, 0);
    s.cameras[0].position = {0, 1.5f, 2.0f};
    s.cameras[0].target = {0, 0, 0};
    const Path path = parsePath(R"({"fps": 1, "objects": [{"select": {"min": [-0.7, 0.25, -0.3], "max": [-0.1, 0.35, 0.3]},
        "keys": [{"t": 0, "translate": [0, 0, 0]}, {"t": 1, "translate": [1, 0, 0]}]}]})", "test", "slide");
    Settings st;
    st.ao.variant = AoSettings::Variant::Off;
    st.lpv.mode = Toggle::Off;
    st.reference.kind = ReferenceSettings::Kind::Ao;
    st.reference.spp = 8;
    st.reference.cacheDir = "off";
    st.ao.radius = 1.0f;
    const glm::ivec2 size(40, 30);
    auto frame = [&](Renderer& r) {
        View v = makeView(resolveCamera(r.scene(), st), size, nullptr, 0);
        r.render(v);
        auto* out = dynamic_cast<ReferenceOutput*>(r.findPass("ref.ao"));
        REQUIRE(out);
        return std::make_pair(readTexture(out->mean()), readTexture(r.resources().gbuffer.linearDepth));
    };
    gl::Profiler prof(false);
    Renderer r(s, st, prof);
    auto [ao0, depth0] = frame(r);
    Scene moved = s;
    SceneChange ch = evaluateScene(moved, s, &path, 1.0);
    REQUIRE(ch.geometry);
    r.updateScene(moved);
    CHECK(r.lastSceneUpdate().geometry);
    auto [ao1, depth1] = frame(r);
    // The oracle: a renderer built from the moved scene (same seed, same triangles).
    gl::Profiler prof2(false);
    Renderer fresh(moved, st, prof2);
    auto [aoF, depthF] = frame(fresh);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < ao1.data.size(); i += 4) {
        CHECK(ao1.data[i] == aoF.data[i]);
        CHECK(depth1.data[i] == depthF.data[i]);
        differ += ao1.data[i] != ao0.data[i];
    }
    CHECK(differ > ao1.data.size() / 4 / 20);  // the lid's shadow and the lid moved
    r.updateScene(moved);
    CHECK_FALSE(r.lastSceneUpdate().geometry);  // nothing moved since the last update
}

TEST_CASE("dynamic: a still path has flicker exactly 0 and no disocclusion") {
    GpuFixture gpu;
    const Scene scene = lampScene();
    Settings st = smallLpvSettings();
    st.reference.spp = 4;
    st.reference.cacheDir = "off";
    gl::Profiler prof(false);
    Renderer r(scene, st, prof);
    const Path path = parsePath(R"({"fps": 10, "duration": 0.3, "camera": {"keys": [{"t": 0, "position": [0.3, 1.2, 1.5],
        "target": [0, 0, -0.6]}]}})", "test", "still");
    RunOptions opts;
    opts.resolution = {32, 24};
    opts.frames = path.frameCount();
    opts.warmup = 1;
    opts.reference = true;
    opts.outDir = (std::filesystem::temp_directory_path() / ("rtgi-dyn-" + std::to_string(::getpid()))).string();
    Camera last;
    nlohmann::json j = runPathFrames(r, path, opts, last);
    REQUIRE(j.contains("temporal"));
    const auto& t = j["temporal"];
    CHECK(t["reference_frames"] == 4);
    REQUIRE(t["flicker"].is_object());
    CHECK(t["flicker"]["max"].get<double>() == 0.0);
    CHECK(t["disoccluded_fraction"]["max"].get<double>() == 0.0);
    CHECK(t["rmse"]["mean"].get<double>() > 0.0);
    CHECK(std::filesystem::exists(opts.outDir + "/temporal.csv"));
    std::filesystem::remove_all(opts.outDir);
}
