#pragma once
// Shared helpers of the GPU tier: a fresh EGL context per test case (Mesa
// llvmpipe in CI), with KHR_debug on, and small analytic scenes.
#include "gl/context.h"
#include "gl/image_io.h"
#include "render/renderer.h"
#include "render/visibility/visibility.h"
#include "test_scenes.h"

#include <doctest/doctest.h>

#include <cstdint>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace rtgi::test {

struct GpuFixture {
    std::unique_ptr<gl::HeadlessContext> ctx;
    GpuFixture() {
        ctx = gl::HeadlessContext::create({-1, true});
        gl::takeDebugErrorCount();
    }
    ~GpuFixture() {
        // Every GPU test also asserts that the driver reported no GL error.
        CHECK(gl::takeDebugErrorCount() == 0);
    }
    const gl::ContextInfo& info() const { return ctx->info(); }
};


// A horizontal square floor at y = 0 of half-size h, albedo `albedo`, with
// an optional sun (direction towards the sun, irradiance).
inline Scene floorScene(float h, glm::vec3 albedo, bool withSun, glm::vec3 towardSun = {0, 1, 0}, float e = 1.0f) {
    Scene s;
    s.name = "test:floor";
    Material m;
    m.baseColor = glm::vec4(albedo, 1);
    m.roughness = 1.0f;
    s.materials.push_back(m);
    addQuad(s, {-h, 0, h}, {h, 0, h}, {h, 0, -h}, {-h, 0, -h}, 0);
    if (withSun) {
        Light l;
        l.type = LightType::Directional;
        l.direction = -glm::normalize(towardSun);
        l.intensity = e;
        s.lights.push_back(l);
    }
    Camera c;
    c.position = {0, 2, 3};
    c.target = {0, 0, 0};
    c.fovY = glm::radians(60.0f);
    c.near = 0.1f;
    c.far = 50.0f;
    s.cameras.push_back(c);
    return s;
}

// Floor [-2,2]^2 at y = 0 and a wall at z = -1, x in [-2,2], y in [0, 1.5],
// facing +z: AO partly occluded near the wall (reference tests).
inline Scene floorAndWallScene() {
    Scene s = floorScene(2.0f, glm::vec3(0.5f), false);
    s.name = "test:corner";
    addQuad(s, {-2, 0, -1}, {2, 0, -1}, {2, 1.5f, -1}, {-2, 1.5f, -1}, 0);
    s.cameras[0].position = {0.3f, 1.2f, 1.5f};
    s.cameras[0].target = {0, 0, -0.6f};
    return s;
}

// Renders `frames` frames of scene with settings at size; returns the renderer.
inline std::unique_ptr<Renderer> renderFrames(const Scene& scene, const Settings& settings, glm::ivec2 size,
                                              gl::Profiler& profiler, int frames = 1, bool check = false) {
    auto r = std::make_unique<Renderer>(scene, settings, profiler);
    r->setCheck(check);
    Camera cam = resolveCamera(scene, settings);
    View prev;
    for (int f = 0; f < frames; ++f) {
        View v = makeView(cam, size, f == 0 ? nullptr : &prev, unsigned(f));
        r->render(v);
        prev = v;
    }
    glFinish();
    return r;
}

// A 2D texture of format fmt filled from `comps` floats per texel.
inline gl::Texture floatTexture(gl::MemoryLedger& ledger, const char* label, GLenum fmt, int w, int h, int comps,
                                const std::vector<float>& data) {
    gl::Texture t(ledger, label, {GL_TEXTURE_2D, fmt, w, h});
    GLenum f = comps == 1 ? GL_RED : comps == 2 ? GL_RG : GL_RGBA;
    glTextureSubImage2D(t.id(), 0, 0, 0, w, h, f, GL_FLOAT, data.data());
    return t;
}

// Renders `frames` frames with --check on; CHECKs that no output holds NaN or
// Inf (each offender named) and returns their total count.
inline std::uint64_t nonFinite(const Scene& s, const Settings& st, glm::ivec2 size, int frames = 2) {
    gl::Profiler prof(false);
    Renderer r(s, st, prof);
    r.setCheck(true);
    Camera cam = resolveCamera(s, st);
    View prev;
    for (int f = 0; f < frames; ++f) {
        View v = makeView(cam, size, f ? &prev : nullptr, unsigned(f));
        r.render(v);
        prev = v;
    }
    std::uint64_t bad = 0;
    for (auto& c : r.finiteCounts()) {
        INFO(c.pass << " " << c.resource << " nan=" << c.nan << " inf=" << c.inf);
        CHECK(c.nan + c.inf == 0);
        bad += c.nan + c.inf;
    }
    CHECK_FALSE(r.finiteCounts().empty());
    return bad;
}

// LPV on at a size llvmpipe runs in well under a second (8^3, 4 iterations,
// RSM 64^2, shadow map 256^2).
// The path tracer's one-bounce Lambert indirect light (reference=indirect,
// reference.bounces=1, reference.specular=off, uncached) with `s`'s scene settings.
inline Settings oneBounceReference(Settings s, int spp) {
    s.lpv.mode = Toggle::Off;
    s.reference.kind = ReferenceSettings::Kind::Indirect;
    s.reference.spp = spp;
    s.reference.bounces = 1;
    s.reference.specular = false;
    s.reference.cacheDir = "off";
    return s;
}

