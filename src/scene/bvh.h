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

// Watertight ray/triangle test (Woop, Benthin, Wald, "Watertight
// Ray/Triangle Intersection", JCGT 2(1), 2013), the same float arithmetic as
// bvhTriangle in bvh.glsl (but for GLSL's looser division); hits with tMin < t < tMax count. The ray is
// turned once into its permutation and shear (WatertightRay), each triangle
// is then sheared into 2D about the ray origin, and the signs of its three
// edge functions decide the hit. A ray meeting an edge shared by two
// triangles (same vertices, bit for bit) sees exactly negated edge functions
// in them, so it hits one or both, never neither: Möller–Trumbore let such
// rays slip through (docs/reference.md, "Ray/triangle test").
struct WatertightRay {
    glm::vec3 origin;
    int kx = 0, ky = 1, kz = 2;    // kz: axis of the largest |dir| component
    float sx = 0, sy = 0, sz = 1;  // shear: dir[kx]/dir[kz], dir[ky]/dir[kz], 1/dir[kz]
};
WatertightRay watertightRay(glm::vec3 origin, glm::vec3 dir);
std::optional<RayHit> intersectTriangle(const gpu::BvhTriangle& tri, const WatertightRay& ray, float tMin, float tMax);
std::optional<RayHit> intersectTriangle(const gpu::BvhTriangle& tri, glm::vec3 origin, glm::vec3 dir, float tMin,
                                        float tMax);
std::optional<RayHit> traceClosest(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMin, float tMax);
bool traceAny(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMin, float tMax);

}  // namespace rtgi
