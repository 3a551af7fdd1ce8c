// G-buffer and direct lighting against CPU double-precision oracles on
// analytic geometry, and pass pruning.
#include "gpu_fixture.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

// Ray through the point (x + 0.5 + dx, y + 0.5 + dy) of the pixel grid intersected with the plane y = 0,
// in double precision: returns the linear view depth (or -1 on a miss).
double cpuFloorDepth(const Camera& c, glm::ivec2 size, int x, int y, double dx = 0, double dy = 0) {
    glm::dvec3 eye(c.position), target(c.target), up(0, 1, 0);
    glm::dvec3 f = glm::normalize(target - eye);
    glm::dvec3 r = glm::normalize(glm::cross(f, up));
    glm::dvec3 u = glm::cross(r, f);
    double t = std::tan(0.5 * double(c.fovY));
    double aspect = double(size.x) / double(size.y);
    double ndcX = (x + 0.5 + dx) / size.x * 2 - 1, ndcY = (y + 0.5 + dy) / size.y * 2 - 1;
    glm::dvec3 dir = f + r * (ndcX * t * aspect) + u * (ndcY * t);  // unnormalized: view z component = 1
    if (dir.y >= 0) return -1;
    double s = -eye.y / dir.y;  // eye + s*dir hits y = 0; view depth = s (dir has unit forward component)
    return s;
}

}  // namespace

TEST_CASE("G-buffer linear depth and view-space normals match a CPU ray cast of a known plane") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene s = floorScene(20, glm::vec3(0.5f), false);
    Settings st;
    st.camera.target = glm::vec3(0, 1.6f, 0);  // horizon inside the image: sky pixels too
    const glm::ivec2 size(48, 32);
    auto r = renderFrames(s, st, size, prof);
    FloatImage depth = readTexture(r->resources().gbuffer.linearDepth);
    FloatImage normal = readTexture(r->resources().gbuffer.normal);
    Camera cam = resolveCamera(s, st);
    glm::mat4 view = glm::lookAt(cam.position, cam.target, glm::vec3(0, 1, 0));
    (void)view;
    glm::vec3 expectedN = glm::normalize(glm::mat3(view) * glm::vec3(0, 1, 0));
    GLint subpixelBits = 0;
    glGetIntegerv(GL_SUBPIXEL_BITS, &subpixelBits);
    REQUIRE(subpixelBits >= 4);  // the GL minimum
    int hits = 0, misses = 0;
    for (int y = 0; y < size.y; y += 3)
        for (int x = 0; x < size.x; x += 5) {
            double d = cpuFloorDepth(cam, size, x, y);
            INFO("pixel " << x << "," << y);
            if (d < 0 || d > 40) {
                // Sky (or beyond the 20 m floor: skip the silhouette region).
                if (d < 0) {
                    CHECK(depth.at(x, y, 0) == 0.0f);
                    ++misses;
                }
                continue;
            }
            // Only pixels well inside the floor (the floor is 40 m wide). Rasterizers
            // snap vertices to 2^-GL_SUBPIXEL_BITS of a pixel (NVIDIA: 8 bits), which
            // moves the interpolated plane by up to that much in x and y: at grazing
            // rows that exceeds 1e-4 relative (measured on an H100: 1.3e-4 at row 12),
            // so the bound adds the depth change of one sub-pixel step in each axis.
            double step = std::ldexp(1.0, -subpixelBits);
            double snap = std::abs(cpuFloorDepth(cam, size, x, y, step, 0) - d) +
                          std::abs(cpuFloorDepth(cam, size, x, y, 0, step) - d);
            CHECK(std::abs(double(depth.at(x, y, 0)) - d) <= 1e-4 * d + snap);
            CHECK(normal.at(x, y, 0) == doctest::Approx(expectedN.x).epsilon(1e-3));
            CHECK(normal.at(x, y, 1) == doctest::Approx(expectedN.y).epsilon(1e-3));
            CHECK(normal.at(x, y, 2) == doctest::Approx(expectedN.z).epsilon(1e-3));
            ++hits;
        }
    CHECK(hits > 20);
    CHECK(misses > 5);
}

TEST_CASE("direct sun lighting of a Lambertian floor equals albedo/pi * E * cos(theta)") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    for (float elevationDeg : {90.0f, 60.0f, 25.0f}) {
        float el = glm::radians(elevationDeg);
        glm::vec3 toward(std::cos(el), std::sin(el), 0.0f);
        const float e = 3.0f;
        const glm::vec3 albedo(0.6f, 0.3f, 0.1f);
        Scene s = floorScene(20, albedo, true, toward, e);
        Settings st;
        st.lpv.mode = Toggle::Off;
        auto r = renderFrames(s, st, {32, 24}, prof);
        FloatImage direct = readTexture(r->resources().direct);
        // Pixel in the lower middle: on the floor, unshadowed (nothing above it).
        int x = 16, y = 4;
        // Dielectric GGX adds a small specular lobe; roughness 1 and F0 = 0.04
        // keep it below 4 % of the diffuse term for these angles, so the
        // tolerance is 5 % of the Lambert value.
        for (int c = 0; c < 3; ++c) {
            double expected = albedo[c] / M_PI * e * std::sin(el);
            INFO("elevation " << elevationDeg << " channel " << c);
            CHECK(direct.at(x, y, c) == doctest::Approx(expected).epsilon(0.05));
        }
    }
}

