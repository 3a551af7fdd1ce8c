// Point, spot and area lights of the real-time path (render/lights.h,
// post/direct.comp, shadow.local) against CPU double oracles: the
// inverse-square cosine law with the BRDF of brdf.glsl written out in double,
// the KHR_lights_punctual spot cone, shadows of a cube against a CPU ray cast,
// culling and pass gating.
#include "gpu_fixture.h"

#include "render/lights.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const glm::ivec2 kSize{64, 48};

// Lambert + GGX (height-correlated Smith, Schlick F0 = 0.04), dielectric,
// as specified in brdf.glsl's comments, evaluated in double.
double brdfCos(glm::dvec3 n, glm::dvec3 v, glm::dvec3 l, double albedo, double roughness) {
    double nl = glm::dot(n, l);
    if (nl <= 0) return 0;
    double nv = std::max(glm::dot(n, v), 1e-4);
    glm::dvec3 h = glm::normalize(l + v);
    double a = std::max(roughness * roughness, 1e-3), a2 = a * a;
    double nh = std::max(glm::dot(n, h), 0.0);
    double t = nh * nh * (a2 - 1) + 1;
    double D = a2 / (M_PI * t * t);
    double V = 0.5 / (nl * std::sqrt(nv * nv * (1 - a2) + a2) + nv * std::sqrt(nl * nl * (1 - a2) + a2));
    double F = 0.04 + 0.96 * std::pow(1.0 - std::clamp(glm::dot(v, h), 0.0, 1.0), 5.0);
    return (albedo / M_PI + F * D * V) * nl;
}

// KHR_lights_punctual, "Inner and Outer Cone Angles": scale = 1 / max(0.001,
// cos inner − cos outer), offset = −cos outer · scale, t = saturate(cd·scale +
// offset), attenuation t².
double khrSpot(double cd, double inner, double outer) {
    double scale = 1.0 / std::max(0.001, std::cos(inner) - std::cos(outer));
    double t = std::clamp(cd * scale - std::cos(outer) * scale, 0.0, 1.0);
    return t * t;
}

Light pointLight(glm::vec3 p, float intensity) {
    Light l;
    l.type = LightType::Point;
    l.name = "point";
    l.position = p;
    l.intensity = intensity;
    return l;
}

Light spotLight(glm::vec3 p, glm::vec3 dir, float intensity, float inner, float outer) {
    Light l = pointLight(p, intensity);
    l.type = LightType::Spot;
    l.name = "spot";
    l.direction = dir;
    l.innerCone = inner;
    l.outerCone = outer;
    return l;
}

