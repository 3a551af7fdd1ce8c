#include "scene/enclosure.h"

#include "scene/bvh.h"
#include "scene/color.h"
#include "scene/emitters.h"
#include "scene/scene.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace rtgi {

namespace {

// One source of direct light as the measure sees it: a direction to it from p, its distance (infinite
// for the sun) and its unshadowed irradiance at p on a surface with normal n.
struct Source {
    glm::vec3 dir{0.0f};
    float dist = 0.0f;
    double irradiance = 0.0;
};

Source sourceAt(const Light& l, glm::vec3 p, glm::vec3 n) {
    Source s;
    if (l.type == LightType::Directional) {
        s.dir = -glm::normalize(l.direction);
        s.dist = 1e30f;
        s.irradiance = l.intensity * luminance(l.color.x, l.color.y, l.color.z) * std::max(0.0f, glm::dot(n, s.dir));
        return s;
    }
    const glm::vec3 d = l.position - p;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f) || (l.range > 0.0f && d2 > l.range * l.range)) return s;
    s.dist = std::sqrt(d2);
    s.dir = d / s.dist;
    double cone = 1.0;
    if (l.type == LightType::Spot) {
        const double c = glm::dot(-s.dir, glm::normalize(l.direction));
        const double ci = std::cos(l.innerCone), co = std::cos(l.outerCone);
        cone = std::clamp((c - co) / std::max(ci - co, 1e-6), 0.0, 1.0);
    }
    s.irradiance = l.intensity * luminance(l.color.x, l.color.y, l.color.z) * cone * std::max(0.0f, glm::dot(n, s.dir)) / d2;
    return s;
}
}  // namespace

Enclosure measureEnclosure(const Scene& scene, int rays, std::uint32_t seed) {
    Enclosure e;
    const std::vector<glm::vec3> tris = sceneTriangles(scene);
    // Normals in the same triangle order as sceneTriangles (draw order).
    std::vector<glm::vec3> normals;
    normals.reserve(tris.size());
    for (auto& d : scene.draws)
        for (std::uint32_t k = 0; k < d.indexCount; ++k)
            normals.push_back(scene.vertices[scene.indices[d.firstIndex + k]].normal);
    const std::size_t n = tris.size() / 3;
    std::vector<double> cdf(n);
    double area = 0.0;
    for (std::size_t t = 0; t < n; ++t) {
        area += 0.5 * double(glm::length(glm::cross(tris[3 * t + 1] - tris[3 * t], tris[3 * t + 2] - tris[3 * t])));
        cdf[t] = area;
    }
    if (n == 0 || !(area > 0.0) || rays <= 0) return e;
    const std::vector<EmissiveTriangle> emitters = emissiveTriangles(scene, scene.materials);
    const std::size_t sources = scene.lights.size() + emitters.size();
    const Bvh bvh = buildBvh(tris);
    const Aabb b = scene.bounds();
    const float diag = std::max(glm::length(b.hi - b.lo), 1e-6f);
    const float eps = 1e-4f * diag;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    double litWeight = 0.0, litEscaped = 0.0;
    int areaEscaped = 0, litRays = 0, tries = 0;
    // Until `rays` points were lit (a small lit room in a large dark scene), at most 16 x rays points.
    for (; litRays < rays && tries < 16 * rays; ++tries) {
        const std::size_t t = std::min<std::size_t>(
            std::size_t(std::lower_bound(cdf.begin(), cdf.end(), u01(rng) * area) - cdf.begin()), n - 1);
        // Uniform point on the triangle, its interpolated shading normal.
        const double s = std::sqrt(u01(rng)), v = u01(rng);
        const float w0 = float(1.0 - s), w1 = float(s * (1.0 - v)), w2 = float(s * v);
        const glm::vec3 p = w0 * tris[3 * t] + w1 * tris[3 * t + 1] + w2 * tris[3 * t + 2];
        glm::vec3 nrm = w0 * normals[3 * t] + w1 * normals[3 * t + 1] + w2 * normals[3 * t + 2];
        if (!(glm::dot(nrm, nrm) > 0.0f)) nrm = glm::cross(tris[3 * t + 1] - tris[3 * t], tris[3 * t + 2] - tris[3 * t]);
        nrm = glm::normalize(nrm);
        const glm::vec3 origin = p + eps * nrm;
        // Direct irradiance from one source drawn uniformly (times their count: an unbiased estimate of the sum).
        double weight = 0.0;
        if (sources > 0) {
            const std::size_t k = std::min<std::size_t>(std::size_t(u01(rng) * double(sources)), sources - 1);
            Source src;
            if (k < scene.lights.size()) {
                src = sourceAt(scene.lights[k], p, nrm);
            } else {
                const EmissiveTriangle& em = emitters[k - scene.lights.size()];
                const std::size_t et = em.triangle;
                const glm::vec3 c = (tris[3 * et] + tris[3 * et + 1] + tris[3 * et + 2]) / 3.0f;
                const glm::vec3 en = glm::normalize(glm::cross(tris[3 * et + 1] - tris[3 * et], tris[3 * et + 2] - tris[3 * et]));
                const glm::vec3 d = c - p;
                const float d2 = glm::dot(d, d);
                if (d2 > 0.0f) {
                    src.dist = std::sqrt(d2);
                    src.dir = d / src.dist;
                    // Either side of the triangle may face p (winding is not the emitting side's guarantee here).
                    src.irradiance = luminance(em.radiance.x, em.radiance.y, em.radiance.z) * em.area * std::abs(glm::dot(en, src.dir)) *
                                     std::max(0.0f, glm::dot(nrm, src.dir)) / d2;
                    src.dist *= 0.999f;  // stop short of the emitter itself
                }
            }
            if (src.irradiance > 0.0 && !traceAny(bvh, origin, src.dir, 0.0f, std::min(src.dist, 4.0f * diag + 1.0f)))
                weight = src.irradiance * double(sources);
        }
        // Cosine-distributed direction about nrm (Malley: a uniform disk point lifted onto the hemisphere).
        const double rr = std::sqrt(u01(rng)), phi = 2.0 * glm::pi<double>() * u01(rng);
        const glm::vec3 tx = glm::normalize(std::abs(nrm.x) > 0.5f ? glm::cross(nrm, glm::vec3(0, 1, 0))
                                                                    : glm::cross(nrm, glm::vec3(1, 0, 0)));
        const glm::vec3 ty = glm::cross(nrm, tx);
        const glm::vec3 dir = glm::normalize(float(rr * std::cos(phi)) * tx + float(rr * std::sin(phi)) * ty +
                                             float(std::sqrt(std::max(0.0, 1.0 - rr * rr))) * nrm);
        const bool escaped = !traceAny(bvh, origin, dir, 0.0f, 4.0f * diag + 1.0f);
        areaEscaped += escaped;
        litRays += weight > 0.0;
        litWeight += weight;
        if (escaped) litEscaped += weight;
    }
    e.lit = litWeight > 0.0;
    e.rays = e.lit ? litRays : tries;
    e.escaped = e.lit ? litEscaped / litWeight : double(areaEscaped) / double(tries);
    return e;
}

}  // namespace rtgi
