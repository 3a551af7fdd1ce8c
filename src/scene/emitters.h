#pragma once
// Emissive surfaces as lights: the emissive triangles (for the reference's
// next-event estimation) and their connected, nearly coplanar regions (each
// becomes one light of the real-time path, docs/lights.md).
#include "scene/scene.h"

#include <cstdint>
#include <vector>

namespace rtgi {

struct EmissiveTriangle {
    std::uint32_t triangle = 0;  // index in draw order (GpuScene index buffer / BVH triangle id)
    double area = 0;
    glm::vec3 radiance{0.0f};    // emitted radiance Le (material emissive after overrides)
};

// Triangles whose material emits (any channel > 0) and whose area is > 0.
// `materials` are the scene's materials after settings overrides.
std::vector<EmissiveTriangle> emissiveTriangles(const Scene& scene, const std::vector<Material>& materials);

// A connected emissive region: triangles that share a vertex position and
// whose normals agree within kRegionCos, grouped by union-find. An elongated
// region (a strip light) is cut across its principal in-plane axis into
// k = round(length / width) ≤ kMaxRegionPieces slabs of about square shape,
// each returned as a region of its own (triangles clipped to the slab).
struct EmissiveRegion {
    glm::dvec3 centroid{0.0};   // area-weighted
    glm::dvec3 normal{0, 1, 0}; // area-weighted mean face normal, on the side its vertex normals point to
    double area = 0;
    glm::dvec3 radiance{0.0};   // area-weighted mean Le
    std::size_t triangles = 0;  // triangles (or clipped parts of them) in it
    // The rectangle that stands for it in the real-time path: centred on the
    // centroid, sides along the principal axes, the aspect of its bounding
    // box there, scaled to the region's area (|halfU|·|halfV|·4 = area), so
    // a rectangular panel is itself; halfU × halfV points along `normal`.
    glm::dvec3 halfU{0.0}, halfV{0.0};
    // Radiant flux leaving the front side of a Lambertian emitter: π·Le·A.
    glm::dvec3 power() const { return 3.14159265358979323846 * radiance * area; }
};
constexpr double kRegionCos = 0.95;
constexpr int kMaxRegionPieces = 8;

std::vector<EmissiveRegion> emissiveRegions(const Scene& scene, const std::vector<Material>& materials);

}  // namespace rtgi