// Box [lo, hi] of outward-facing quads, material m.
void addBox(Scene& s, glm::vec3 lo, glm::vec3 hi, int m) {
    glm::vec3 c[8];
    for (int i = 0; i < 8; ++i) c[i] = {(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z};
    glm::vec3 centre = 0.5f * (lo + hi);
    auto face = [&](int a, int b, int cc, int d) {
        glm::vec3 n = glm::cross(c[b] - c[a], c[d] - c[a]);
        if (glm::dot(n, 0.25f * (c[a] + c[b] + c[cc] + c[d]) - centre) > 0) addQuad(s, c[a], c[b], c[cc], c[d], m);
        else addQuad(s, c[a], c[d], c[cc], c[b], m);
    };
    face(0, 1, 3, 2);
    face(4, 5, 7, 6);
    face(0, 1, 5, 4);
    face(2, 3, 7, 6);
    face(0, 2, 6, 4);
    face(1, 3, 7, 5);
}

// Segment p -> q against the box grown by g (negative: shrunk), slab test in double.
bool segmentHitsBox(glm::dvec3 p, glm::dvec3 q, glm::dvec3 lo, glm::dvec3 hi, double g) {
    glm::dvec3 d = q - p;
    double t0 = 0, t1 = 1;
    for (int a = 0; a < 3; ++a) {
        double l = lo[a] - g, h = hi[a] + g;
        if (std::abs(d[a]) < 1e-15) {
            if (p[a] < l || p[a] > h) return false;
            continue;
        }
        double ta = (l - p[a]) / d[a], tb = (h - p[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) return false;
    }
    return true;
}

Settings lightSettings() {
    Settings st;
    st.lpv.mode = Toggle::Off;
    st.light.localShadowSize = 512;
    return st;
}

struct Frame {
    FloatImage direct, depth;
    std::unique_ptr<Renderer> r;
};

// Calls fn(x, y, p) for every pixel that sees geometry, p its world position (double).
template <class F>
void forEachSurfacePixel(const Frame& f, const Scene& s, const Settings& st, F&& fn) {
    for (int y = 0; y < kSize.y; ++y)
        for (int x = 0; x < kSize.x; ++x)
            if (f.depth.at(x, y, 0) > 0) fn(x, y, worldPosition(s, st, kSize, f.depth, x, y));
}

Frame render(const Scene& s, const Settings& st, gl::Profiler& prof) {
    Frame f;
    f.r = renderFrames(s, st, kSize, prof);
    f.direct = readTexture(f.r->resources().direct);
    f.depth = readTexture(f.r->resources().gbuffer.linearDepth);
    return f;
}

}  // namespace

TEST_CASE("Local lights: a point light on a plane follows the inverse-square cosine law (double oracle)") {
    GpuFixture fx;
    gl::Profiler prof(false);
    const double albedo = 0.6, I = 3.0;
    Scene s = floorScene(4.0f, glm::vec3(float(albedo)), false);
    const glm::dvec3 lp(0.4, 1.5, -0.3);
    s.lights.push_back(pointLight(glm::vec3(lp), float(I)));
    Settings st = lightSettings();
    Frame f = render(s, st, prof);
    REQUIRE(f.r->findPass("shadow.local") != nullptr);
    CHECK(f.r->localLightsShadowed() == 1);
    Camera cam = resolveCamera(s, st);
    int n = 0, bad = 0;
    double worst = 0;
    forEachSurfacePixel(f, s, st, [&](int x, int y, glm::dvec3 p) {
        if (std::abs(p.x) > 3.9 || std::abs(p.z) > 3.9) return;  // the floor's silhouette
        glm::dvec3 toL = lp - p, v = glm::normalize(glm::dvec3(cam.position) - p);
        double d2 = glm::dot(toL, toL);
        double expect = brdfCos({0, 1, 0}, v, toL / std::sqrt(d2), albedo, 1.0) * I / d2;
        double got = f.direct.at(x, y, 0);
        double rel = std::abs(got - expect) / expect;
        worst = std::max(worst, rel);
        // fp16 output (5e-4) and the G-buffer position (depth in fp32).
        if (rel > 5e-3) ++bad;
        ++n;
    });
    INFO("floor pixels " << n << ", worst relative error " << worst);
    REQUIRE(n > 1000);
    CHECK(bad == 0);  // also: no shadow acne anywhere on the receiver
}

TEST_CASE("Local lights: spot cone falloff follows the KHR_lights_punctual formula") {
    GpuFixture fx;
    gl::Profiler prof(false);
    const double albedo = 0.5, I = 4.0, inner = glm::radians(15.0), outer = glm::radians(35.0);
    Scene s = floorScene(4.0f, glm::vec3(float(albedo)), false);
    const glm::dvec3 lp(0.0, 1.2, 0.0), dir = glm::normalize(glm::dvec3(0.2, -1.0, 0.1));
    s.lights.push_back(spotLight(glm::vec3(lp), glm::vec3(dir), float(I), float(inner), float(outer)));
    s.cameras[0].position = {0.0f, 2.5f, 1.5f};
    s.cameras[0].target = {0.1f, 0.0f, 0.0f};
    Settings st = lightSettings();
    Frame f = render(s, st, prof);
    Camera cam = resolveCamera(s, st);
    int n = 0, penumbra = 0, bad = 0;
    forEachSurfacePixel(f, s, st, [&](int x, int y, glm::dvec3 p) {
        glm::dvec3 toL = lp - p, l = glm::normalize(toL), v = glm::normalize(glm::dvec3(cam.position) - p);
        double cd = glm::dot(-l, dir);
        double expect = brdfCos({0, 1, 0}, v, l, albedo, 1.0) * I / glm::dot(toL, toL) * khrSpot(cd, inner, outer);
        double got = f.direct.at(x, y, 0);
        if (std::abs(got - expect) > 5e-3 * expect + 2e-4) ++bad;
        if (cd > std::cos(outer) && cd < std::cos(inner)) ++penumbra;
        ++n;
    });
    INFO("pixels " << n << ", in the penumbra " << penumbra << ", off " << bad);
    REQUIRE(penumbra > 50);
    CHECK(bad <= n / 200);  // PCF at the cone's rim may differ on a handful
}

TEST_CASE("Local lights: spot and point shadows of a cube agree with a CPU ray cast (>= 99 % away from edges)") {
    GpuFixture fx;
    gl::Profiler prof(false);
    const glm::dvec3 lo(-0.3, 0.4, -0.3), hi(0.3, 0.9, 0.3);
    for (int kind = 0; kind < 2; ++kind) {
        Scene s = floorScene(4.0f, glm::vec3(0.5f), false);
        addBox(s, glm::vec3(lo), glm::vec3(hi), 0);
        glm::dvec3 lp = kind == 0 ? glm::dvec3(0.25, 2.2, 0.1) : glm::dvec3(-0.2, 1.6, 0.3);
        if (kind == 0)
            s.lights.push_back(spotLight(glm::vec3(lp), {0, -1, 0}, 8.0f, glm::radians(50.0f), glm::radians(60.0f)));
        else
            s.lights.push_back(pointLight(glm::vec3(lp), 4.0f));
        s.cameras[0].position = {0.0f, 3.5f, 2.5f};
        s.cameras[0].target = {0.0f, 0.0f, 0.0f};
        Settings st = lightSettings();
        Frame f = render(s, st, prof);
        Camera cam = resolveCamera(s, st);
        int n = 0, agree = 0, shadowed = 0;
        forEachSurfacePixel(f, s, st, [&](int x, int y, glm::dvec3 p) {
            if (std::abs(p.y) > 1e-3 || std::abs(p.x) > 3.5 || std::abs(p.z) > 3.5) return;  // floor only
            // Away from edges: the answer does not change when the cube
            // grows or shrinks by 3 cm (a few shadow texels there).
            bool grown = segmentHitsBox(p, lp, lo, hi, 0.03), shrunk = segmentHitsBox(p, lp, lo, hi, -0.03);
            if (grown != shrunk) return;
            glm::dvec3 toL = lp - p, l = glm::normalize(toL), v = glm::normalize(glm::dvec3(cam.position) - p);
            double unshadowed = brdfCos({0, 1, 0}, v, l, 0.5, 1.0) * (kind == 0 ? 8.0 : 4.0) / glm::dot(toL, toL);
            if (kind == 0) unshadowed *= khrSpot(glm::dot(-l, glm::dvec3(0, -1, 0)), glm::radians(50.0), glm::radians(60.0));
            if (unshadowed < 1e-3) return;  // outside the cone: nothing to decide
            bool gpuShadowed = f.direct.at(x, y, 0) < 0.5 * unshadowed;
            agree += gpuShadowed == grown;
            shadowed += grown;
            ++n;
        });
        INFO((kind == 0 ? "spot" : "point") << ": pixels " << n << ", CPU-shadowed " << shadowed << ", agree " << agree);
        REQUIRE(n > 500);
        REQUIRE(shadowed > 30);
        CHECK(agree >= 0.99 * n);
    }
}

TEST_CASE("Local lights: zero intensity and out-of-view lights are left out with a reason") {
    GpuFixture fx;
    gl::Profiler prof(false);
    Scene s = floorScene(4.0f, glm::vec3(0.5f), false);
    Settings st = lightSettings();
    {
        Frame f = render(s, st, prof);  // no local light at all
        CHECK(f.r->findPass("shadow.local") == nullptr);
        CHECK(f.r->ledger().entries().count("shadow.local.maps") == 0);
    }
    Light dark = pointLight({0, 1, 0}, 0.0f);
    dark.name = "dark";
    s.lights.push_back(dark);
    {
        Frame f = render(s, st, prof);
        CHECK(f.r->findPass("shadow.local") == nullptr);  // only a zero-intensity light
        bool listed = false;
        for (auto& k : f.r->skipped()) listed |= k.name == "light:dark" && k.reason == "zero intensity";
        CHECK(listed);
    }
    // A ranged light far behind the camera: its sphere misses the frustum.
    Light far = pointLight({0, 1, 40}, 5.0f);
    far.range = 2.0f;
    s.lights.push_back(far);
    s.lights.push_back(pointLight({0, 1, 0}, 1.0f));
    Frame f = render(s, st, prof);
    CHECK(f.r->localLightsCulled() == 2);  // the dark one and the far one
    CHECK(f.r->localLightsShadowed() == 1);
    // Influence radius of an unranged light: I/r² equals the cutoff.
    LocalLights ll = resolveLocalLights(s, st);
    REQUIRE(ll.lights.size() == 3);
    CHECK(ll.lights[2].influence == doctest::Approx(std::sqrt(1.0 / lightCutoffIrradiance(1.0f))));
    CHECK(ll.lights[1].influence == doctest::Approx(2.0f));
}

namespace {

// Lambert's formula on the polygon q clipped (Sutherland–Hodgman, double)
// to the half-space above p's tangent plane: the irradiance of a one-sided
// uniform emitter of radiance le whose front faces p (written here in
// double, independently of lib/lights.glsl's fp32 clipping).
double clippedPolygonIrradiance(glm::dvec3 p, glm::dvec3 n, const std::vector<glm::dvec3>& q, double le) {
    std::vector<glm::dvec3> c;
    for (std::size_t i = 0; i < q.size(); ++i) {
        glm::dvec3 a = q[i], b = q[(i + 1) % q.size()];
        double ha = glm::dot(a - p, n), hb = glm::dot(b - p, n);
        if (ha >= 0) c.push_back(a);
        if ((ha >= 0) != (hb >= 0)) c.push_back(a + (b - a) * (ha / (ha - hb)));
    }
    return c.size() < 3 ? 0.0 : polygonIrradiance(p, n, c, le);
}

// ∫ over the rectangle centre ± u ± v (emitting along u × v, radiance le) of
// f(ω)·max(n·ω, 0)·max(−nₗ·ω, 0)/r² dA by the midpoint rule on k × k cells:
// the reflected radiance for a BRDF f, by brute force in double.
template <class F>
double integrateOverRectangle(glm::dvec3 p, glm::dvec3 n, glm::dvec3 c, glm::dvec3 u, glm::dvec3 v, double le, int k,
                              F&& f) {
    const glm::dvec3 nl = glm::normalize(glm::cross(u, v));
    const double cell = 4.0 * glm::length(u) * glm::length(v) / (double(k) * k);
    double sum = 0;
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
            glm::dvec3 x = c + u * ((i + 0.5) / k * 2 - 1) + v * ((j + 0.5) / k * 2 - 1);
            glm::dvec3 d = x - p;
            double r2 = glm::dot(d, d);
            glm::dvec3 w = d / std::sqrt(r2);
            double cosR = glm::dot(n, w), cosL = -glm::dot(nl, w);
            if (cosR > 0 && cosL > 0) sum += f(w) * cosR * cosL / r2;
        }
    return sum * cell * le;
}

// GGX alone (dielectric F0 = 0.04, no cosine): brdfCos minus its Lambert part, over cos.
double ggxSpecular(glm::dvec3 n, glm::dvec3 v, glm::dvec3 l, double roughness) {
    double nl = glm::dot(n, l);
    return nl > 0 ? (brdfCos(n, v, l, 0.0, roughness)) / nl : 0.0;
}

}  // namespace

