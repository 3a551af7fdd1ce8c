// BVH: traversal of the flattened nodes returns exactly the hits of a
// brute-force loop over all triangles (closest distance + triangle id, any
// hit), on random triangle soups and on built-in scenes; the triangle and
// box tests are watertight on a finely tessellated quad.
#include "scene/bvh.h"
#include "scene/scene.h"
#include "watertight_rays.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <random>

using namespace rtgi;

namespace {

struct Brute {
    std::vector<gpu::BvhTriangle> tris;  // original order
    explicit Brute(const std::vector<glm::vec3>& v) {
        for (std::size_t t = 0; t < v.size() / 3; ++t) {
            std::uint32_t id = std::uint32_t(t);
            float f;
            std::memcpy(&f, &id, 4);
            tris.push_back({glm::vec4(v[3 * t], f), glm::vec4(v[3 * t + 1], 0), glm::vec4(v[3 * t + 2], 0)});
        }
    }
    std::optional<RayHit> closest(glm::vec3 o, glm::vec3 d, float tMax) const {
        std::optional<RayHit> best;
        for (auto& t : tris)
            if (auto h = intersectTriangle(t, o, d, 0.0f, best ? best->t : tMax)) best = h;
        return best;
    }
};

void checkAgainstBruteForce(const std::vector<glm::vec3>& verts, glm::vec3 lo, glm::vec3 hi, int rays, unsigned seed) {
    Bvh bvh = buildBvh(verts);
    REQUIRE(bvh.triangles.size() == verts.size() / 3);
    CHECK(bvh.depth < RTGI_BVH_STACK);  // the GPU stack cannot overflow
    Brute brute(verts);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> g(0.0f, 1.0f);
    int hits = 0;
    for (int i = 0; i < rays; ++i) {
        glm::vec3 o = lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
        glm::vec3 d = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        float tMax = i % 3 == 0 ? 0.3f * glm::length(hi - lo) : 1e30f;  // finite and unbounded rays
        auto a = traceClosest(bvh, o, d, 0.0f, tMax);
        auto b = brute.closest(o, d, tMax);
        REQUIRE(a.has_value() == b.has_value());
        CHECK(traceAny(bvh, o, d, 0.0f, tMax) == b.has_value());
        if (!a) continue;
        ++hits;
        // Same triangle test on the same floats: the distance is bitwise equal.
        CHECK(a->t == b->t);
        // Coincident faces (boxes touching walls in built-in scenes) tie at
        // the same t: either triangle is the closest hit then.
        if (a->triangle != b->triangle) {
            const auto& ta = bvh.triangles;
            auto other = std::find_if(ta.begin(), ta.end(), [&](const gpu::BvhTriangle& t) {
                std::uint32_t id;
                std::memcpy(&id, &t.v0.w, 4);
                return id == a->triangle;
            });
            REQUIRE(other != ta.end());
            auto h = intersectTriangle(*other, o, d, 0.0f, 1e30f);
            REQUIRE(h);
            CHECK(h->t == b->t);
        }
    }
    CHECK(hits > rays / 10);  // the rays exercise the tree, not only misses
}

}  // namespace

TEST_CASE("BVH closest and any hit equal brute force on random triangle soups") {
    for (unsigned seed : {1u, 2u, 3u}) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        std::vector<glm::vec3> v;
        int n = 50 + int(seed) * 300;
        for (int t = 0; t < n; ++t) {
            glm::vec3 c(u(rng) * 4, u(rng) * 4, u(rng) * 4);
            for (int k = 0; k < 3; ++k) v.push_back(c + 0.8f * glm::vec3(u(rng), u(rng), u(rng)));
        }
        checkAgainstBruteForce(v, glm::vec3(-5), glm::vec3(5), 2000, seed);
    }
}

