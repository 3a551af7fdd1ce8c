#include "render/lights.h"

#include "render/gpu_scene.h"
#include "scene/emitters.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/norm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

namespace rtgi {

float lightCutoffIrradiance(float exposure) { return float(M_PI) * std::ldexp(1.0f, -10) / std::max(exposure, 1e-30f); }

namespace {
float maxComponent(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

float influenceRadius(float range, float peakIntensity, float cutoff) {
    float r = std::sqrt(peakIntensity / cutoff);  // I/d² = cutoff
    return range > 0.0f ? std::min(range, r) : r;
}
}  // namespace

LocalLights resolveLocalLights(const Scene& scene, const Settings& settings) {
    LocalLights out;
    const float cutoff = lightCutoffIrradiance(settings.post.exposure);
    int index = 0;
    for (auto& l : scene.lights) {
        if (l.type == LightType::Directional) continue;
        std::string name = l.name.empty() ? "light " + std::to_string(index) : l.name;
        ++index;
        LocalLight L;
        L.name = name;
        glm::vec3 dir = glm::length(l.direction) > 0 ? glm::normalize(l.direction) : glm::vec3(0, -1, 0);
        L.gpu.positionRange = glm::vec4(l.position, l.range);
        L.gpu.colorIntensity = glm::vec4(l.color * l.intensity, 0);
        L.gpu.directionType = glm::vec4(dir, l.type == LightType::Point ? RTGI_LIGHT_POINT : RTGI_LIGHT_SPOT);
        L.gpu.cone = glm::vec4(std::cos(l.innerCone), std::cos(l.outerCone), -1, 0);
        L.shape.centerRadius = glm::vec4(l.position, settings.light.lightRadius ? *settings.light.lightRadius : l.radius);
        float peak = maxComponent(l.color * l.intensity);
        L.influence = influenceRadius(l.range, peak, cutoff);
        // Kept in the buffer (the reference indexes the scene's lights in
        // order) but culled every frame when it cannot add anything.
        if (!(peak > 0.0f)) out.leftOut.push_back({name, "zero intensity"});
        out.lights.push_back(L);
    }
    out.sceneLights = int(out.lights.size());
    if (!settings.light.emissiveLights) return out;
    int r = 0;
    for (auto& reg : emissiveRegions(scene, resolveMaterials(scene, settings))) {
        LocalLight L;
        L.name = "emissive region " + std::to_string(r++);
        glm::vec3 n(reg.normal);
        // Slightly in front of the emitting surface, so the region itself
        // (behind the light, where the cosine lobe is 0) never shadows it.
        glm::vec3 p = glm::vec3(reg.centroid) + n * float(0.01 * std::sqrt(reg.area));
        glm::vec3 i0 = glm::vec3(reg.radiance * reg.area);  // I(θ) = Le·A·cos θ
        L.gpu.positionRange = glm::vec4(p, 0);
        L.gpu.colorIntensity = glm::vec4(i0, 0);
        L.gpu.directionType = glm::vec4(n, RTGI_LIGHT_AREA);
        L.gpu.cone = glm::vec4(0, 0, -1, 0);
        L.shape.centerRadius = glm::vec4(glm::vec3(reg.centroid), 0);
        L.shape.halfU = glm::vec4(glm::vec3(reg.halfU), 0);
        L.shape.halfV = glm::vec4(glm::vec3(reg.halfV), 0);
        L.influence = influenceRadius(0.0f, maxComponent(i0), cutoff);
        out.lights.push_back(L);
    }
    return out;
}

namespace {
std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}
double maxComponent(glm::dvec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

// The radiometric products with the scene's own values (scale 1) and with the
// settings' multipliers; the first product beyond its limit is reported.
struct RangeProblem {
    std::string what;  // "emissive region 0 (material 'lamp'): Le x A = 9.9e+41"
    double value = 0, limit = 0;
};
std::optional<RangeProblem> radiometricProblem(const Scene& scene, double emissiveScale, std::optional<double> sunE,
                                               double sunScale, bool emissiveLights) {
    double flux = 0;
    for (std::size_t m = 0; m < scene.materials.size(); ++m) {
        const double le = maxComponent(glm::dvec3(scene.materials[m].emissive)) * emissiveScale;
        if (!(le <= kMaxRadiance)) return RangeProblem{"material '" + scene.materials[m].name + "': emission", le, kMaxRadiance};
    }
    if (const Light* sun = scene.sun(); sun || sunE) {  // the same sun as resolveSun (gpu_scene.cpp)
        const double e = (sun ? maxComponent(glm::dvec3(sun->color)) : 1.0) * (sunE ? *sunE : double(sun->intensity)) * sunScale;
        if (!(e <= kMaxRadiance)) return RangeProblem{"the sun's irradiance", e, kMaxRadiance};
        const Aabb b = scene.bounds();
        const double d2 = glm::length2(glm::dvec3(b.hi) - glm::dvec3(b.lo));
        flux += e * d2;
    }
    for (auto& l : scene.lights) {
        if (l.type == LightType::Directional) continue;
        const double i = maxComponent(glm::dvec3(l.color)) * double(l.intensity);
        if (!(i <= kMaxRadiance)) return RangeProblem{"light '" + l.name + "': intensity", i, kMaxRadiance};
        flux += 4.0 * M_PI * i;
    }
    if (emissiveLights && emissiveScale > 0) {
        int r = 0;
        for (auto& reg : emissiveRegions(scene, scene.materials)) {
            const double i = maxComponent(reg.radiance) * emissiveScale * reg.area;
            if (!(i <= kMaxRadiance))
                return RangeProblem{"emissive region " + std::to_string(r) + ": emission x area = " + num(maxComponent(reg.radiance) * emissiveScale) +
                                        " x " + num(reg.area) + " m^2, an intensity of",
                                    i, kMaxRadiance};
            flux += 2.0 * M_PI * i;  // cosine lobe: ∫ I cos θ dω over the hemisphere = π I ≤ 2π I
            ++r;
        }
    }
    if (!(flux <= kMaxLightFlux)) return RangeProblem{"the flux of all lights into the RSMs and the LPV", flux, kMaxLightFlux};
    return std::nullopt;
}
}  // namespace

void checkRadiometricRange(const Scene& scene, const Settings& settings) {
    if (auto p = radiometricProblem(scene, 1.0, std::nullopt, 1.0, settings.light.emissiveLights))
        throw SceneError(scene.name + ": " + p->what + " " + num(p->value) + " exceeds " + num(p->limit) +
                         " (products on the GPU would overflow float; docs/STABILITY.md \"Radiometric range\")");
    const std::optional<double> sunE =
        settings.light.sunIrradiance ? std::optional<double>(*settings.light.sunIrradiance) : std::nullopt;
    if (auto p = radiometricProblem(scene, settings.light.emissiveScale, sunE, settings.light.sunScale,
                                    settings.light.emissiveLights))
    {
        std::string keys;  // the settings that differ from the scene's own values
        if (settings.light.emissiveScale != 1.0f) keys += "emissive.scale=" + num(settings.light.emissiveScale);
        if (settings.light.sunScale != 1.0f) keys += (keys.empty() ? "" : ", ") + std::string("sun.scale=") + num(settings.light.sunScale);
        if (sunE) keys += (keys.empty() ? "" : ", ") + std::string("sun.irradiance=") + num(*sunE);
        throw ConfigError(keys + ": " + p->what + " becomes " +
                          num(p->value) + ", more than " + num(p->limit) +
                          " (products on the GPU would overflow float; docs/STABILITY.md \"Radiometric range\")");
    }
}

bool hasLocalLights(const Scene& scene, const Settings& settings) {
    for (auto& l : scene.lights)
        if (l.type != LightType::Directional && maxComponent(l.color * l.intensity) > 0.0f) return true;
    if (!settings.light.emissiveLights || !(settings.light.emissiveScale > 0.0f)) return false;
    for (auto& d : scene.draws)
        if (d.indexCount > 0 && d.material >= 0 && std::size_t(d.material) < scene.materials.size() &&
            maxComponent(scene.materials[std::size_t(d.material)].emissive) > 0.0f)
            return true;
    return false;
}

bool sphereInFrustum(const glm::mat4& m, glm::vec3 c, float radius) {
    glm::mat4 t = glm::transpose(m);  // rows of m
    const glm::vec4 planes[6] = {t[3] + t[0], t[3] - t[0], t[3] + t[1], t[3] - t[1], t[3] + t[2], t[3] - t[2]};
    for (auto& p : planes) {
        float len = glm::length(glm::vec3(p));
        if (!(len > 0.0f)) continue;
        if (glm::dot(glm::vec3(p), c) + p.w < -radius * len) return false;
    }
    return true;
}

int maxShadowLayers(const LocalLights& ll) {
    int n = 0;
    for (auto& l : ll.lights) n += int(l.gpu.directionType.w) == RTGI_LIGHT_SPOT ? 1 : 6;
    return n;
}

FrameLights frameLights(const LocalLights& ll, const glm::mat4& cameraViewProj, const Aabb& bounds, bool shadows,
                        int mapSize) {
    FrameLights f;
    for (std::size_t i = 0; i < ll.lights.size(); ++i) {
        const LocalLight& L = ll.lights[i];
        gpu::GpuLight g = L.gpu;
        f.shapes.push_back(L.shape);
        glm::vec3 pos(g.positionRange);
        bool zero = !(maxComponent(glm::vec3(g.colorIntensity)) > 0.0f);
        if (zero || !sphereInFrustum(cameraViewProj, pos, L.influence)) {
            g.directionType.w = 0;  // culled: the direct pass skips it
            ++f.culled;
            f.gpu.push_back(g);
            continue;
        }
        if (shadows) {
            // Far plane: the influence radius, but never past the scene box.
            float far = 0;
            for (int c = 0; c < 8; ++c) {
                glm::vec3 corner((c & 1) ? bounds.hi.x : bounds.lo.x, (c & 2) ? bounds.hi.y : bounds.lo.y,
                                 (c & 4) ? bounds.hi.z : bounds.lo.z);
                far = std::max(far, glm::length(corner - pos));
            }
            far = std::max(std::min(far, L.influence) * 1.01f, 1e-6f);
            f.shapes.back().halfU.w = far;
            float near = far * 1e-3f;  // D32F keeps ~1e-3 relative depth precision at 1e6 : 1 near/far
            int first = int(f.views.size());
            bool spot = int(g.directionType.w) == RTGI_LIGHT_SPOT;
            float halfFov;
            if (spot) {
                // The cone plus one texel of margin for the PCF taps; beyond
                // 80° the texels stretch too much (wider cones clip there).
                halfFov = std::min(std::acos(std::clamp(g.cone.y, -1.0f, 1.0f)) * 1.02f + 1.0f / float(mapSize),
                                   glm::radians(80.0f));
                glm::vec3 d(g.directionType);
                glm::vec3 up = std::abs(d.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
                glm::mat4 vp = glm::perspective(2.0f * halfFov, 1.0f, near, far) * glm::lookAt(pos, pos + d, up);
                f.views.push_back({vp, int(i), first, std::tan(halfFov)});
            } else {
                halfFov = glm::radians(45.0f);
                const glm::vec3 axis[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
                const glm::vec3 up[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
                glm::mat4 proj = glm::perspective(glm::radians(90.0f), 1.0f, near, far);
                for (int k = 0; k < 6; ++k)
                    f.views.push_back({proj * glm::lookAt(pos, pos + axis[k], up[k]), int(i), first + k, 1.0f});
            }
            g.cone.z = float(first);
            // Normal offset: 1.5 texels at distance 1 (scaled by the distance in the shader).
            g.cone.w = 1.5f * 2.0f * std::tan(halfFov) / float(mapSize);
            ++f.shadowed;
        }
        f.gpu.push_back(g);
    }
    return f;
}

}  // namespace rtgi