TEST_CASE("Area lights: a rectangular emitter is one area light; unshadowed, the direct pass equals Lambert's polygon "
          "formula (with horizon clipping) below and beside it") {
    GpuFixture fx;
    gl::Profiler prof(false);
    // 0.44 x 0.3 m (aspect < 1.5: one rectangle, not a strip), 0.6 m above the floor
    const double albedo = 0.6, le = 8.0, hu = 0.22, hv = 0.15, y0 = 0.6;
    Scene s = floorScene(4.0f, glm::vec3(float(albedo)), false);
    Material e;
    e.baseColor = glm::vec4(0, 0, 0, 1);
    e.emissive = glm::vec3(float(le));
    s.materials.push_back(e);
    const float u = float(hu), v = float(hv), yf = float(y0);
    addQuad(s, {-u, yf, -v}, {u, yf, -v}, {u, yf, v}, {-u, yf, v}, 1);  // normal -y (faces the floor)
    // A low wall at x = 0.1 facing +x, under the emitter: its tangent plane
    // cuts the rectangle, so only the part at x > 0.1 lights it (clipping).
    addQuad(s, {0.1f, 0.0f, 1.0f}, {0.1f, 0.0f, -1.0f}, {0.1f, 0.45f, -1.0f}, {0.1f, 0.45f, 1.0f}, 0);
    s.cameras[0].position = {1.6f, 1.1f, 1.4f};
    s.cameras[0].target = {0.0f, 0.15f, 0.0f};
    Settings st = lightSettings();
    st.post.passesOff = "shadow.local";  // unshadowed: the oracle has no occlusion
    st.light.emissiveSplit = 1;
    LocalLights ll = resolveLocalLights(s, st);
    REQUIRE(ll.lights.size() == 1);
    const LocalLight& L = ll.lights[0];
    // Centroid, normal, I0 = Le·A and the rectangle: an independent reading of the quad.
    CHECK(L.gpu.positionRange.x == doctest::Approx(0.0).epsilon(1e-6));
    CHECK(L.gpu.directionType.y == doctest::Approx(-1.0f));
    CHECK(L.gpu.colorIntensity.x == doctest::Approx(le * 4 * hu * hv).epsilon(1e-5));
    CHECK(int(L.gpu.directionType.w) == RTGI_LIGHT_AREA);
    CHECK(glm::dvec3(L.shape.centerRadius).y == doctest::Approx(y0));
    const double lu = glm::length(glm::dvec3(L.shape.halfU)), lv = glm::length(glm::dvec3(L.shape.halfV));
    CHECK(std::max(lu, lv) == doctest::Approx(hu).epsilon(1e-5));
    CHECK(std::min(lu, lv) == doctest::Approx(hv).epsilon(1e-5));
    CHECK(glm::normalize(glm::cross(glm::dvec3(L.shape.halfU), glm::dvec3(L.shape.halfV))).y == doctest::Approx(-1.0));

    // emissive.split=2 cuts it into four lights whose diffuse terms sum to the same closed form.
    for (int split : {1, 2}) {
        CAPTURE(split);
        st.light.emissiveSplit = split;
        REQUIRE(resolveLocalLights(s, st).lights.size() == std::size_t(split * split));
        Frame f = render(s, st, prof);
        Camera cam = resolveCamera(s, st);
        const std::vector<glm::dvec3> quad = {{-hu, y0, -hv}, {hu, y0, -hv}, {hu, y0, hv}, {-hu, y0, hv}};
        int floorN = 0, wallN = 0, clipped = 0, bad = 0;
        double worst = 0;
        forEachSurfacePixel(f, s, st, [&](int x, int y, glm::dvec3 p) {
            glm::dvec3 n;
            if (std::abs(p.y) < 1e-3 && std::abs(p.x) < 1.9 && std::abs(p.z) < 1.9 && p.x > 0.12) n = {0, 1, 0};
            else if (std::abs(p.x - 0.1) < 1e-3 && p.y > 0.02 && p.y < 0.43 && std::abs(p.z) < 0.95) n = {1, 0, 0};
            else return;
            glm::dvec3 vdir = glm::normalize(glm::dvec3(cam.position) - p);
            // Diffuse: ρ/π · Lambert's closed form; the small GGX lobe of the
            // dielectric (F0 = 0.04, roughness 1) integrated by brute force.
            double diffuse = albedo / M_PI * clippedPolygonIrradiance(p, n, quad, le);
            double spec = integrateOverRectangle(p, n, {0, y0, 0}, {hu, 0, 0}, {0, 0, hv}, le, 64,
                                                 [&](glm::dvec3 w) { return ggxSpecular(n, vdir, w, 1.0); });
            double expect = diffuse + spec, got = f.direct.at(x, y, 0);
            double err = std::abs(got - expect) / expect;
            worst = std::max(worst, err);
            if (err > 0.01) ++bad;
            (n.y > 0 ? floorN : wallN)++;
            // The wall's tangent plane cuts the rectangle: without clipping, Lambert's formula would be off.
            if (n.x > 0 && std::abs(polygonIrradiance(p, n, quad, le) / clippedPolygonIrradiance(p, n, quad, le) - 1) > 0.05)
                ++clipped;
        });
        MESSAGE("floor pixels " << floorN << ", wall pixels " << wallN << " (" << clipped << " clipped), off by > 1 % "
                                << bad << ", worst " << worst);
        REQUIRE(floorN > 500);
        REQUIRE(wallN > 100);
        CHECK(clipped > wallN / 2);  // the wall pixels do test the clipping
        CHECK(bad <= (floorN + wallN) / 200);  // ≤ 0.5 % of the pixels (the representative-point GGX is ~3 % of the total)
        CHECK(worst < 0.03);
    }
}

