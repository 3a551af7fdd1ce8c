#include "scene/emitters.h"

#include <algorithm>
#include <array>
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
    std::map<std::size_t, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < items.size(); ++i) groups[find(i)].push_back(i);

    std::vector<EmissiveRegion> out;
    for (auto& [root, members] : groups) {
        // The whole region: normal, and its in-plane extent along the
        // principal axis t1 of its vertices (and t2 across it).
        glm::dvec3 normal(0.0), centroid(0.0);
        double area = 0;
        for (std::size_t i : members) {
            double a = 0.5 * glm::length(items[i].t.cross);
            normal += 0.5 * items[i].t.cross;
            centroid += a * (items[i].t.p[0] + items[i].t.p[1] + items[i].t.p[2]) / 3.0;
            area += a;
        }
        double ln = glm::length(normal);
        normal = ln > 0 ? normal / ln : glm::dvec3(0, 1, 0);
        centroid /= area;
        glm::dvec3 u = std::abs(normal.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
        u = glm::normalize(u - normal * glm::dot(u, normal));
        glm::dvec3 v = glm::cross(normal, u);
        // Second moments of the area (not of the vertices, so the triangulation
        // does not tilt the axis): ∫ x xᵀ dA = A/12 (Σ pᵢpᵢᵀ + s sᵀ), s = Σ pᵢ.
        double cuu = 0, cvv = 0, cuv = 0;
        for (std::size_t i : members) {
            double a = 0.5 * glm::length(items[i].t.cross), su = 0, sv = 0, uu = 0, vv = 0, uv = 0;
            for (auto& p : items[i].t.p) {
                double pu = glm::dot(p - centroid, u), pv = glm::dot(p - centroid, v);
                su += pu, sv += pv, uu += pu * pu, vv += pv * pv, uv += pu * pv;
            }
            cuu += a / 12.0 * (uu + su * su);
            cvv += a / 12.0 * (vv + sv * sv);
            cuv += a / 12.0 * (uv + su * sv);
        }
        double angle = 0.5 * std::atan2(2.0 * cuv, cuu - cvv);
        glm::dvec3 t1 = std::cos(angle) * u + std::sin(angle) * v, t2 = glm::cross(normal, t1);
        double lo1 = 1e300, hi1 = -1e300, lo2 = 1e300, hi2 = -1e300;
        for (std::size_t i : members)
            for (auto& p : items[i].t.p) {
                double a = glm::dot(p - centroid, t1), b = glm::dot(p - centroid, t2);
                lo1 = std::min(lo1, a), hi1 = std::max(hi1, a), lo2 = std::min(lo2, b), hi2 = std::max(hi2, b);
            }
        // Elongated regions (strip lights) are cut across t1 into k slabs of
        // about square shape, k = round(length / width) ≤ kMaxRegionPieces;
        // each slab is one light (its clipped area, centroid, radiance).
        double len = hi1 - lo1, width = std::max(hi2 - lo2, 1e-12 * len);
        int k = int(std::clamp(std::round(len / width), 1.0, double(kMaxRegionPieces)));
        std::vector<EmissiveRegion> pieces(static_cast<std::size_t>(k));
        for (auto& r : pieces) r.normal = normal;
        std::vector<std::array<double, 4>> boxes(pieces.size(), {1e300, -1e300, 1e300, -1e300});  // lo1 hi1 lo2 hi2
        for (std::size_t i : members) {
            const Item& it = items[i];
            for (int piece = 0; piece < k; ++piece) {
                // Sutherland–Hodgman: the triangle clipped to lo1 + [piece, piece+1]·len/k along t1.
                std::vector<glm::dvec3> poly(it.t.p, it.t.p + 3);
                const double bounds[2] = {lo1 + len * piece / k, lo1 + len * (piece + 1) / k};
                for (int side = 0; side < 2 && k > 1; ++side) {
                    std::vector<glm::dvec3> next;
                    auto inside = [&](const glm::dvec3& p) {
                        double sdist = glm::dot(p - centroid, t1) - bounds[side];
                        return side == 0 ? sdist >= 0 : sdist <= 0;
                    };
                    for (std::size_t a = 0; a < poly.size(); ++a) {
                        const glm::dvec3 &p = poly[a], &q = poly[(a + 1) % poly.size()];
                        bool ip = inside(p), iq = inside(q);
                        if (ip) next.push_back(p);
                        if (ip != iq) {
                            double dp = glm::dot(p - centroid, t1) - bounds[side], dq = glm::dot(q - centroid, t1) - bounds[side];
                            next.push_back(p + (q - p) * (dp / (dp - dq)));
                        }
                    }
                    poly = std::move(next);
                    if (poly.size() < 3) break;
                }
                if (poly.size() < 3) continue;
                EmissiveRegion& r = pieces[std::size_t(piece)];
                for (auto& q : poly) {
                    double a = glm::dot(q - centroid, t1), b = glm::dot(q - centroid, t2);
                    boxes[std::size_t(piece)][0] = std::min(boxes[std::size_t(piece)][0], a);
                    boxes[std::size_t(piece)][1] = std::max(boxes[std::size_t(piece)][1], a);
                    boxes[std::size_t(piece)][2] = std::min(boxes[std::size_t(piece)][2], b);
                    boxes[std::size_t(piece)][3] = std::max(boxes[std::size_t(piece)][3], b);
                }
                for (std::size_t a = 1; a + 1 < poly.size(); ++a) {  // fan
                    double at = 0.5 * glm::length(glm::cross(poly[a] - poly[0], poly[a + 1] - poly[0]));
                    r.centroid += at * (poly[0] + poly[a] + poly[a + 1]) / 3.0;
                    r.radiance += at * it.le;
                    r.area += at;
                }
                ++r.triangles;
            }
        }
        for (std::size_t piece = 0; piece < pieces.size(); ++piece) {
            EmissiveRegion& r = pieces[piece];
            if (!(r.area > 0)) continue;
            r.centroid /= r.area;
            r.radiance /= r.area;
            const auto& b = boxes[piece];
            const double w1 = std::max(b[1] - b[0], 0.0), w2 = std::max(b[3] - b[2], 0.0);
            const double s = w1 * w2 > 0 ? std::sqrt(r.area / (w1 * w2)) : 1.0;
            r.halfU = t1 * (0.5 * w1 * s);
            r.halfV = t2 * (0.5 * w2 * s);  // t1 × t2 = normal
            out.push_back(r);
        }
    }
    return out;
}

}  // namespace rtgi
