#pragma once
// Bounding volume hierarchy over a Scene's triangles for the ray-traced
// reference (SPEC 7.1): built on the CPU with binned SAH, flattened into the
// node / triangle arrays that the GPU traverses (compute/lib/bvh.glsl). The
// CPU traversal below walks the same flattened arrays with the same
// triangle test, so unit tests check the exact layout the GPU sees.
#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <vector>

#include "compute/lib/bvh_shared.h"

namespace rtgi {

struct Scene;

namespace gpu {
static_assert(sizeof(BvhNode) == 32, "BvhNode must match std430 (vec3 + uint packs into 16 bytes)");
static_assert(sizeof(BvhTriangle) == 48);
}  // namespace gpu

struct BvhBuildOptions {
    int bins = 16;         // SAH bins per axis
    int maxLeafSize = 4;   // leaves are split while SAH says so or they exceed this
    int maxDepth = RTGI_BVH_STACK - 8;  // traversal stack bound (leaves may grow past maxLeafSize there)
};

struct Bvh {
    std::vector<gpu::BvhNode> nodes;          // nodes[0] = root
    std::vector<gpu::BvhTriangle> triangles;  // leaf order
    int depth = 0;
};

// Triangles are given as 3 positions each; triangle id = position in the list.
Bvh buildBvh(const std::vector<glm::vec3>& triangleVertices, const BvhBuildOptions& options = {});
// The Scene's triangles in GpuScene index-buffer order (only kept draws), so
// that triangle id t reads indices 3t..3t+2 of GpuScene::indices().
std::vector<glm::vec3> sceneTriangles(const Scene& scene);

struct RayHit {
    float t = 0;
    std::uint32_t triangle = 0;  // original triangle id
    float u = 0, v = 0;          // barycentrics of v1, v2
};

// Möller–Trumbore in float, the same arithmetic as bvh.glsl; hits with
// tMin < t < tMax count.
std::optional<RayHit> intersectTriangle(const gpu::BvhTriangle& tri, glm::vec3 origin, glm::vec3 dir, float tMin,
                                        float tMax);
std::optional<RayHit> traceClosest(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMin, float tMax);
bool traceAny(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMin, float tMax);

}  // namespace rtgi