TEST_CASE("Area lights: the representative-point GGX term against numerical integration of GGX over the rectangle") {
    GpuFixture fx;
    gl::Profiler prof(false);
    const double le = 4.0, hu = 0.3, hv = 0.2, y0 = 0.7;
    Scene s = floorScene(4.0f, glm::vec3(1.0f), false);
    s.materials[0].metallic = 1.0f;  // F0 = base colour = 1: F = 1, no diffuse lobe
    Material e;
    e.baseColor = glm::vec4(0, 0, 0, 1);
    e.emissive = glm::vec3(float(le));
    s.materials.push_back(e);
    const float u = float(hu), v = float(hv), yf = float(y0);
    addQuad(s, {-u, yf, -v}, {u, yf, -v}, {u, yf, v}, {-u, yf, v}, 1);
    s.cameras[0].position = {0.0f, 1.0f, 1.8f};
    s.cameras[0].target = {0.0f, 0.0f, -0.3f};
    Settings st = lightSettings();
    st.post.passesOff = "shadow.local";
    Camera cam = resolveCamera(s, st);
    for (double rough : {0.3, 0.5, 0.75, 1.0}) {
        s.materials[0].roughness = float(rough);
        Frame f = render(s, st, prof);
        double se = 0, sr = 0, got = 0, want = 0;
        int n = 0;
        forEachSurfacePixel(f, s, st, [&](int x, int y, glm::dvec3 p) {
            if (std::abs(p.y) > 1e-3 || std::abs(p.x) > 1.5 || p.z < -1.5 || (x + y) % 2) return;
            glm::dvec3 nn(0, 1, 0), vdir = glm::normalize(glm::dvec3(cam.position) - p);
            const double a = std::max(rough * rough, 1e-3), a2 = a * a;
            double ref = integrateOverRectangle(p, nn, {0, y0, 0}, {hu, 0, 0}, {0, 0, hv}, le, 160, [&](glm::dvec3 w) {
                glm::dvec3 h = glm::normalize(w + vdir);
                double nl = glm::dot(nn, w), nv = std::max(glm::dot(nn, vdir), 1e-4), nh = std::max(h.y, 0.0);
                double t = nh * nh * (a2 - 1) + 1;
                double V = 0.5 / (nl * std::sqrt(nv * nv * (1 - a2) + a2) + nv * std::sqrt(nl * nl * (1 - a2) + a2));
                return a2 / (M_PI * t * t) * V;  // F = 1
            });
            double g = f.direct.at(x, y, 0);
            se += (g - ref) * (g - ref);
            sr += ref * ref;
            got += g;
            want += ref;
            ++n;
        });
        const double relRmse = std::sqrt(se / sr), energy = got / want;
        MESSAGE("roughness " << rough << ": relative RMSE " << relRmse << ", energy ratio " << energy << " (" << n
                             << " pixels)");
        REQUIRE(n > 200);
        // Documented tolerance (docs/lights.md "Area shading"): the
        // representative point keeps the reflected energy within 15 % and
        // the per-pixel relative RMSE within 40 % for roughness >= 0.3
        // (measured: energy 0.89-0.99, relative RMSE 0.36 at 0.3, 0.05 at 1).
        CHECK(std::abs(energy - 1.0) < 0.15);
        CHECK(relRmse < (rough >= 0.75 ? 0.15 : 0.40));
    }
}

