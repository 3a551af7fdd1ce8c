// Issue 23, per-object transforms in the GPU scene (GpuScene::setTransforms,
// compute/scene/transform.comp; docs/temporal.md, "Object motion"): the
// vertices the dispatch writes against a CPU transform in double, the
// previous positions of the last rendered frame through every mix of
// transform and re-upload states, the G-buffer against the re-upload path,
// and a static scene that allocates and dispatches nothing new.
#include "gpu_fixture.h"

#include "render/gpu_scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

using Ranges = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

// A floor and a small open box (three quads of different normals) standing on it.
Scene boxScene() {
    Scene s = floorScene(4.0f, glm::vec3(0.5f), false);
    addQuad(s, {-0.4f, 0.1f, 0.3f}, {0.4f, 0.1f, 0.3f}, {0.4f, 0.9f, 0.3f}, {-0.4f, 0.9f, 0.3f}, 0);   // front
    addQuad(s, {0.4f, 0.1f, 0.3f}, {0.4f, 0.1f, -0.3f}, {0.4f, 0.9f, -0.3f}, {0.4f, 0.9f, 0.3f}, 0);   // side
    addQuad(s, {-0.4f, 0.9f, 0.3f}, {0.4f, 0.9f, 0.3f}, {0.4f, 0.9f, -0.3f}, {-0.4f, 0.9f, -0.3f}, 0);  // top
    return s;
}
const Ranges kBox = {{4, 12}};  // the box's vertices (after the floor's 4)

// Rotation about a skew axis, non-uniform scale and a translation (double).
glm::dmat4 motion(double angleDeg, glm::dvec3 t, glm::dvec3 scale) {
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), t);
    m = glm::rotate(m, glm::radians(angleDeg), glm::normalize(glm::dvec3(0.3, 1.0, -0.2)));
    return glm::scale(m, scale);
}

Scene stateOf(const Scene& rest, const glm::dmat4& m) {
    Scene s = rest;
    transformVertices(s, rest, kBox, m);
    return s;
}

std::vector<GpuVertex> download(const gl::Buffer& b) {
    std::vector<GpuVertex> v(std::size_t(b.size()) / sizeof(GpuVertex));
    b.download(v.data(), b.size());
    return v;
}

bool inBox(std::size_t i) { return i >= 4 && i < 16; }

// Positions (and normals when `normals`) of `got` against the rest scene moved by
// m in double on the box (normals by the inverse transpose), exactly the rest elsewhere.
void checkVertices(const std::vector<GpuVertex>& got, const Scene& rest, const glm::dmat4& m, bool normals) {
    REQUIRE(got.size() == rest.vertices.size());
    const glm::dmat3 nm = glm::transpose(glm::inverse(glm::dmat3(m)));
    double worstP = 0, worstN = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        const Vertex& r = rest.vertices[i];
        const glm::dvec3 gp(got[i].position[0], got[i].position[1], got[i].position[2]);
        const glm::dvec3 gn(got[i].normal[0], got[i].normal[1], got[i].normal[2]);
        CAPTURE(i);
        if (!inBox(i)) {
            CHECK(gp == glm::dvec3(r.position));
            if (normals) CHECK(gn == glm::dvec3(r.normal));
            continue;
        }
        const glm::dvec3 p = glm::dvec3(m * glm::dvec4(glm::dvec3(r.position), 1.0));
        // fp32: a 4-term dot product, each term rounded (|p| <= 3 here).
        const double ep = glm::length(gp - p);
        CHECK(ep <= 1e-5 * (1.0 + glm::length(p)));
        worstP = std::max(worstP, ep);
        if (normals) {
            const glm::dvec3 n = glm::normalize(nm * glm::dvec3(r.normal));
            const double en = glm::length(gn - n);
            CHECK(en <= 1e-5);
            worstN = std::max(worstN, en);
        }
    }
    MESSAGE("worst position error " << worstP << ", normal " << worstN);
}

bool ledgerHas(Renderer& r, const std::string& label) {
    for (auto& [name, bytes] : r.ledger().entries())
        if (name == label) return true;
    return false;
}