// LPV alone (AO, and with it the bent-normal lookup, off: the LPV tests test the volume).
// Passes that rasterize the camera's G-buffer and the sun's shadow map under
// the settings' raster.path (auto: compute on the device, hardware on llvmpipe).
inline std::vector<std::string> gbufferPassNames(const Settings& s) {
    if (useComputeRaster(s)) return {"visibility.raster", "visibility.resolve"};
    return {"gbuffer"};
}
inline std::string shadowPassName(const Settings& s) { return useComputeRasterLightViews(s) ? "shadow.raster" : "shadow"; }

inline Settings smallLpvSettings() {
    Settings s;
    s.ao.variant = AoSettings::Variant::Off;
    s.lpv.mode = Toggle::On;
    s.lpv.grid = glm::ivec3(8);
    s.lpv.iterations = 4;
    s.lpv.rsm = 64;
    // The single-volume KD10 scheme the oracles of these tests derive (cascades, flow
    // re-emission and energy conservation have tests of their own).
    s.lpv.cascades = 1;
    s.lpv.reemit = LpvSettings::Reemit::Face;
    s.lpv.energyConserving = false;
    // The geometry volume's blocking and the plain Chebyshev bound of the lookup (the defaults until
    // the fifth leak pass): the raster baseline propagates the same way; the face openness and the
    // sharpened lookup have tests of their own (test_lpv_leaks.cpp).
    s.lpv.blocking = LpvSettings::Blocking::Oriented;
    s.lpv.visibilityExponent = 1;
    s.lpv.coarseIterations = 0;  // every cascade runs lpv.iterations (the oracles' scheme)
    s.light.shadowSize = 256;
    return s;
}

// The scene uniformly scaled by k about the origin, cameras included (scale
// invariance and precision-at-scale tests).
inline Scene scaledScene(Scene s, float k) {
    for (auto& v : s.vertices) v.position *= k;
    for (auto& c : s.cameras) {
        c.position *= k;
        c.target *= k;
        c.near *= k;
        c.far *= k;
    }
    return s;
}

// World position of pixel (x, y) of a `size` image from the G-buffer's
// linear depth (depth.glsl conventions), in double precision.
inline glm::dvec3 worldPosition(const Scene& scene, const Settings& s, glm::ivec2 size, const FloatImage& depth, int x,
                                int y) {
    Camera cam = resolveCamera(scene, s);
    View v = makeView(cam, size, nullptr, 0);
    double d = depth.at(x, y, 0);
    double th = std::tan(0.5 * double(cam.fovY)), aspect = double(size.x) / double(size.y);
    glm::dvec2 ndc((x + 0.5) / size.x * 2.0 - 1.0, (y + 0.5) / size.y * 2.0 - 1.0);
    glm::dvec4 vp(ndc.x * th * aspect * d, ndc.y * th * d, -d, 1.0);
    return glm::dvec3(glm::inverse(glm::dmat4(v.view)) * vp);
}

// Closed box [-1,1]^3 of inward-facing quads, albedo a, emission le, with a
// camera inside it (furnace tests, closed-box flux oracles).
inline Scene closedBoxScene(float albedo, float le) {
    Scene s;
    s.name = "test:closed-box";
    Material m;
    m.baseColor = glm::vec4(glm::vec3(albedo), 1);
    m.emissive = glm::vec3(le);
    m.roughness = 1.0f;
    s.materials.push_back(m);
    for (int axis = 0; axis < 3; ++axis)
        for (float side : {-1.0f, 1.0f}) {
            glm::vec3 q[4];
            const float uv[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
            for (int k = 0; k < 4; ++k) {
                q[k][axis] = side;
                q[k][(axis + 1) % 3] = uv[k][0];
                q[k][(axis + 2) % 3] = uv[k][1];
            }
            glm::vec3 n = glm::cross(q[1] - q[0], q[3] - q[0]), c = 0.25f * (q[0] + q[1] + q[2] + q[3]);
            if (glm::dot(n, -c) > 0) addQuad(s, q[0], q[1], q[2], q[3], 0);
            else addQuad(s, q[0], q[3], q[2], q[1], 0);
        }
    Camera c;
    c.position = {0.2f, 0.1f, 0.3f};
    c.target = {-0.5f, -0.3f, -1.0f};
    c.fovY = glm::radians(70.0f);
    c.near = 0.05f;
    c.far = 10.0f;
    s.cameras.push_back(c);
    return s;
}

// Irradiance at p (unit normal n) from a uniform Lambertian polygon of
// radiance le with corners q (either winding), two-sided, unoccluded:
// E = le/2 |Σ_i θ_i n·(v_i × v_{i+1})/|v_i × v_{i+1}||, v_i = q_i − p
// (Lambert's polygon formula; e.g. Arvo 1995, "The irradiance Jacobian").
inline double polygonIrradiance(glm::dvec3 p, glm::dvec3 n, const std::vector<glm::dvec3>& q, double le) {
    double sum = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
        glm::dvec3 a = glm::normalize(q[i] - p), b = glm::normalize(q[(i + 1) % q.size()] - p);
        glm::dvec3 c = glm::cross(a, b);
        double len = glm::length(c);
        if (len > 0) sum += std::acos(std::max(-1.0, std::min(1.0, glm::dot(a, b)))) * glm::dot(n, c) / len;
    }
    return 0.5 * le * std::abs(sum);
}

}  // namespace rtgi::test