namespace {

// Visibility across a straight shadow edge at x = 0 (along z): per floor
// pixel with |z| < 0.5, shadowed / unshadowed direct light, binned by x over
// [−2·half, 2·half]; where it crosses 0.1, 0.5 and 0.9 (linear interpolation
// between bin centres), and the mean in the outermost bins.
struct PenumbraProfile {
    double x10 = 0, x50 = 0, x90 = 0, umbra = 0, lit = 0;
    int filled = 0;
};
PenumbraProfile penumbraProfile(const Frame& lit, const Frame& shadowed, const Scene& s, const Settings& st, double half) {
    const int bins = 40;
    const double lo = -2 * half, hi = 2 * half;
    std::vector<double> sum(bins, 0.0);
    std::vector<int> count(bins, 0);
    forEachSurfacePixel(shadowed, s, st, [&](int x, int y, glm::dvec3 p) {
        if (std::abs(p.y) > 1e-3 || std::abs(p.z) > 0.5 || p.x < lo || p.x >= hi) return;
        double base = lit.direct.at(x, y, 0);
        if (!(base > 0)) return;
        int b = int((p.x - lo) / (hi - lo) * bins);
        sum[std::size_t(b)] += shadowed.direct.at(x, y, 0) / base;
        ++count[std::size_t(b)];
    });
    auto crossing = [&](double level) {
        double prevX = 0, prevV = -1;
        for (int b = 0; b < bins; ++b) {
            if (count[std::size_t(b)] == 0) continue;
            double x = lo + (b + 0.5) * (hi - lo) / bins, vis = sum[std::size_t(b)] / count[std::size_t(b)];
            if (prevV >= 0 && prevV < level && vis >= level) return prevX + (x - prevX) * (level - prevV) / (vis - prevV);
            prevX = x, prevV = vis;
        }
        return std::nan("");
    };
    PenumbraProfile r;
    for (int c : count) r.filled += c > 0;
    r.x10 = crossing(0.1), r.x50 = crossing(0.5), r.x90 = crossing(0.9);
    r.umbra = sum[1] / std::max(count[1], 1);
    r.lit = sum[bins - 2] / std::max(count[bins - 2], 1);
    return r;
}

// Floor, a plate at height hB covering x < 0 (edge along z at x = 0), camera
// under the plate looking along −z so the edge crosses the columns.
Scene plateScene(double hB, bool plate) {
    Scene s = floorScene(4.0f, glm::vec3(0.7f), false);
    s.cameras[0].position = {0.0f, 0.3f, 1.0f};
    s.cameras[0].target = {0.0f, 0.0f, -0.3f};
    s.cameras[0].fovY = glm::radians(60.0f);
    if (plate) addBox(s, {-3.0f, float(hB) - 0.01f, -3.0f}, {0.0f, float(hB), 3.0f}, 0);
    return s;
}

}  // namespace