Settings gbufferOnly(RasterSettings::Path path = RasterSettings::Path::Hardware) {
    Settings st;
    st.raster.path = path;
    st.ao.variant = AoSettings::Variant::Off;
    st.lpv.mode = Toggle::Off;
    return st;
}

}  // namespace

TEST_CASE("transforms: the dispatch writes the CPU double transform of the object-space vertices, and the last "
          "rendered frame's positions as the previous ones") {
    GpuFixture gpu;
    const Scene rest = boxScene();
    const Settings st = gbufferOnly();
    gl::Profiler prof(false);
    prof.setMeasuring(true);
    Renderer r(rest, st, prof);
    const glm::ivec2 size(32, 24);
    View v0 = makeView(resolveCamera(rest, st), size, nullptr, 0);
    r.render(v0);
    const std::vector<GpuVertex> restGpu = download(r.gpuScene().vertices());

    const glm::dmat4 m1 = motion(35.0, {0.3, 0.2, -0.4}, {1.5, 0.5, 2.0});
    const glm::dmat4 m2 = motion(-50.0, {-0.2, 0.4, 0.1}, {0.7, 1.8, 1.1});
    r.updateScene(stateOf(rest, m1));
    REQUIRE(r.lastSceneUpdate().geometry);
    REQUIRE(r.lastSceneUpdate().transforms);
    // The first move: the box's 12 object-space vertices (32 bytes each) once, then one 144-byte transform.
    CHECK(r.lastSceneUpdate().uploadedBytes ==
          std::int64_t(12 * sizeof(gpu::MovableVertex) + sizeof(gpu::ObjectTransform)));
    View v1 = makeView(resolveCamera(rest, st), size, &v0, 1);
    r.render(v1);
    checkVertices(download(r.gpuScene().vertices()), rest, m1, true);
    // Previous positions: the rest pose frame 0 rendered.
    REQUIRE(r.gpuScene().objectMotion());
    checkVertices(download(r.gpuScene().previousVertices()), rest, glm::dmat4(1.0), false);
    // uv and material stay as uploaded.
    auto now = download(r.gpuScene().vertices());
    for (std::size_t i = 0; i < now.size(); ++i) {
        CHECK(now[i].uv[0] == restGpu[i].uv[0]);
        CHECK(now[i].uv[1] == restGpu[i].uv[1]);
        CHECK(now[i].material == restGpu[i].material);
    }

    // Two states before the next frame: the previous positions stay those of frame 1.
    r.updateScene(stateOf(rest, motion(10.0, {0, 0, 0}, {1, 1, 1})));
    r.updateScene(stateOf(rest, m2));
    CHECK(r.lastSceneUpdate().uploadedBytes == std::int64_t(sizeof(gpu::ObjectTransform)));  // matrices only
    View v2 = makeView(resolveCamera(rest, st), size, &v1, 2);
    r.render(v2);
    checkVertices(download(r.gpuScene().vertices()), rest, m2, true);
    checkVertices(download(r.gpuScene().previousVertices()), rest, m1, false);
    CHECK(ledgerHas(r, "scene.transforms"));
    CHECK(ledgerHas(r, "scene.movable_vertices"));
    prof.flush();
    bool timed = false;
    for (auto& p : prof.results()) timed = timed || p.name == "scene.transform";
    CHECK(timed);  // the dispatch is profiled as its own scope (rtgi-bench: ms.scene.transform)

    // Back to the rest pose (a state without motions): the box at the identity by transforms, the previous positions m2.
    r.updateScene(rest);
    REQUIRE(r.lastSceneUpdate().geometry);
    CHECK(r.lastSceneUpdate().transforms);
    CHECK(r.lastSceneUpdate().uploadedBytes == std::int64_t(sizeof(gpu::ObjectTransform)));
    View v3 = makeView(resolveCamera(rest, st), size, &v2, 3);
    r.render(v3);
    checkVertices(download(r.gpuScene().vertices()), rest, glm::dmat4(1.0), true);
    checkVertices(download(r.gpuScene().previousVertices()), rest, m2, false);
}

