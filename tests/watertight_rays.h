#pragma once
// Oracle of the watertight ray/triangle test (docs/reference.md, "Ray/triangle
// test"), shared by the unit tier (CPU BVH) and the GPU tier (bvh.glsl): a
// finely tessellated quad, rotated and moved to awkward float coordinates, and
// rays aimed exactly at its shared vertices and at points of its shared edges
// (each must hit: no ray slips between two triangles), plus rays aimed just
// outside its outer border (each must miss: the test is not made watertight by
// being generous).
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <random>
#include <vector>

namespace rtgi::test {

struct WatertightRay {
    glm::vec3 origin, dir;
    glm::vec3 target;  // the point aimed at
    bool onMesh;       // target on a shared vertex / edge (must hit) or just outside the border (must miss)
    std::vector<std::uint32_t> incident;  // the triangles whose closure holds the target (any may be hit)
};

struct WatertightCase {
    std::vector<glm::vec3> triangles;  // 3 positions each; shared vertices are bit-identical floats
    std::vector<WatertightRay> rays;
    float cell = 0;        // edge length of a grid cell
    float outside = 0;     // how far outside the border the must-miss targets lie
};

// n × n cells, 2 triangles each, with the cell diagonal alternating so that
// interior vertices are shared by 6 or 8 triangles.
inline WatertightCase watertightCase(int n, int origins, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    WatertightCase c;
    const float side = 23.7f;  // not a power of 2: the grid coordinates round
    c.cell = side / float(n);
    c.outside = 1e-3f * c.cell;  // ~100x the rounding of the coordinates (|p| < 80)
    // Random rotation (normalized quaternion) and translation, both in float.
    glm::vec4 q;
    do q = glm::vec4(u(rng), u(rng), u(rng), u(rng));
    while (glm::length(q) < 0.1f || glm::length(q) > 1.0f);
    q = glm::normalize(q);
    const float x = q.x, y = q.y, z = q.z, w = q.w;
    const glm::mat3 rot(1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w),  //
                        2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w),  //
                        2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y));
    const glm::vec3 origin0(37.3f * u(rng), 37.3f * u(rng), 37.3f * u(rng));
    auto place = [&](float a, float b, float h) { return origin0 + rot * glm::vec3(a, b, h); };
    auto local = [&](int i) { return -0.5f * side + side * (float(i) / float(n)); };
    std::vector<glm::vec3> grid(std::size_t((n + 1) * (n + 1)));
    std::vector<std::vector<std::uint32_t>> trianglesAt(grid.size());  // per grid vertex, ascending
    auto id = [&](int i, int j) { return std::size_t(j * (n + 1) + i); };
    auto at = [&](int i, int j) -> glm::vec3& { return grid[id(i, j)]; };
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) at(i, j) = place(local(i), local(j), 0.0f);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::size_t a = id(i, j), b = id(i + 1, j), cc = id(i + 1, j + 1), d = id(i, j + 1);
            const std::size_t even[6] = {a, b, cc, a, cc, d}, odd[6] = {a, b, d, b, cc, d};
            for (std::size_t v : (i + j) % 2 == 0 ? even : odd) {
                trianglesAt[v].push_back(std::uint32_t(c.triangles.size() / 3));
                c.triangles.push_back(grid[v]);
            }
        }

    // Targets: every interior vertex, one point on every interior edge (the
    // lerp of its two stored vertices, in float), and points just outside the
    // border (border vertices and edge points moved outward in the plane).
    std::uniform_real_distribution<float> s01(0.05f, 0.95f);
    struct Target {
        glm::vec3 p;
        bool onMesh;
        std::vector<std::uint32_t> incident;
    };
    std::vector<Target> targets;
    auto edge = [&](std::size_t a, std::size_t b) {  // a point of the edge a-b and the two triangles holding it
        Target t{grid[a] + s01(rng) * (grid[b] - grid[a]), true, {}};
        std::set_intersection(trianglesAt[a].begin(), trianglesAt[a].end(), trianglesAt[b].begin(), trianglesAt[b].end(),
                              std::back_inserter(t.incident));
        targets.push_back(t);
    };
    auto lerp = [&](glm::vec3 a, glm::vec3 b) { return a + s01(rng) * (b - a); };
    for (int j = 1; j < n; ++j)
        for (int i = 1; i < n; ++i) targets.push_back({at(i, j), true, trianglesAt[id(i, j)]});
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            if (i < n && j > 0 && j < n) edge(id(i, j), id(i + 1, j));
            if (j < n && i > 0 && i < n) edge(id(i, j), id(i, j + 1));
            if (i < n && j < n) {
                if ((i + j) % 2 == 0) edge(id(i, j), id(i + 1, j + 1));
                else edge(id(i + 1, j), id(i, j + 1));
            }
        }
    const glm::vec3 ex = rot[0], ey = rot[1];
    for (int k = 0; k <= n; ++k) {
        for (auto [p, out] : {std::pair{at(k, 0), -ey}, std::pair{at(k, n), ey}, std::pair{at(0, k), -ex}, std::pair{at(n, k), ex}})
            targets.push_back({p + c.outside * out, false, {}});
        if (k < n) {
            targets.push_back({lerp(at(k, 0), at(k + 1, 0)) - c.outside * ey, false, {}});
            targets.push_back({lerp(at(k, n), at(k + 1, n)) + c.outside * ey, false, {}});
            targets.push_back({lerp(at(0, k), at(0, k + 1)) - c.outside * ex, false, {}});
            targets.push_back({lerp(at(n, k), at(n, k + 1)) + c.outside * ex, false, {}});
        }
    }

    // Origins on both sides, near and far, some beyond the quad's border so
    // that rays arrive at grazing angles; half the directions are normalized
    // (as the renderer's are), half are target − origin unnormalized.
    for (int o = 0; o < origins; ++o) {
        float h = (o % 2 ? -1.0f : 1.0f) * (o % 4 < 2 ? 3.1f : 17.9f);
        glm::vec3 org = place(side * u(rng), side * u(rng), h);
        for (std::size_t t = 0; t < targets.size(); ++t) {
            glm::vec3 d = targets[t].p - org;
            if (t % 2) d = glm::normalize(d);
            c.rays.push_back({org, d, targets[t].p, targets[t].onMesh, targets[t].incident});
        }
    }
    return c;
}

}  // namespace rtgi::test
