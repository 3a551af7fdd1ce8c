// Stress cases of SSR (issue 9): thickness 0 and huge, reflected rays
// parallel to the view direction (camera looking straight down at a mirror),
// every tracer. Oracles: finiteness of every output, and geometry: a ray
// reflected off a floor with nothing above it can hit nothing, so the
// confidence (hit mask) must be 0 wherever a ray leaves towards the camera.
#include "gpu_fixture.h"

#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

// Mirror floor (metallic, roughness 0) and an emissive wall at z = -3.
Scene mirrorWithWall() {
    Scene s = floorScene(10, glm::vec3(1.0f), true, {0.3f, 1, 0.4f}, 2.0f);
    s.materials[0].metallic = 1.0f;
    s.materials[0].roughness = 0.0f;
    Material wall;
    wall.baseColor = glm::vec4(0.5f, 0.5f, 0.5f, 1);
    wall.roughness = 1.0f;
    wall.emissive = glm::vec3(2.0f);
    s.materials.push_back(wall);
    addQuad(s, {-2, 0, -3}, {2, 0, -3}, {2, 2, -3}, {-2, 2, -3}, 1);
    return s;
}

struct SsrRun {
    FloatImage confidence;
    std::uint64_t bad = 0;
};

SsrRun runSsr(const Scene& s, const Settings& st, glm::ivec2 size) {
    gl::Profiler prof(false);
    auto rp = renderFrames(s, st, size, prof, 3, /*check=*/true);
    Renderer& r = *rp;
    SsrRun out;
    int ssrOutputs = 0;
    for (auto& c : r.finiteCounts()) {
        INFO(c.pass << " " << c.resource << " nan=" << c.nan << " inf=" << c.inf << " neg=" << c.negative);
        CHECK(c.nan + c.inf == 0);
        CHECK(c.negative == 0);
        out.bad += c.nan + c.inf;
        ssrOutputs += c.pass.rfind("ssr.", 0) == 0;
    }
    CHECK(ssrOutputs >= 6);
    out.confidence = readTexture(r.resources().specularOcclusion);
    return out;
}

}  // namespace

TEST_CASE("stress: SSR thickness 0 and 1e6, every tracer, stays finite") {
    GpuFixture gpu;
    Scene s = mirrorWithWall();
    s.cameras[0].position = {0, 1, 2};
    s.cameras[0].target = {0, 0.5f, -3};
    for (auto tracer : {SsrSettings::Tracer::Linear, SsrSettings::Tracer::Dda, SsrSettings::Tracer::Hiz})
        for (float thickness : {0.0f, 1e6f}) {
            Settings st;
            st.ssr.tracer = tracer;
            st.ssr.thickness = thickness;
            INFO(std::string(toString(tracer)) << " thickness " << thickness);
            SsrRun r = runSsr(s, st, {24, 16});
            CHECK(r.bad == 0);
            float lo = 1, hi = 0;
            for (int y = 0; y < r.confidence.height; ++y)
                for (int x = 0; x < r.confidence.width; ++x) {
                    lo = std::min(lo, r.confidence.at(x, y, 0));
                    hi = std::max(hi, r.confidence.at(x, y, 0));
                }
            // The confidence is a weight in [0, 1] whatever the thickness.
            CHECK(lo >= 0.0f);
            CHECK(hi <= 1.0f);
        }
}

TEST_CASE("stress: SSR rays parallel to the view (camera straight down on a mirror) hit nothing and stay finite") {
    GpuFixture gpu;
    Scene s = floorScene(10, glm::vec3(1.0f), true, {0.3f, 1, 0.4f}, 2.0f);
    s.materials[0].metallic = 1.0f;
    s.materials[0].roughness = 0.0f;
    // Straight down: the centre pixel's reflected ray points exactly back at the camera (its
    // screen-space direction is the zero vector); the others leave upwards into empty space.
    s.cameras[0].position = {0, 3, 0};
    s.cameras[0].target = {0, 0, 0};
    for (auto tracer : {SsrSettings::Tracer::Linear, SsrSettings::Tracer::Dda, SsrSettings::Tracer::Hiz})
        for (float thickness : {0.0f, 0.2f, 1e6f}) {
            Settings st;
            st.ssr.tracer = tracer;
            st.ssr.thickness = thickness;
            st.ssr.halfResolution = false;
            INFO(std::string(toString(tracer)) << " thickness " << thickness);
            SsrRun r = runSsr(s, st, {17, 17});  // odd: one pixel centre lies exactly on the view axis
            CHECK(r.bad == 0);
            // Nothing lies above the floor: every reflected ray leaves towards the camera, in front
            // of the depth buffer, so no thickness can turn it into a hit.
            float hi = 0;
            for (int y = 0; y < r.confidence.height; ++y)
                for (int x = 0; x < r.confidence.width; ++x) hi = std::max(hi, r.confidence.at(x, y, 0));
            CHECK(hi == 0.0f);
        }
}
