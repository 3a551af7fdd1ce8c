// Light list of the real-time path without GL (render/lights.h,
// scene/emitters.h): emissive regions (union-find over shared corners with
// agreeing normals), area-light power, frustum culling of influence spheres,
// shadow layer layout, the light budget's schedule (LightSchedule) and caps.
#include "render/lights.h"
#include "render/view.h"
#include "scene/emitters.h"
#include "test_scenes.h"

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

using namespace rtgi;
using rtgi::test::addQuad;

namespace {

Scene emitterScene() {
    Scene s;
    Material white, lamp;
    lamp.emissive = glm::vec3(2.0f, 1.0f, 0.5f);
    s.materials = {white, lamp};
    addQuad(s, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}, {-5, 0, -5}, 0);  // floor, not emissive
    // Panel A: two quads sharing an edge, facing down (1 m x 0.8 m at y = 3).
    addQuad(s, {-0.5f, 3, -0.8f}, {0, 3, -0.8f}, {0, 3, 0}, {-0.5f, 3, 0}, 1);
    addQuad(s, {0, 3, -0.8f}, {0.5f, 3, -0.8f}, {0.5f, 3, 0}, {0, 3, 0}, 1);
    for (std::size_t i = 4; i < s.vertices.size(); ++i) s.vertices[i].normal = {0, -1, 0};
    // Panel B: a separate 0.2 m square far away, facing +x.
    addQuad(s, {4, 1, -0.1f}, {4, 1, 0.1f}, {4, 1.2f, 0.1f}, {4, 1.2f, -0.1f}, 1);
    return s;
}

}  // namespace

TEST_CASE("emissive regions: connected coplanar triangles form one region with its area, centroid, normal, power") {
    Scene s = emitterScene();
    auto tris = emissiveTriangles(s, s.materials);
    CHECK(tris.size() == 6);  // 2 + 2 + 2, the floor does not emit
    double area = 0;
    for (auto& t : tris) area += t.area;
    CHECK(area == doctest::Approx(0.8 + 0.04));
    auto regions = emissiveRegions(s, s.materials);
    REQUIRE(regions.size() == 2);
    std::sort(regions.begin(), regions.end(), [](auto& a, auto& b) { return a.area > b.area; });
    const EmissiveRegion& a = regions[0];
    CHECK(a.area == doctest::Approx(0.8));
    CHECK(a.triangles == 4);
    CHECK(a.centroid.x == doctest::Approx(0.0).scale(1.0));
    CHECK(a.centroid.y == doctest::Approx(3.0));
    CHECK(a.centroid.z == doctest::Approx(-0.4));
    CHECK(a.normal.y == doctest::Approx(-1.0));  // the side the vertex normals point to
    CHECK(a.power().x == doctest::Approx(M_PI * 2.0 * 0.8));
    const EmissiveRegion& b = regions[1];
    CHECK(b.area == doctest::Approx(0.04));
    CHECK(std::abs(b.normal.x) == doctest::Approx(1.0));

    // A folded pair (90° between the halves) is two regions even though it shares an edge.
    Scene f;
    Material lamp;
    lamp.emissive = glm::vec3(1.0f);
    f.materials = {lamp};
    addQuad(f, {0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}, 0);
    addQuad(f, {0, 0, 0}, {0, 0, -1}, {0, 1, -1}, {0, 1, 0}, 0);
    CHECK(emissiveRegions(f, f.materials).size() == 2);
}

