#include "scene/bvh.h"

#include "scene/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>

namespace rtgi {
namespace {

struct Box {
    glm::vec3 lo{1e30f}, hi{-1e30f};
    void grow(glm::vec3 p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void grow(const Box& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    float area() const {
        if (lo.x > hi.x) return 0.0f;
        glm::vec3 e = hi - lo;
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
};

struct Builder {
    const BvhBuildOptions& opt;
    std::vector<Box> triBox;
    std::vector<glm::vec3> centroid;
    std::vector<std::uint32_t> order;  // triangle ids, permuted into leaf order
    std::vector<gpu::BvhNode> nodes;
    int depth = 0;

    void setLeaf(std::uint32_t node, std::uint32_t first, std::uint32_t count) {
        nodes[node].index = first;
        nodes[node].count = count;
    }

    // Builds the subtree of `node` over order[first, first + count).
    void build(std::uint32_t node, std::uint32_t first, std::uint32_t count, int level) {
        depth = std::max(depth, level);
        Box bounds, cbounds;
        for (std::uint32_t i = first; i < first + count; ++i) {
            bounds.grow(triBox[order[i]]);
            cbounds.grow(centroid[order[i]]);
        }
        nodes[node].lo = bounds.lo;
        nodes[node].hi = bounds.hi;
        if (count <= 1 || level >= opt.maxDepth) return setLeaf(node, first, count);

        // Binned SAH (Wald 2007): cost = A_L·N_L + A_R·N_R, relative to the
        // leaf cost A·N with traversal and intersection costs equal.
        const int nb = opt.bins;
        float bestCost = 1e30f;
        int bestAxis = -1, bestSplit = 0;
        glm::vec3 ext = cbounds.hi - cbounds.lo;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(ext[axis] > 0.0f)) continue;
            std::vector<Box> bin(static_cast<std::size_t>(nb));
            std::vector<std::uint32_t> n(static_cast<std::size_t>(nb), 0u);
            float scale = float(nb) / ext[axis];
            for (std::uint32_t i = first; i < first + count; ++i) {
                int b = std::min(nb - 1, int((centroid[order[i]][axis] - cbounds.lo[axis]) * scale));
                bin[std::size_t(b)].grow(triBox[order[i]]);
                ++n[std::size_t(b)];
            }
            std::vector<float> rightCost(static_cast<std::size_t>(nb), 0.0f);
            Box acc;
            std::uint32_t cnt = 0;
            for (int b = nb - 1; b > 0; --b) {
                acc.grow(bin[std::size_t(b)]);
                cnt += n[std::size_t(b)];
                rightCost[std::size_t(b)] = acc.area() * float(cnt);
            }
            acc = Box{};
            cnt = 0;
            for (int b = 0; b < nb - 1; ++b) {
                acc.grow(bin[std::size_t(b)]);
                cnt += n[std::size_t(b)];
                if (cnt == 0 || cnt == count) continue;
                float c = acc.area() * float(cnt) + rightCost[std::size_t(b + 1)];
                if (c < bestCost) {
                    bestCost = c;
                    bestAxis = axis;
                    bestSplit = b;
                }
            }
        }
        float leafCost = bounds.area() * float(count);
        std::uint32_t mid;
        if (bestAxis >= 0 && (bestCost + bounds.area() < leafCost || count > std::uint32_t(opt.maxLeafSize))) {
            float scale = float(nb) / ext[bestAxis];
            auto it = std::partition(order.begin() + first, order.begin() + first + count, [&](std::uint32_t t) {
                int b = std::min(nb - 1, int((centroid[t][bestAxis] - cbounds.lo[bestAxis]) * scale));
                return b <= bestSplit;
            });
            mid = std::uint32_t(it - order.begin());
        } else if (count > std::uint32_t(opt.maxLeafSize)) {
            // All centroids coincide: split the list in half (any split is as good).
            mid = first + count / 2;
        } else {
            return setLeaf(node, first, count);
        }
        auto left = std::uint32_t(nodes.size());
        nodes.emplace_back();
        nodes.emplace_back();
        nodes[node].index = left;
        nodes[node].count = 0;
        build(left, first, mid - first, level + 1);
        build(left + 1, mid, first + count - mid, level + 1);
    }
};

std::uint32_t floatBits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}
float bitsFloat(std::uint32_t u) {
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

// Slab test; returns the entry distance or +inf when missed. The exit
// distance is scaled up by RTGI_BVH_BOX_EXIT_SCALE so that rounding cannot
// reject a box the ray touches (see bvh_shared.h).
float intersectBox(const gpu::BvhNode& n, glm::vec3 o, glm::vec3 invD, float tMin, float tMax) {
    glm::vec3 t0 = (n.lo - o) * invD, t1 = (n.hi - o) * invD;
    glm::vec3 tn = glm::min(t0, t1), tf = glm::max(t0, t1) * RTGI_BVH_BOX_EXIT_SCALE;
    float enter = std::max(std::max(tn.x, tn.y), std::max(tn.z, tMin));
    float exit = std::min(std::min(tf.x, tf.y), std::min(tf.z, tMax));
    return enter <= exit ? enter : 1e30f;
}

glm::vec3 safeInverse(glm::vec3 d) {
    glm::vec3 r;
    for (int i = 0; i < 3; ++i) r[i] = 1.0f / (std::abs(d[i]) > 1e-20f ? d[i] : std::copysign(1e-20f, d[i]));
    return r;
}

template <bool Any>
std::optional<RayHit> traverse(const Bvh& bvh, glm::vec3 o, glm::vec3 d, float tMin, float tMax) {
    std::optional<RayHit> best;
    if (bvh.nodes.empty()) return best;
    glm::vec3 invD = safeInverse(d);
    const WatertightRay ray = watertightRay(o, d);
    std::array<std::uint32_t, RTGI_BVH_STACK> stack{};
    int sp = 0;
    std::uint32_t node = 0;
    if (intersectBox(bvh.nodes[0], o, invD, tMin, tMax) >= 1e30f) return best;
    for (;;) {
        const gpu::BvhNode& n = bvh.nodes[node];
        if (n.count > 0) {
            for (std::uint32_t i = n.index; i < n.index + n.count; ++i)
                if (auto h = intersectTriangle(bvh.triangles[i], ray, tMin, tMax)) {
                    best = h;
                    tMax = h->t;
                    if (Any) return best;
                }
        } else {
            // Nearer child first; the farther one goes on the stack.
            std::uint32_t a = n.index, b = n.index + 1;
            float ta = intersectBox(bvh.nodes[a], o, invD, tMin, tMax);
            float tb = intersectBox(bvh.nodes[b], o, invD, tMin, tMax);
            if (tb < ta) {
                std::swap(a, b);
                std::swap(ta, tb);
            }
            if (ta < 1e30f) {
                if (tb < 1e30f) stack[std::size_t(sp++)] = b;
                node = a;
                continue;
            }
        }
        // Pop, skipping nodes that lie beyond the closest hit found since.
        bool found = false;
        while (sp > 0) {
            node = stack[std::size_t(--sp)];
            if (intersectBox(bvh.nodes[node], o, invD, tMin, tMax) < 1e30f) {
                found = true;
                break;
            }
        }
        if (!found) return best;
    }
}

}  // namespace

Bvh buildBvh(const std::vector<glm::vec3>& v, const BvhBuildOptions& options) {
    Builder b{options, {}, {}, {}, {}, 0};
    const std::size_t n = v.size() / 3;
    b.triBox.resize(n);
    b.centroid.resize(n);
    for (std::size_t t = 0; t < n; ++t) {
        for (int k = 0; k < 3; ++k) b.triBox[t].grow(v[3 * t + std::size_t(k)]);
        b.centroid[t] = (v[3 * t] + v[3 * t + 1] + v[3 * t + 2]) / 3.0f;
    }
    b.order.resize(n);
    std::iota(b.order.begin(), b.order.end(), 0u);
    b.nodes.reserve(2 * n + 1);
    b.nodes.emplace_back();
    b.build(0, 0, std::uint32_t(n), 0);
    Bvh out;
    out.nodes = std::move(b.nodes);
    out.depth = b.depth;
    out.triangles.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint32_t t = b.order[i];
        out.triangles[i] = {glm::vec4(v[3 * t], bitsFloat(t)), glm::vec4(v[3 * t + 1], 0), glm::vec4(v[3 * t + 2], 0)};
    }
    return out;
}

std::vector<glm::vec3> sceneTriangles(const Scene& scene) {
    std::vector<glm::vec3> out;
    for (auto& d : scene.draws)
        for (std::uint32_t k = 0; k < d.indexCount; ++k)
            out.push_back(scene.vertices[scene.indices[d.firstIndex + k]].position);
    return out;
}

// Woop, Benthin, Wald 2013, section 3 (permutation and shear of the ray):
// kz is the axis of the largest |d| component, kx and ky follow it
// cyclically and are swapped where d[kz] < 0, which keeps the triangles'
// winding (the sign of det) in the sheared space. The tie-breaking (the
// lower axis wins) is the same as in bvh.glsl bvhRay.
WatertightRay watertightRay(glm::vec3 o, glm::vec3 d) {
    glm::vec3 a = glm::abs(d);
    WatertightRay r;
    r.origin = o;
    r.kz = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
    r.kx = (r.kz + 1) % 3;
    r.ky = (r.kx + 1) % 3;
    if (d[r.kz] < 0.0f) std::swap(r.kx, r.ky);
    r.sx = d[r.kx] / d[r.kz];
    r.sy = d[r.ky] / d[r.kz];
    r.sz = 1.0f / d[r.kz];
    return r;
}

// Section 4 of the paper: the vertices relative to the origin, sheared so
// that the ray runs along +z from (0, 0); U, V, W are twice the signed areas
// of the 2D triangles (0, B, C), (0, C, A), (0, A, B), i.e. the unnormalized
// barycentrics of A = v0, B = v1, C = v2. An edge shared with a neighbour
// is computed from the same two sheared vertices in the other order there,
// x·y' − y·x' against x'·y − y'·x: exactly the negated float as long as
// neither product is fused into the subtraction (bvh.cpp is compiled with
// -ffp-contract=off, see CMakeLists.txt; bvh.glsl marks these `precise`).
std::optional<RayHit> intersectTriangle(const gpu::BvhTriangle& tri, const WatertightRay& r, float tMin, float tMax) {
    const glm::vec3 a = glm::vec3(tri.v0) - r.origin, b = glm::vec3(tri.v1) - r.origin, c = glm::vec3(tri.v2) - r.origin;
    const float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
    const float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
    const float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
    float u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    // An edge function of exactly 0 may be a float product tie where the
    // true sign is not 0: products of floats are exact in double, so the
    // recomputed difference has the true sign (the paper's fallback).
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
        u = float(double(cx) * double(by) - double(cy) * double(bx));
        v = float(double(ax) * double(cy) - double(ay) * double(cx));
        w = float(double(bx) * double(ay) - double(by) * double(ax));
    }
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return std::nullopt;
    const float det = u + v + w;
    if (det == 0.0f) return std::nullopt;  // the ray lies in the triangle's plane
    // Scaled distance: the sheared z of the vertices interpolated with the
    // unnormalized barycentrics (z' = z / d[kz], so t = z').
    const float az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
    const float inv = 1.0f / det;
    const float t = (u * az + v * bz + w * cz) * inv;
    if (!(t > tMin && t < tMax)) return std::nullopt;
    return RayHit{t, floatBits(tri.v0.w), v * inv, w * inv};
}

std::optional<RayHit> intersectTriangle(const gpu::BvhTriangle& tri, glm::vec3 o, glm::vec3 d, float tMin, float tMax) {
    return intersectTriangle(tri, watertightRay(o, d), tMin, tMax);
}

std::optional<RayHit> traceClosest(const Bvh& bvh, glm::vec3 o, glm::vec3 d, float tMin, float tMax) {
    return traverse<false>(bvh, o, d, tMin, tMax);
}

bool traceAny(const Bvh& bvh, glm::vec3 o, glm::vec3 d, float tMin, float tMax) {
    return traverse<true>(bvh, o, d, tMin, tMax).has_value();
}

}  // namespace rtgi
