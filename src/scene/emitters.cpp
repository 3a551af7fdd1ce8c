#include "scene/emitters.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

namespace rtgi {
namespace {

struct Tri {
    glm::dvec3 p[3];
    glm::dvec3 cross;  // 2 A n, n on the side the vertex normals point to (the side the author lit)
};

Tri triangleAt(const Scene& scene, const DrawRange& d, std::uint32_t k) {
    Tri t;
    glm::dvec3 vn(0.0);
    for (int i = 0; i < 3; ++i) {
        const Vertex& v = scene.vertices[scene.indices[d.firstIndex + k + std::uint32_t(i)]];
        t.p[i] = glm::dvec3(v.position);
        vn += glm::dvec3(v.normal);
    }
    t.cross = glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]);
    if (glm::dot(t.cross, vn) < 0.0) t.cross = -t.cross;
    return t;
}

bool emits(const Material& m) { return m.emissive.x > 0.0f || m.emissive.y > 0.0f || m.emissive.z > 0.0f; }

}  // namespace

std::vector<EmissiveTriangle> emissiveTriangles(const Scene& scene, const std::vector<Material>& materials) {
    std::vector<EmissiveTriangle> out;
    std::uint32_t id = 0;
    for (auto& d : scene.draws) {
        const bool on = d.material >= 0 && std::size_t(d.material) < materials.size() && emits(materials[std::size_t(d.material)]);
        for (std::uint32_t k = 0; k + 2 < d.indexCount; k += 3, ++id) {
            if (!on) continue;
            double area = 0.5 * glm::length(triangleAt(scene, d, k).cross);
            if (area > 0.0) out.push_back({id, area, materials[std::size_t(d.material)].emissive});
        }
    }
    return out;
}

std::vector<EmissiveRegion> emissiveRegions(const Scene& scene, const std::vector<Material>& materials) {
    struct Item {
        Tri t;
        glm::dvec3 le;
    };
    std::vector<Item> items;
    for (auto& d : scene.draws) {
        if (d.material < 0 || std::size_t(d.material) >= materials.size() || !emits(materials[std::size_t(d.material)])) continue;
        for (std::uint32_t k = 0; k + 2 < d.indexCount; k += 3) {
            Tri t = triangleAt(scene, d, k);
            if (glm::length(t.cross) > 0.0) items.push_back({t, glm::dvec3(materials[std::size_t(d.material)].emissive)});
        }
    }
    // Union-find over triangles sharing a vertex position (positions are
    // compared exactly: the loaders keep shared corners bit-identical; a
    // region split by a crack only becomes two lights).
    std::vector<std::size_t> parent(items.size());
    std::iota(parent.begin(), parent.end(), std::size_t(0));
    auto find = [&](std::size_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    std::map<std::tuple<double, double, double>, std::vector<std::size_t>> byVertex;
    for (std::size_t i = 0; i < items.size(); ++i)
        for (auto& p : items[i].t.p) byVertex[{p.x, p.y, p.z}].push_back(i);
    for (auto& [key, list] : byVertex)
        for (std::size_t a = 0; a < list.size(); ++a)
            for (std::size_t b = a + 1; b < list.size(); ++b) {
                glm::dvec3 na = glm::normalize(items[list[a]].t.cross), nb = glm::normalize(items[list[b]].t.cross);
                if (glm::dot(na, nb) >= kRegionCos) parent[find(list[a])] = find(list[b]);
            }
    std::map<std::size_t, EmissiveRegion> regions;
    for (std::size_t i = 0; i < items.size(); ++i) {
        auto [it, fresh] = regions.try_emplace(find(i));
        EmissiveRegion& r = it->second;
        if (fresh) r.normal = glm::dvec3(0.0);  // accumulated below
        double a = 0.5 * glm::length(items[i].t.cross);
        r.centroid += a * (items[i].t.p[0] + items[i].t.p[1] + items[i].t.p[2]) / 3.0;
        r.normal += 0.5 * items[i].t.cross;
        r.radiance += a * items[i].le;
        r.area += a;
        ++r.triangles;
    }
    std::vector<EmissiveRegion> out;
    for (auto& [root, r] : regions) {
        r.centroid /= r.area;
        r.radiance /= r.area;
        double ln = glm::length(r.normal);
        r.normal = ln > 0 ? r.normal / ln : glm::dvec3(0, 1, 0);
        out.push_back(r);
    }
    for (std::size_t i = 0; i < items.size(); ++i) {
        EmissiveRegion& r = out[std::size_t(std::distance(regions.begin(), regions.find(find(i))))];
        for (auto& p : items[i].t.p) r.radius = std::max(r.radius, glm::length(p - r.centroid));
    }
    return out;
}

}  // namespace rtgi