TEST_CASE("emissive regions: a strip light (one quad, 2 m x 0.25 m) is cut into 8 square slabs carrying its power") {
    Scene s;
    Material lamp;
    lamp.emissive = glm::vec3(3.0f);
    s.materials = {lamp};
    addQuad(s, {-1, 2, 0}, {1, 2, 0}, {1, 2, -0.25f}, {-1, 2, -0.25f}, 0);  // two long triangles
    auto regions = emissiveRegions(s, s.materials);
    REQUIRE(regions.size() == 8);  // round(2 / 0.25) = 8 = kMaxRegionPieces
    std::sort(regions.begin(), regions.end(), [](auto& a, auto& b) { return a.centroid.x < b.centroid.x; });
    double power = 0;
    for (int i = 0; i < 8; ++i) {
        const EmissiveRegion& r = regions[std::size_t(i)];
        CHECK(r.area == doctest::Approx(0.0625));
        CHECK(r.centroid.x == doctest::Approx(-1.0 + 0.25 * (i + 0.5)));
        CHECK(r.centroid.y == doctest::Approx(2.0));
        CHECK(r.centroid.z == doctest::Approx(-0.125));
        CHECK(r.radiance.x == doctest::Approx(3.0));
        power += r.power().x;
    }
    CHECK(power == doctest::Approx(M_PI * 3.0 * 0.5));  // π·Le·A of the whole strip
    // A 0.47 x 0.38 panel (the Cornell box's) stays one light.
    Scene p;
    p.materials = {lamp};
    addQuad(p, {-0.24f, 1.98f, 0.16f}, {0.23f, 1.98f, 0.16f}, {0.23f, 1.98f, -0.22f}, {-0.24f, 1.98f, -0.22f}, 0);
    CHECK(emissiveRegions(p, p.materials).size() == 1);
}

TEST_CASE("emissive regions: the rectangle of a region is the panel itself, or has the region's area (disc)") {
    Material lamp;
    lamp.emissive = glm::vec3(1.0f);
    // A 0.3 x 0.2 m panel turned 30° about the vertical, facing down: its
    // rectangle has the same corners (half extents 0.15 and 0.1 along its sides).
    Scene s;
    s.materials = {lamp};
    const double c = std::cos(M_PI / 6), sn = std::sin(M_PI / 6);
    auto at = [&](double x, double z) { return glm::vec3(float(c * x - sn * z), 1.0f, float(sn * x + c * z)); };
    addQuad(s, at(-0.15, 0.1), at(0.15, 0.1), at(0.15, -0.1), at(-0.15, -0.1), 0);
    auto regions = emissiveRegions(s, s.materials);
    REQUIRE(regions.size() == 1);
    const EmissiveRegion& r = regions[0];
    CHECK(glm::length(r.halfU) == doctest::Approx(0.15).epsilon(1e-6));
    CHECK(glm::length(r.halfV) == doctest::Approx(0.1).epsilon(1e-6));
    CHECK(std::abs(glm::dot(glm::normalize(r.halfU), glm::dvec3(c, 0, sn))) == doctest::Approx(1.0).epsilon(1e-6));
    CHECK(glm::dot(glm::normalize(glm::cross(r.halfU, r.halfV)), r.normal) == doctest::Approx(1.0));
    // A disc (48-gon fan) of radius 0.2: a square of the disc's area (4·|u|·|v| = A), centred on it.
    Scene d;
    d.materials = {lamp};
    const int n = 48;
    for (int i = 0; i < n; ++i) {
        double a0 = 2 * M_PI * i / n, a1 = 2 * M_PI * (i + 1) / n;
        auto base = std::uint32_t(d.vertices.size());
        for (glm::vec3 p : {glm::vec3(0, 2, 0), glm::vec3(0.2f * float(std::cos(a1)), 2, 0.2f * float(std::sin(a1))),
                            glm::vec3(0.2f * float(std::cos(a0)), 2, 0.2f * float(std::sin(a0)))})
            d.vertices.push_back({p, {0, -1, 0}, {0, 0}});
        for (std::uint32_t k = 0; k < 3; ++k) d.indices.push_back(base + k);
    }
    d.draws.push_back({0, std::uint32_t(d.indices.size()), 0});
    auto disc = emissiveRegions(d, d.materials);
    REQUIRE(disc.size() == 1);
    const double area = 0.5 * n * 0.04 * std::sin(2 * M_PI / n);  // the 48-gon's area
    CHECK(disc[0].area == doctest::Approx(area));
    CHECK(4 * glm::length(disc[0].halfU) * glm::length(disc[0].halfV) == doctest::Approx(area));
    CHECK(glm::length(disc[0].halfU) == doctest::Approx(glm::length(disc[0].halfV)).epsilon(0.02));
    CHECK(glm::length(disc[0].centroid - glm::dvec3(0, 2, 0)) < 1e-6);
}