TEST_CASE("Area lights: the penumbra of a plate's edge under a rectangular light has the similar-triangles width") {
    GpuFixture fx;
    gl::Profiler prof(false);
    const double le = 5.0, hx = 0.2, hz = 0.1, H = 1.0, hB = 0.5;
    Scene open = plateScene(hB, false), s = plateScene(hB, true);
    for (Scene* sc : {&open, &s}) {
        Material e;
        e.baseColor = glm::vec4(0, 0, 0, 1);
        e.emissive = glm::vec3(float(le));
        const int m = int(sc->materials.size());
        sc->materials.push_back(e);
        const float u = float(hx), v = float(hz), yf = float(H);
        addQuad(*sc, {-u, yf, -v}, {u, yf, -v}, {u, yf, v}, {-u, yf, v}, m);
    }
    Settings st = lightSettings();
    for (int split : {1, 2}) {  // one light, or four (emissive.split) whose penumbrae add up to the same
        CAPTURE(split);
        st.light.emissiveSplit = split;
        Frame lit = render(open, st, prof), shadowed = render(s, st, prof);
        // A ray from (x, 0) to the light point (l, H) passes the plate's plane at
        // x + (l − x)·hB/H, so the penumbra spans |x| ≤ hx·hB/(H − hB) and the
        // visibility rises linearly in l (uniform over the rectangle's width):
        // 0.1 and 0.9 at ∓0.8·half.
        const double half = hx * hB / (H - hB);
        PenumbraProfile r = penumbraProfile(lit, shadowed, s, st, half);
        MESSAGE("rectangle, split " << split << ": penumbra 10-90 % width " << r.x90 - r.x10 << " (predicted "
                                    << 1.6 * half << "), x(0.5) " << r.x50);
        REQUIRE(r.filled > 30);
        REQUIRE(std::isfinite(r.x10));
        REQUIRE(std::isfinite(r.x90));
        CHECK(std::abs((r.x90 - r.x10) / (1.6 * half) - 1.0) < 0.25);
        CHECK(std::abs(r.x50) < 0.15 * half);
        CHECK(r.umbra < 0.05);  // deep in the umbra
        CHECK(r.lit > 0.95);    // fully outside
    }
}

