// shadow.cache: the sun's shadow map is redrawn only when its light frustum,
// size, writer or the geometry changed. Oracle: the frame that reuses the map
// is bit-identical to the frame that redraws it every time, and a map reused
// after a change of the sun equals the map a fresh renderer draws.
#include "gl/image_io.h"
#include "gpu_fixture.h"
#include "scene/builtin.h"

using namespace rtgi;
using namespace rtgi::test;

namespace {

double passStat(const Renderer& r, const std::string& pass, const std::string& key) {
    Pass* p = r.findPass(pass);
    REQUIRE(p != nullptr);
    for (auto& [k, v] : p->stats())
        if (k == key) return v;
    FAIL("no stat " << key << " in " << pass);
    return -1;
}

bool sameImage(const FloatImage& a, const FloatImage& b) {
    return a.width == b.width && a.height == b.height && a.channels == b.channels && a.data == b.data;
}

Settings cacheSettings(RasterSettings::Path path, bool cache) {
    Settings s = smallLpvSettings();
    s.raster.path = path;
    s.light.shadowSize = 128;
    s.light.shadowCache = cache;
    s.lpv.mode = Toggle::Off;  // no float atomics: the frames compare bit for bit
    return s;
}

}  // namespace

TEST_CASE("shadow.cache: a reused sun shadow map gives the same frame as one redrawn every frame") {
    GpuFixture gpu;
    Scene scene = loadBuiltin("box-on-plane");
    for (auto path : {RasterSettings::Path::Hardware, RasterSettings::Path::Compute}) {
        Settings on = cacheSettings(path, true), off = cacheSettings(path, false);
        const std::string pass = shadowPassName(on);
        INFO(pass);
        gl::Profiler p1(false), p2(false);
        auto cached = renderFrames(scene, on, {32, 24}, p1, 3);
        auto redrawn = renderFrames(scene, off, {32, 24}, p2, 3);
        CHECK(passStat(*cached, pass, "redraws") == 1);  // static sun and geometry: drawn once
        CHECK(passStat(*redrawn, pass, "redraws") == 3);
        CHECK(sameImage(readTexture(cached->resources().shadowMap), readTexture(redrawn->resources().shadowMap)));
        CHECK(sameImage(readTexture(cached->resources().hdr), readTexture(redrawn->resources().hdr)));
    }
}

TEST_CASE("shadow.cache: a new sun direction or new geometry redraws the map") {
    GpuFixture gpu;
    Scene scene = loadBuiltin("box-on-plane");
    Settings s = cacheSettings(RasterSettings::Path::Hardware, true);
    gl::Profiler prof(false);
    auto r = renderFrames(scene, s, {32, 24}, prof, 2);
    const FloatImage before = readTexture(r->resources().shadowMap);

    Settings turned = s;
    turned.light.sunDirection = glm::vec3(-0.6f, 1.0f, 0.1f);
    r->configure(turned);
    Camera cam = resolveCamera(scene, turned);
    r->render(makeView(cam, {32, 24}, nullptr, 2));
    glFinish();
    CHECK(passStat(*r, "shadow", "redraws") == 1);  // the rebuilt pass drew it once, for the new sun
    const FloatImage after = readTexture(r->resources().shadowMap);
    CHECK_FALSE(sameImage(before, after));
    gl::Profiler fresh(false);
    auto f = renderFrames(scene, turned, {32, 24}, fresh, 1);
    CHECK(sameImage(after, readTexture(f->resources().shadowMap)));

    // Same sun again: reused; geometry changed: redrawn.
    r->render(makeView(cam, {32, 24}, nullptr, 3));
    CHECK(passStat(*r, "shadow", "redraws") == 1);
    Scene moved = scene;  // an object moved (issue 23): the renderer rewrites the vertices
    for (auto& v : moved.vertices)
        if (v.position.y > 0.01f) v.position.x += 0.05f;
    r->updateScene(moved);
    r->render(makeView(cam, {32, 24}, nullptr, 4));
    CHECK(passStat(*r, "shadow", "redraws") == 2);
}