TEST_CASE("local lights: area lights from regions, culling by influence sphere, shadow layer layout") {
    Scene s = emitterScene();
    Light spot;
    spot.type = LightType::Spot;
    spot.name = "spot";
    spot.position = {0, 2, 2};
    spot.direction = {0, -1, 0};
    spot.intensity = 5.0f;
    spot.outerCone = 0.5f;
    s.lights.push_back(spot);
    Light behind;
    behind.type = LightType::Point;
    behind.name = "behind";
    behind.position = {0, 1, 30};
    behind.range = 1.0f;
    behind.intensity = 5.0f;
    s.lights.push_back(behind);
    Settings st;
    st.light.emissiveSplit = 1;  // one light per region (emissive.split has its own test)
    LocalLights ll = resolveLocalLights(s, st);
    REQUIRE(ll.lights.size() == 4);  // spot, point, 2 area lights
    CHECK(ll.sceneLights == 2);
    CHECK(maxShadowLayers(ll) == 1 + 6 + 6 + 6);
    int areas = 0;
    for (auto& l : ll.lights) areas += int(l.gpu.directionType.w) == RTGI_LIGHT_AREA;
    CHECK(areas == 2);
    st.light.emissiveLights = false;
    CHECK(resolveLocalLights(s, st).lights.size() == 2);
    CHECK(hasLocalLights(s, st));
    st.light.emissiveLights = true;

    // Camera at (0, 1.5, 8) looking at -z: the ranged light at z = 30 is behind it.
    glm::mat4 view = glm::lookAt(glm::vec3(0, 1.5f, 8), glm::vec3(0, 1.5f, 0), glm::vec3(0, 1, 0));
    glm::mat4 proj = glm::perspective(glm::radians(60.0f), 1.5f, 0.1f, 100.0f);
    Aabb box = s.bounds();
    FrameLights fl = frameLights(ll, proj * view, box, true, 256);
    REQUIRE(fl.gpu.size() == 4);
    CHECK(fl.culled == 1);
    CHECK(fl.gpu[1].directionType.w == 0.0f);  // culled: the direct pass skips it
    CHECK(fl.shadowed == 3);
    CHECK(fl.views.size() == 1 + 6 + 6);
    // Fixed layers (the light budget caches maps across frames, so culling
    // never moves a light's layers): disjoint blocks covering 0..19, each
    // kept light's cone.z is its first layer, its views follow in order.
    CHECK(ll.shadowLayers == 19);
    std::vector<int> owner(19, -1);
    for (std::size_t i = 0; i < ll.lights.size(); ++i)
        for (int k = 0; k < ll.lights[i].faces; ++k) {
            REQUIRE(ll.lights[i].firstLayer >= 0);
            CHECK(owner[std::size_t(ll.lights[i].firstLayer + k)] == -1);
            owner[std::size_t(ll.lights[i].firstLayer + k)] = int(i);
        }
    for (std::size_t i : {0u, 2u, 3u}) CHECK(fl.gpu[i].cone.z == float(ll.lights[i].firstLayer));
    for (auto& v : fl.views) {
        CHECK(v.light != 1);  // the culled light draws nothing
        CHECK(v.layer == ll.lights[std::size_t(v.light)].firstLayer + (v.face - ll.lights[std::size_t(v.light)].firstFace));
    }
    // Every cube face's frustum holds the points along its axis, and the
    // spot's holds its axis.
    glm::vec3 p(fl.gpu[2].positionRange);
    const glm::vec3 axis[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int k = 0; k < 6; ++k) {
        glm::vec4 c = fl.views[std::size_t(1 + k)].viewProj * glm::vec4(p + 0.5f * axis[k], 1.0f);
        CHECK(std::abs(c.x / c.w) < 1e-4f);
        CHECK(std::abs(c.y / c.w) < 1e-4f);
        CHECK(c.z / c.w > -1.0f);
        CHECK(c.z / c.w < 1.0f);
    }
    // No shadows requested: nothing gets a layer.
    FrameLights plain = frameLights(ll, proj * view, box, false, 256);
    CHECK(plain.views.empty());
    for (auto& g : plain.gpu) CHECK(g.cone.z == -1.0f);
    // A sphere straddling a frustum plane is kept, one fully outside is not.
    CHECK(sphereInFrustum(proj * view, {0, 1.5f, 8.5f}, 1.0f));
    CHECK_FALSE(sphereInFrustum(proj * view, {0, 1.5f, 12.0f}, 1.0f));
}