TEST_CASE("Area lights: the shadow of a tall box (a blocker spanning many depths) against the exact visible share of "
          "the rectangle; the split light's shadow is at least as close") {
    GpuFixture fx;
    gl::Profiler prof(false);
    // A 0.5 x 0.4 m panel 1 m up; a box 0.5 m wide and 0.55 m tall beside its centre, so the panel's centre
    // sees its top and one side while its corners see the other sides: PCSS's one mean blocker depth per pixel.
    const double le = 5.0, hx = 0.25, hz = 0.2, H = 1.0;
    const glm::dvec3 lo(0.15, 0.0, -0.25), hi(0.65, 0.55, 0.25);
    Scene s = floorScene(4.0f, glm::vec3(0.7f), false);
    addBox(s, glm::vec3(lo), glm::vec3(hi), 0);
    Material e;
    e.baseColor = glm::vec4(0, 0, 0, 1);
    e.emissive = glm::vec3(float(le));
    s.materials.push_back(e);
    addQuad(s, {-float(hx), float(H), -float(hz)}, {float(hx), float(H), -float(hz)}, {float(hx), float(H), float(hz)},
            {-float(hx), float(H), float(hz)}, int(s.materials.size() - 1));
    s.cameras[0].position = {0.2f, 0.95f, 1.4f};
    s.cameras[0].target = {0.7f, 0.0f, 0.0f};
    s.cameras[0].fovY = glm::radians(70.0f);
    // The visible share of the panel from a floor point, weighted by the point-to-area form factor (double).
    auto visibleShare = [&](glm::dvec3 p) {
        const int k = 48;
        double all = 0, seen = 0;
        for (int j = 0; j < k; ++j)
            for (int i = 0; i < k; ++i) {
                const glm::dvec3 l(-hx + (i + 0.5) / k * 2 * hx, H, -hz + (j + 0.5) / k * 2 * hz), d = l - p;
                const double r2 = glm::dot(d, d), w = (d.y / std::sqrt(r2)) * (d.y / std::sqrt(r2)) / r2;
                all += w;
                if (!segmentHitsBox(p, l, lo, hi, 0.0)) seen += w;
            }
        return seen / all;
    };
    double penErr[2] = {0, 0};
    for (int split : {1, 2}) {
        CAPTURE(split);
        Settings st = lightSettings();
        st.light.emissiveSplit = split;
        Frame shadowed = render(s, st, prof);
        st.post.passesOff = "shadow.local";
        Frame open = render(s, st, prof);
        int pen = 0, umbra = 0, umbraBad = 0, litN = 0, litBad = 0;
        double sum = 0;
        forEachSurfacePixel(shadowed, s, st, [&](int x, int y, glm::dvec3 p) {
            if (std::abs(p.y) > 1e-3 || std::abs(p.x) > 1.5 || std::abs(p.z) > 1.5) return;
            const double base = open.direct.at(x, y, 0);
            if (!(base > 0)) return;
            const double got = shadowed.direct.at(x, y, 0) / base, want = visibleShare(p);
            if (want < 0.02) {
                ++umbra, umbraBad += got > 0.15;
            } else if (want > 0.98) {
                ++litN, litBad += got < 0.85;
            } else {
                ++pen, sum += std::abs(got - want);
            }
        });
        penErr[split - 1] = sum / std::max(pen, 1);
        MESSAGE("split " << split << ": penumbra pixels " << pen << ", mean |visibility error| " << penErr[split - 1]
                         << "; umbra " << umbra << " (" << umbraBad << " > 0.15), lit " << litN << " (" << litBad
                         << " < 0.85)");
        REQUIRE(pen > 300);
        REQUIRE(umbra > 40);
        REQUIRE(litN > 300);
        CHECK(umbraBad <= umbra / 20);
        CHECK(litBad <= litN / 50);
        CHECK(penErr[split - 1] < 0.12);
    }
    CHECK(penErr[1] <= penErr[0]);
}

TEST_CASE("Area lights: a point light with light.radius casts the penumbra of a disc of that radius") {
    GpuFixture fx;
    gl::Profiler prof(false);
    const double R = 0.2, H = 1.0, hB = 0.5;
    Scene open = plateScene(hB, false), s = plateScene(hB, true);
    for (Scene* sc : {&open, &s}) sc->lights.push_back(pointLight({0.0f, float(H), 0.0f}, 2.0f));
    Settings st = lightSettings();
    st.light.lightRadius = float(R);
    Frame lit = render(open, st, prof), shadowed = render(s, st, prof);
    // A disc of radius R seen from under the edge: the visible fraction at
    // offset t·R of the edge's image is (acos t − t√(1 − t²))/π, 0.1 at
    // t = 0.6877, so the 10-90 % width is 2·0.6877·R·hB/(H − hB).
    const double scale = hB / (H - hB);
    PenumbraProfile r = penumbraProfile(lit, shadowed, s, st, R * scale);
    MESSAGE("disc: penumbra 10-90 % width " << r.x90 - r.x10 << " (predicted " << 2 * 0.6877 * R * scale << ")");
    REQUIRE(r.filled > 30);
    REQUIRE(std::isfinite(r.x10));
    REQUIRE(std::isfinite(r.x90));
    CHECK(std::abs((r.x90 - r.x10) / (2 * 0.6877 * R * scale) - 1.0) < 0.25);
    CHECK(std::abs(r.x50) < 0.15 * R * scale);
    CHECK(r.umbra < 0.05);
    CHECK(r.lit > 0.95);
    // Radius 0: the punctual 3x3 PCF, a penumbra of a few shadow texels only.
    st.light.lightRadius = 0.0f;
    Frame hardLit = render(open, st, prof), hard = render(s, st, prof);
    PenumbraProfile h = penumbraProfile(hardLit, hard, s, st, R * scale);
    MESSAGE("punctual: penumbra 10-90 % width " << h.x90 - h.x10);
    CHECK(h.x90 - h.x10 < 0.25 * (r.x90 - r.x10));
}

TEST_CASE("The original Cornell box (emissive panel, no sun) runs with shadows and LPV on by default") {
    const char* path = RTGI_SHARED_SCENES "/cornell-box/cornell-box.gltf";
    if (!std::ifstream(path)) {
        MESSAGE("skipped: " << path << " is not present");
        return;
    }
    GpuFixture fx;
    gl::Profiler prof(false);
    Scene s = loadGltf(path);
    Settings st = smallLpvSettings();
    st.lpv.mode = Toggle::Auto;
    st.light.localShadowSize = 128;
    auto r = renderFrames(s, st, {48, 36}, prof);
    for (const char* p : {"shadow.local", "direct", "lpv.rsm", "lpv.inject", "lpv.propagate", "lpv.apply"})
        CHECK_MESSAGE(r->findPass(p) != nullptr, p);
    CHECK(r->localLightsShadowed() == 4);  // the panel, as 2 x 2 area lights (emissive.split=auto)
    CHECK(r->settings().light.emissiveSplit == 2);  // auto, shown resolved
    FloatImage direct = readTexture(r->resources().direct), indirect = readTexture(r->resources().indirectDiffuse);
    double d = 0, ir = 0, ig = 0;
    for (int y = 0; y < 36; ++y)
        for (int x = 0; x < 48; ++x) {
            d += direct.at(x, y, 0);
            ir += indirect.at(x, y, 0);
            ig += indirect.at(x, y, 1);
        }
    CHECK(d > 0.0);
    CHECK(ir > 0.0);
    CHECK(ig > 0.0);
}