TEST_CASE("transforms: mixed with re-uploads, the previous positions are always the last rendered frame's") {
    GpuFixture gpu;
    const Scene rest = boxScene();
    const Settings st = gbufferOnly();
    gl::Profiler prof(false);
    Renderer r(rest, st, prof);
    const glm::ivec2 size(16, 16);
    std::optional<View> prev;
    auto frame = [&](int i) {
        View v = makeView(resolveCamera(rest, st), size, prev ? &*prev : nullptr, unsigned(i));
        r.render(v);
        prev = v;
    };
    frame(0);
    const glm::dmat4 m[] = {motion(20, {0.1, 0, 0}, {1, 1, 1}), motion(40, {0.2, 0.1, 0}, {1.2, 0.9, 1}),
                            motion(60, {0.3, 0.1, 0.2}, {0.8, 1.3, 1}), motion(80, {0.1, 0.3, 0.2}, {1, 1, 1.4})};
    r.updateScene(stateOf(rest, m[0]));  // by transforms
    CHECK(r.lastSceneUpdate().transforms);
    frame(1);
    Scene direct = stateOf(rest, m[1]);
    direct.motions.clear();  // vertices written directly: re-uploaded
    r.updateScene(direct);
    CHECK_FALSE(r.lastSceneUpdate().transforms);
    CHECK(r.lastSceneUpdate().uploadedBytes == r.gpuScene().vertices().size());
    frame(2);
    checkVertices(download(r.gpuScene().vertices()), rest, m[1], true);
    checkVertices(download(r.gpuScene().previousVertices()), rest, m[0], false);
    r.updateScene(stateOf(rest, m[2]));  // transforms again after a re-upload
    CHECK(r.lastSceneUpdate().transforms);
    frame(3);
    checkVertices(download(r.gpuScene().vertices()), rest, m[2], true);
    checkVertices(download(r.gpuScene().previousVertices()), rest, m[1], false);
    r.updateScene(stateOf(rest, m[3]));
    frame(4);
    checkVertices(download(r.gpuScene().vertices()), rest, m[3], true);
    checkVertices(download(r.gpuScene().previousVertices()), rest, m[2], false);
}

TEST_CASE("transforms: overlapping motions of one state fall back to the re-upload, bit for bit the CPU state") {
    GpuFixture gpu;
    const Scene rest = boxScene();
    const Settings st = gbufferOnly();
    gl::Profiler prof(false);
    Renderer r(rest, st, prof);
    Scene s = rest;
    transformVertices(s, rest, {{4, 8}}, motion(30, {0.1, 0, 0}, {1, 1, 1}));
    transformVertices(s, rest, {{8, 8}}, motion(-30, {0, 0.2, 0}, {1, 2, 1}));  // vertices 8..11 in both
    r.updateScene(s);
    CHECK(r.lastSceneUpdate().geometry);
    CHECK_FALSE(r.lastSceneUpdate().transforms);
    r.render(makeView(resolveCamera(rest, st), {16, 16}, nullptr, 0));
    auto got = download(r.gpuScene().vertices());
    for (std::size_t i = 0; i < got.size(); ++i) {
        CAPTURE(i);
        CHECK(glm::vec3(got[i].position[0], got[i].position[1], got[i].position[2]) == s.vertices[i].position);
    }
    CHECK_FALSE(ledgerHas(r, "scene.transforms"));
}