TEST_CASE("emissive.split: each region's rectangle becomes n x n lights that tile it with its power and reach; "
          "auto cuts in two while the pieces fit emissive.max_lights") {
    Scene s = emitterScene();
    Settings st;
    st.light.emissiveSplit = 1;
    const LocalLights whole = resolveLocalLights(s, st);
    REQUIRE(whole.lights.size() == 2);
    CHECK(whole.emissiveSplit == 1);
    for (auto& L : whole.lights) CHECK(L.shape.halfV.w == 4.0f);
    for (int n : {2, 3}) {
        st.light.emissiveSplit = n;
        const LocalLights ll = resolveLocalLights(s, st);
        CHECK(ll.emissiveSplit == n);
        REQUIRE(ll.lights.size() == std::size_t(2 * n * n));
        for (std::size_t r = 0; r < 2; ++r) {
            // The region's rectangle from its own light: centre c, half extents U, V.
            const LocalLight& W = whole.lights[r];
            const glm::dvec3 c(W.shape.centerRadius), U(W.shape.halfU), V(W.shape.halfV);
            const glm::dvec3 nrm = glm::normalize(glm::cross(U, V));
            glm::dvec3 power(0.0);
            double area = 0;
            // Every point of a fine grid over the rectangle lies in exactly one piece.
            const int g = 24;
            std::vector<int> cover(std::size_t(g * g), 0);
            for (int k = 0; k < n * n; ++k) {
                const LocalLight& L = ll.lights[r * std::size_t(n * n) + std::size_t(k)];
                CHECK(int(L.gpu.directionType.w) == RTGI_LIGHT_AREA);
                const glm::dvec3 pc(L.shape.centerRadius), pu(L.shape.halfU), pv(L.shape.halfV);
                CHECK(glm::length(pu) == doctest::Approx(glm::length(U) / n).epsilon(1e-5));
                CHECK(glm::length(pv) == doctest::Approx(glm::length(V) / n).epsilon(1e-5));
                CHECK(std::abs(glm::dot(pc - c, nrm)) < 1e-5);  // in the panel's plane
                CHECK(L.shape.halfV.w == 2.0f);  // soft-shadow rays per side of a piece (4 for a whole panel)
                CHECK(glm::dot(glm::dvec3(L.gpu.directionType), nrm) == doctest::Approx(1.0));
                // The shadow origin sits in front of the piece's own centre.
                const glm::dvec3 o(L.gpu.positionRange);
                CHECK(glm::length(o - pc - nrm * glm::dot(o - pc, nrm)) < 1e-5);
                CHECK(glm::dot(o - pc, nrm) > 0.0);
                const double a = 4.0 * glm::length(pu) * glm::length(pv);
                area += a;
                power += glm::dvec3(L.gpu.colorIntensity);
                // The cut must not move where the panel's light is culled.
                CHECK(L.influence == doctest::Approx(W.influence));
                for (int j = 0; j < g; ++j)
                    for (int i = 0; i < g; ++i) {
                        const glm::dvec3 x = c + U * ((i + 0.5) / g * 2 - 1) + V * ((j + 0.5) / g * 2 - 1);
                        const double su = glm::dot(x - pc, pu) / glm::dot(pu, pu), sv = glm::dot(x - pc, pv) / glm::dot(pv, pv);
                        if (std::abs(su) <= 1.0 && std::abs(sv) <= 1.0) ++cover[std::size_t(j * g + i)];
                    }
            }
            CHECK(area == doctest::Approx(4.0 * glm::length(U) * glm::length(V)).epsilon(1e-5));
            for (int ch = 0; ch < 3; ++ch)
                CHECK(power[ch] == doctest::Approx(double(W.gpu.colorIntensity[ch])).epsilon(1e-5));
            CHECK(std::count(cover.begin(), cover.end(), 1) == g * g);
        }
    }
    // auto: two regions -> 8 pieces fit 32 lights (split 2); with a cap of 7 they do not (split 1).
    st.light.emissiveSplit = 0;
    CHECK(resolveLocalLights(s, st).emissiveSplit == 2);
    CHECK(resolveLocalLights(s, st).lights.size() == 8);
    st.light.maxAreaLights = 7;
    CHECK(resolveLocalLights(s, st).emissiveSplit == 1);
    CHECK(resolveLocalLights(s, st).lights.size() == 2);
    st.light.maxAreaLights = 8;
    CHECK(resolveLocalLights(s, st).emissiveSplit == 2);
    st.light.maxAreaLights = 32;
    st.light.emissiveLights = false;  // no emissive light: nothing to split
    CHECK(resolveLocalLights(s, st).emissiveSplit == 1);
}