namespace {
// rtgi-bench on the original Cornell box with `args` and a full 256-path
// reference (cached in `cache`, or none): its results.json, or null when the
// scene is absent.
nlohmann::json cornellBoxAgainstReference(const std::string& args, const std::string& tag, const std::string& cache = "off") {
    const std::string scene = std::string(RTGI_SHARED_SCENES) + "/cornell-box/cornell-box.gltf";
    if (!std::ifstream(scene)) return nullptr;
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("rtgi-" + tag + "-" + std::to_string(getpid()));
    const std::string cmd = std::string(RTGI_BENCH_EXE) + " --scene " + scene + " " + args +
                            " --no-images --reference --set reference=full --set reference.spp=256"
                            " --set reference.cache=" + cache + " --out " + dir.string() + " > /dev/null 2>&1";
    const int rc = std::system(cmd.c_str());
    REQUIRE((WIFEXITED(rc) && WEXITSTATUS(rc) == 0));
    nlohmann::json j = nlohmann::json::parse(std::ifstream(dir / "results.json"));
    fs::remove_all(dir);
    REQUIRE(j.at("error").at("kind").get<std::string>() == "full");
    return j;
}
}  // namespace

// Issue 13 acceptance: the final image of the original Cornell box with the
// defaults is within relative RMSE 0.35 of the full path-traced reference
// (interior pixels), measured end to end by rtgi-bench --reference. The
// reference's own noise only raises the measured error (it adds in
// quadrature), so the bound holds for the noise-free error too.
TEST_CASE("The original Cornell box with the defaults is within relative RMSE 0.35 of the path tracer") {
    const nlohmann::json j = cornellBoxAgainstReference("--res 64x48 --frames 1 --warmup 0", "cornell-box");
    if (j.is_null()) {
        MESSAGE("skipped: the original Cornell box is not present");
        return;
    }
    const auto& e = j.at("error");
    double rel = e.at("interior").at("rel_rmse").get<double>();
    INFO("interior relative RMSE " << rel << ", RMSE " << e.at("rmse").get<double>() << ", reference noise "
                                   << e.at("reference").at("mean_stderr").get<double>());
    // The frame is lit (an all-black frame has relative RMSE 1) and close to the reference.
    CHECK(rel <= 0.35);
    bool shadowed = false, lpv = false;
    for (const auto& p : j.at("passes")) {
        shadowed |= p.at("name").get<std::string>() == "shadow.local";
        lpv |= p.at("name").get<std::string>() == "lpv.apply";
    }
    CHECK(shadowed);
    CHECK(lpv);
}

// Issue 26 acceptance on llvmpipe: the classic view of the original Cornell
// box (view=front: through the open side, the panel in the picture) with the
// defaults is within interior relative RMSE 0.30 of the full path-traced
// reference at 96x96 with 256 paths. The reference's noise only raises the
// measured error, so the bound holds for the noise-free error too.
TEST_CASE("The original Cornell box from view=front with the defaults is within relative RMSE 0.30 of the path tracer; "
          "the panel split into four lights is closer than one light") {
    namespace fs = std::filesystem;
    const fs::path cache = fs::temp_directory_path() / ("rtgi-cornell-front-cache-" + std::to_string(getpid()));
    const std::string args = "--set view=front --res 96x96 --frames 1 --warmup 1";
    const nlohmann::json j = cornellBoxAgainstReference(args, "cornell-front", cache.string());
    if (j.is_null()) {
        MESSAGE("skipped: the original Cornell box is not present");
        return;
    }
    const auto& e = j.at("error");
    const double rel = e.at("interior").at("rel_rmse").get<double>();
    // The same reference (cached), the panel as one light.
    const nlohmann::json one = cornellBoxAgainstReference(args + " --set emissive.split=1", "cornell-front-one", cache.string());
    fs::remove_all(cache);
    const double relOne = one.at("error").at("interior").at("rel_rmse").get<double>();
    MESSAGE("interior relative RMSE " << rel << " (one light: " << relOne << "; reference noise "
                                      << e.at("reference").at("mean_stderr").get<double>() << "), emissive.split "
                                      << j.at("config").at("emissive.split").dump());
    CHECK(rel <= 0.30);
    CHECK(j.at("config").at("emissive.split").dump() == "2");  // auto: the panel as 2 x 2 lights
    // Four shadow origins: the penumbrae of the boxes come closer to the area light's (session 11 found the
    // direct error there); the four maps drawn from the panel's centre instead would be worse than one light.
    CHECK(rel < relOne);
}