TEST_CASE("a scene without a directional light skips the shadow pass and allocates nothing for it") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene s = floorScene(5, glm::vec3(0.5f), false);
    Settings st;
    auto r = renderFrames(s, st, {16, 16}, prof);
    bool skippedShadow = false;
    for (auto& k : r->skipped())
        if (k.name == "shadow") {
            skippedShadow = true;
            CHECK(k.reason.find("directional") != std::string::npos);
        }
    CHECK(skippedShadow);
    CHECK(r->findPass("shadow") == nullptr);
    // Shared textures are labelled with their resource name (render/frame_resources.cpp).
    CHECK(r->ledger().entries().count("shadowMap") == 0);
    CHECK_FALSE(bool(r->resources().shadowMap));
    // With a sun the pass runs and its map is accounted for.
    Scene lit = floorScene(5, glm::vec3(0.5f), true);
    auto r2 = renderFrames(lit, st, {16, 16}, prof);
    CHECK(r2->findPass(shadowPassName(st)) != nullptr);
    CHECK(r2->ledger().entries().count("shadowMap") == 1);
    CHECK(r2->ledger().entries().at("shadowMap") == std::int64_t(st.light.shadowSize) * st.light.shadowSize * 4);
}

TEST_CASE("a shadow caster darkens the floor beneath it and nothing else") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene s = floorScene(20, glm::vec3(0.5f), true, {0, 1, 0}, 2.0f);
    // A 2 x 2 roof at height 1 over the origin, sun straight above.
    addQuad(s, {-1, 1, 1}, {1, 1, 1}, {1, 1, -1}, {-1, 1, -1}, 0);
    s.cameras[0].position = {0, 6, 0.01f};
    s.cameras[0].target = {0, 0, 0};
    Settings st;
    st.camera.position = glm::vec3(3, 2.5f, 0.001f);
    st.camera.target = glm::vec3(0, 0, 0);
    auto r = renderFrames(s, st, {64, 48}, prof);
    FloatImage direct = readTexture(r->resources().direct);
    FloatImage depth = readTexture(r->resources().gbuffer.linearDepth);
    // Classify pixels by their world position (from depth) under or outside the roof.
    Camera cam = resolveCamera(s, st);
    View v = makeView(cam, {64, 48}, nullptr, 0);
    glm::mat4 inv = glm::inverse(v.proj * v.view);
    int under = 0, open = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            float d = depth.at(x, y, 0);
            if (d <= 0) continue;
            glm::vec4 ndc((x + 0.5f) / 32.0f - 1, (y + 0.5f) / 24.0f - 1, 0, 1);
            // Reconstruct along the pixel ray at linear depth d.
            glm::vec4 farP = inv * glm::vec4(ndc.x, ndc.y, 1, 1);
            glm::vec3 dir = glm::normalize(glm::vec3(farP) / farP.w - cam.position);
            glm::vec3 fwd = glm::normalize(cam.target - cam.position);
            glm::vec3 p = cam.position + dir * (d / glm::dot(dir, fwd));
            if (std::abs(p.y) > 0.02f) continue;  // roof pixels
            float m = std::max(std::abs(p.x), std::abs(p.z));
            if (m < 0.8f) {
                CHECK(direct.at(x, y, 0) < 0.02f);
                ++under;
            } else if (m > 1.3f) {
                CHECK(direct.at(x, y, 0) == doctest::Approx(0.5 / M_PI * 2.0).epsilon(0.06));
                ++open;
            }
        }
    CHECK(under > 10);
    CHECK(open > 10);
}

TEST_CASE("results of the frame: passes in script order, velocity zero for a static camera") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene s = floorScene(5, glm::vec3(0.5f), true);
    Settings st;
    auto r = renderFrames(s, st, {16, 12}, prof, 3);
    std::vector<std::string> expected = gbufferPassNames(st);
    expected.push_back(shadowPassName(st));
    expected.push_back("direct");
    REQUIRE(r->passes().size() >= expected.size() + 1);
    for (std::size_t i = 0; i < expected.size(); ++i) CHECK(r->passes()[i]->name() == expected[i]);
    FloatImage vel = readTexture(r->resources().gbuffer.velocity);
    for (std::size_t i = 0; i < vel.data.size(); i += 4) {
        CHECK(std::abs(vel.data[i]) < 1e-6f);
        CHECK(std::abs(vel.data[i + 1]) < 1e-6f);
    }
}