namespace {
// A floor and `n` point lights of intensities 1, 2, ..., n on a row 2 m above
// it, in front of a camera at (0, 3, 12) looking at the row (all kept).
Scene pointRow(int n) {
    Scene s;
    s.materials = {Material{}};
    addQuad(s, {-20, 0, 20}, {20, 0, 20}, {20, 0, -20}, {-20, 0, -20}, 0);
    for (int i = 0; i < n; ++i) {
        Light l;
        l.type = LightType::Point;
        l.name = "p" + std::to_string(i);
        l.position = {float(i) - 0.5f * float(n - 1), 2.0f, 0.0f};
        l.intensity = float(i + 1);
        l.range = 6.0f;
        s.lights.push_back(l);
    }
    return s;
}
glm::mat4 rowCamera() {
    return glm::perspective(glm::radians(60.0f), 1.5f, 0.1f, 100.0f) *
           glm::lookAt(glm::vec3(0, 3, 12), glm::vec3(0, 1, 0), glm::vec3(0, 1, 0));
}
}  // namespace

TEST_CASE("light budget: faces drawn per frame stay within the budget, the brightest first; the rest wait, then come from the cache") {
    Scene s = pointRow(4);
    Settings st;
    LocalLights ll = resolveLocalLights(s, st);
    REQUIRE(ll.lights.size() == 4);
    const glm::mat4 cam = rowCamera();
    const glm::vec3 eye(0, 3, 12);
    // Needed shadow faces of each light (inView), from frameLights itself.
    auto needed = [&](int light) {
        int n = 0;
        for (auto& v : frameLights(ll, cam, s.bounds(), true, 64).views) n += v.light == light && v.inView;
        return n;
    };
    int total = 0;
    for (int i = 0; i < 4; ++i) total += needed(i);
    REQUIRE(total > 0);

    // Unbudgeted: every face of every kept light, every frame, nothing cached.
    LightSchedule all;
    for (int frame = 0; frame < 2; ++frame) {
        FrameLights fl = frameLights(ll, cam, s.bounds(), true, 64);
        auto p = all.plan(ll, fl, nullptr, true, 0, eye);
        CHECK(p.drawShadows.size() == 24);
        CHECK(p.waiting == 0);
        CHECK(p.cachedFaces == 0);
    }

    // Budget 6: one light per frame (each needs at most 6 faces), brightest first;
    // the others wait (type 0: not lit, nothing of theirs is read).
    LightSchedule sched;
    std::vector<int> order;
    for (int frame = 0; frame < 4; ++frame) {
        FrameLights fl = frameLights(ll, cam, s.bounds(), true, 64);
        auto p = sched.plan(ll, fl, nullptr, true, 6, eye);
        REQUIRE(!p.drawShadows.empty());
        const int light = p.drawShadows.front().light;
        for (auto& v : p.drawShadows) {
            CHECK(v.light == light);
            CHECK(v.inView);
        }
        CHECK(int(p.drawShadows.size()) == needed(light));
        order.push_back(light);
        CHECK(p.waiting == 3 - frame);
        int lit = 0;
        for (auto& g : fl.gpu) lit += g.directionType.w != 0.0f;
        CHECK(lit == frame + 1);
    }
    // Same distance class: priority = screen influence x intensity decides; the
    // brightest light (p3) first, every light once.
    CHECK(order.front() == 3);
    std::vector<int> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    CHECK(sorted == std::vector<int>{0, 1, 2, 3});
    // Static: nothing drawn, everything from the cache.
    FrameLights fl = frameLights(ll, cam, s.bounds(), true, 64);
    auto p = sched.plan(ll, fl, nullptr, true, 6, eye);
    CHECK(p.drawShadows.empty());
    CHECK(p.waiting == 0);
    CHECK(p.cachedFaces == total);
    // A light changed: only its faces are redrawn, it stays lit meanwhile.
    sched.lightChanged(1);
    fl = frameLights(ll, cam, s.bounds(), true, 64);
    p = sched.plan(ll, fl, nullptr, true, 6, eye);
    CHECK(int(p.drawShadows.size()) == needed(1));
    for (auto& v : p.drawShadows) CHECK(v.light == 1);
    CHECK(p.waiting == 0);
    // Geometry moved, budget 6: one light redrawn, the others keep their stale
    // maps (lit, counted as cached), with the view they were drawn with.
    const glm::mat4 before = sched.shadowViewProj(ll.lights[0].firstFace);
    sched.invalidateAll();
    fl = frameLights(ll, cam, s.bounds(), true, 64);
    p = sched.plan(ll, fl, nullptr, true, 6, eye);
    CHECK(p.waiting == 0);
    CHECK(p.drawShadows.front().light == 3);
    CHECK(sched.shadowViewProj(ll.lights[0].firstFace) == before);
    // The storage was reallocated: every light waits again for its maps.
    sched.shadowStorageLost();
    fl = frameLights(ll, cam, s.bounds(), true, 64);
    p = sched.plan(ll, fl, nullptr, true, 6, eye);
    CHECK(p.waiting == 3);
}