TEST_CASE("transforms: a rotated, scaled object renders the G-buffer and velocity of the re-upload path, both "
          "raster paths") {
    GpuFixture gpu;
    const Scene rest = boxScene();
    const glm::ivec2 size(48, 36);
    const glm::dmat4 m1 = motion(25.0, {0.2, 0.1, -0.1}, {1.3, 0.8, 1.1});
    const glm::dmat4 m2 = motion(40.0, {0.35, 0.15, 0.05}, {1.2, 0.9, 1.3});
    for (auto path : {RasterSettings::Path::Hardware, RasterSettings::Path::Compute}) {
        CAPTURE(int(path));
        const Settings st = gbufferOnly(path);
        struct Out {
            FloatImage depth, normal, velocity;
        };
        auto run = [&](bool transforms) {
            gl::Profiler prof(false);
            Renderer r(rest, st, prof);
            const Camera c0 = resolveCamera(rest, st), c1 = c0;  // a still camera: only the box has velocity
            View v0 = makeView(c0, size, nullptr, 0);
            Scene s1 = stateOf(rest, m1), s2 = stateOf(rest, m2);
            if (!transforms) s1.motions.clear(), s2.motions.clear();
            r.updateScene(s1);
            CHECK(r.lastSceneUpdate().transforms == transforms);
            r.render(v0);
            r.updateScene(s2);
            r.render(makeView(c1, size, &v0, 1));
            return Out{readTexture(r.resources().gbuffer.linearDepth), readTexture(r.resources().gbuffer.normal),
                       readTexture(r.resources().gbuffer.velocity)};
        };
        Out a = run(true), b = run(false);
        // Vertices differ by fp32 rounding (GPU dot product vs the CPU's double
        // transform rounded once): a pixel centre within that of a silhouette
        // may see the other surface; everywhere else the same surface.
        int same = 0, boxPixels = 0, silhouette = 0;
        for (int y = 0; y < size.y; ++y)
            for (int x = 0; x < size.x; ++x) {
                const double da = a.depth.at(x, y, 0), db = b.depth.at(x, y, 0);
                if (std::abs(da - db) > 1e-4 * std::max(da, db)) {
                    ++silhouette;
                    continue;
                }
                ++same;
                for (int c = 0; c < 3; ++c) CHECK(std::abs(a.normal.at(x, y, c) - b.normal.at(x, y, c)) <= 2e-3);
                glm::dvec2 va(a.velocity.at(x, y, 0), a.velocity.at(x, y, 1)),
                    vb(b.velocity.at(x, y, 0), b.velocity.at(x, y, 1));
                CHECK(glm::length(va - vb) <= 2e-3 * glm::length(vb) + 1e-5);
                boxPixels += glm::length(vb) > 0.0;
            }
        MESSAGE("same surface " << same << ", silhouette " << silhouette << ", moving " << boxPixels);
        CHECK(silhouette <= size.x * size.y / 100);
        CHECK(boxPixels > 30);
    }
}

TEST_CASE("transforms: a static scene with a moving camera allocates and dispatches nothing for motion") {
    GpuFixture gpu;
    const Scene rest = boxScene();
    for (auto path : {RasterSettings::Path::Hardware, RasterSettings::Path::Compute}) {
        CAPTURE(int(path));
        const Settings st = gbufferOnly(path);
        gl::Profiler prof(false);
        prof.setMeasuring(true);
        Renderer r(rest, st, prof);
        Camera c = resolveCamera(rest, st);
        std::optional<View> prev;
        for (int f = 0; f < 3; ++f) {
            r.updateScene(rest);
            CHECK_FALSE(r.lastSceneUpdate().geometry);
            CHECK(r.lastSceneUpdate().uploadedBytes == 0);
            c.position.x += 0.1f;
            View v = makeView(c, {16, 16}, prev ? &*prev : nullptr, unsigned(f));
            r.render(v);
            prev = v;
        }
        CHECK(r.gpuScene().transformObjectCount() == 0);
        CHECK_FALSE(bool(r.gpuScene().movableVertices()));
        CHECK_FALSE(bool(r.gpuScene().objectTransforms()));
        for (const char* label : {"scene.transforms", "scene.movable_vertices", "scene.prev_vertices"})
            CHECK_FALSE(ledgerHas(r, label));
        prof.flush();
        bool gbuffer = false;
        for (auto& p : prof.results()) {
            CHECK(p.name != "scene.transform");
            gbuffer = gbuffer || p.name == gbufferPassNames(st).front();
        }
        CHECK(gbuffer);  // the frames were profiled
    }
}