TEST_CASE("BVH equals brute force on built-in scenes") {
    for (const char* name : {"cornell", "corner", "sphere-on-plane"}) {
        Scene s = loadBuiltin(name);
        Aabb b = s.bounds();
        INFO(name);
        checkAgainstBruteForce(sceneTriangles(s), b.lo, b.hi, 1500, 7u);
    }
}

TEST_CASE("BVH degenerate inputs: coincident centroids and a single triangle") {
    std::vector<glm::vec3> v;
    for (int t = 0; t < 40; ++t) {  // 40 copies of one triangle: no SAH split exists
        v.push_back({-1, 0, -1});
        v.push_back({1, 0, -1});
        v.push_back({0, 0, 1});
    }
    Bvh bvh = buildBvh(v);
    auto h = traceClosest(bvh, {0, 1, 0}, {0, -1, 0}, 0.0f, 1e30f);
    REQUIRE(h);
    CHECK(h->t == doctest::Approx(1.0f));
    Bvh one = buildBvh({{-1, 0, -1}, {1, 0, -1}, {0, 0, 1}});
    CHECK(one.nodes.size() == 1);
    CHECK_FALSE(traceAny(one, {0, 1, 0}, {0, 1, 0}, 0.0f, 1e30f));
}

// Watertightness (docs/reference.md, "Ray/triangle test"): rays aimed
// exactly at the shared vertices and edges of a 64 x 64-cell quad at awkward
// float coordinates all hit, where Möller–Trumbore let rays slip between
// triangles; rays aimed just outside the border all miss. Both through the
// BVH (traceClosest, traceAny) and triangle by triangle (brute force, for
// the cause of a miss: the triangle test or the box test).
TEST_CASE("BVH: rays at shared vertices and edges of a tessellated quad never slip through") {
    for (unsigned seed : {1u, 2u, 3u}) {
        test::WatertightCase c = test::watertightCase(64, 6, seed);
        Bvh bvh = buildBvh(c.triangles);
        int onMesh = 0, missed = 0, bruteMissed = 0, anyMissed = 0, far = 0, spurious = 0;
        for (const auto& r : c.rays) {
            auto h = traceClosest(bvh, r.origin, r.dir, 0.0f, 1e30f);
            bool any = traceAny(bvh, r.origin, r.dir, 0.0f, 1e30f);
            if (!r.onMesh) {
                spurious += h.has_value() || any;
                continue;
            }
            ++onMesh;
            anyMissed += !any;
            if (!h) {
                ++missed;
                bool brute = false;
                for (auto& t : bvh.triangles) brute = brute || intersectTriangle(t, r.origin, r.dir, 0.0f, 1e30f);
                bruteMissed += !brute;
                continue;
            }
            // The hit is the point aimed at, by its distance and by its
            // barycentrics (weights of v1, v2) on the stored vertices, on a
            // triangle that holds it.
            const glm::vec3* v = &c.triangles[3 * std::size_t(h->triangle)];
            glm::vec3 p = r.origin + h->t * r.dir;
            glm::vec3 b = v[0] + h->u * (v[1] - v[0]) + h->v * (v[2] - v[0]);
            far += glm::length(p - r.target) > c.outside || glm::length(b - r.target) > c.outside ||
                   h->u < 0.0f || h->v < 0.0f || h->u + h->v > 1.0f + 1e-6f ||  // rounding of V/det + W/det
                   std::find(r.incident.begin(), r.incident.end(), h->triangle) == r.incident.end();
        }
        INFO("seed " << seed << ": " << onMesh << " rays at shared vertices / edges, " << missed
                     << " missed (triangle test alone: " << bruteMissed << "), any-hit missed " << anyMissed
                     << ", hits away from the target " << far << "; " << c.rays.size() - std::size_t(onMesh)
                     << " rays just outside the border, " << spurious << " hit");
        CHECK(onMesh > 80000);
        CHECK(missed == 0);
        CHECK(bruteMissed == 0);
        CHECK(anyMissed == 0);
        CHECK(far == 0);
        CHECK(spurious == 0);
    }
}