TEST_CASE("light budget: RSM faces count against the same budget and only the lit lights' RSMs are injected") {
    Scene s = pointRow(3);
    Settings st;
    LocalLights ll = resolveLocalLights(s, st);
    const glm::mat4 cam = rowCamera();
    LightSchedule sched;
    FrameLights fl = frameLights(ll, cam, s.bounds(), true, 64), rl = frameLights(ll, cam, s.bounds(), true, 32);
    auto p = sched.plan(ll, fl, &rl, true, 12, glm::vec3(0, 3, 12));
    // One light: its needed shadow faces (>= 1) and its six RSM faces; a second
    // light would need at least 7 more, over the budget of 12.
    REQUIRE(!p.drawRsms.empty());
    CHECK(p.drawRsms.size() == 6);
    CHECK(int(p.drawShadows.size() + p.drawRsms.size()) <= 12);
    for (auto& v : p.injectRsms) CHECK(v.light == p.drawRsms.front().light);
    CHECK(p.injectRsms.size() == 6);
}

TEST_CASE("light budget: local RSM side halves until all faces fit budget x lpv.rsm^2 texels") {
    Settings st;
    st.lpv.rsm = 256;
    st.light.budget = 48;
    CHECK(localRsmSize(st, 18) == 256);   // within the budget: full size (the frame equals the unbudgeted one)
    CHECK(localRsmSize(st, 48) == 256);
    CHECK(localRsmSize(st, 49) == 128);
    CHECK(localRsmSize(st, 192) == 128);  // 192 x 128^2 = 48 x 256^2
    CHECK(localRsmSize(st, 193) == 64);
    CHECK(localRsmSize(st, 12000) == 16); // never below 16
    for (int faces : {49, 200, 2000}) {
        const int n = localRsmSize(st, faces);
        CHECK(double(faces) * n * n <= 48.0 * 256 * 256);
        CHECK(double(faces) * (2 * n) * (2 * n) > 48.0 * 256 * 256);  // the largest power-of-two step that fits
    }
    st.light.budget = 0;
    CHECK(localRsmSize(st, 12000) == 256);
}

TEST_CASE("emissive.max_lights keeps the brightest regions with a warning; the shadow array's layer limit goes to the brightest lights") {
    // 40 separate emissive squares, radiance 1..40 (material per square).
    Scene s;
    s.materials.push_back(Material{});
    addQuad(s, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, {-50, 0, -50}, 0);
    double total = 0, kept = 0;
    for (int i = 0; i < 40; ++i) {
        Material m;
        m.emissive = glm::vec3(float(i + 1));
        s.materials.push_back(m);
        const float x = float(i) * 2.0f - 40.0f;
        addQuad(s, {x, 3, 0}, {x + 1, 3, 0}, {x + 1, 3, -1}, {x, 3, -1}, int(i + 1));
        total += i + 1;
        if (i >= 8) kept += i + 1;
    }
    Settings st;
    st.light.maxAreaLights = 32;
    LocalLights ll = resolveLocalLights(s, st);
    REQUIRE(ll.lights.size() == 32);
    for (auto& l : ll.lights) CHECK(l.gpu.colorIntensity.x >= 9.0f - 1e-3f);  // radiance 9..40 (area 1)
    REQUIRE(ll.warnings.size() == 1);
    char pct[32];
    std::snprintf(pct, sizeof pct, "%.3g", 100.0 * (total - kept) / total);
    CHECK(ll.warnings[0].find("40 emissive regions; the brightest 32 are area lights (emissive.max_lights=32), the other 8 (" +
                              std::string(pct) + " % of the emitted power)") != std::string::npos);
    // A limit of 20 layers: the 3 brightest cubes get 18, the rest go unshadowed (with a warning).
    LocalLights few = resolveLocalLights(s, st, 20);
    CHECK(few.shadowLayers == 18);
    int shadowed = 0;
    for (auto& l : few.lights) {
        if (l.firstLayer < 0) continue;
        ++shadowed;
        CHECK(l.gpu.colorIntensity.x >= 38.0f - 1e-3f);
    }
    CHECK(shadowed == 3);
    REQUIRE(few.warnings.size() == 2);
    CHECK(few.warnings[1].find("29 local lights get no shadow map: the shadow array holds 20 layers") != std::string::npos);
    // Unshadowed lights are kept (drawn without shadow: cone.z = -1).
    const glm::mat4 cam = glm::perspective(glm::radians(90.0f), 1.0f, 0.1f, 500.0f) *
                          glm::lookAt(glm::vec3(0, 40, 30), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    FrameLights fl = frameLights(few, cam, s.bounds(), true, 64);
    for (std::size_t i = 0; i < few.lights.size(); ++i)
        if (few.lights[i].firstLayer < 0 && fl.gpu[i].directionType.w != 0.0f) CHECK(fl.gpu[i].cone.z == -1.0f);
}
