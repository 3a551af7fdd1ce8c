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

LocalLights resolveLocalLights(const Scene& scene, const Settings& settings, int maxLayers) {
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
        L.peak = peak;
        // Kept in the buffer (the reference indexes the scene's lights in
        // order) but culled every frame when it cannot add anything.
        if (!(peak > 0.0f)) out.leftOut.push_back({name, "zero intensity"});
        out.lights.push_back(L);
    }
    out.sceneLights = int(out.lights.size());
    if (settings.light.emissiveLights) {
        std::vector<EmissiveRegion> regions = emissiveRegions(scene, resolveMaterials(scene, settings));
        // emissive.max_lights: the brightest regions by power, in their order.
        std::vector<char> keep(regions.size(), 1);
        const std::size_t cap = std::size_t(std::max(settings.light.maxAreaLights, 0));
        if (regions.size() > cap) {
            std::vector<std::size_t> order(regions.size());
            for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
            auto power = [&](std::size_t i) { return maxComponent(regions[i].power()); };
            std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return power(a) > power(b); });
            double total = 0, left = 0;
            for (std::size_t k = 0; k < order.size(); ++k) {
                total += power(order[k]);
                if (k >= cap) keep[order[k]] = 0, left += power(order[k]);
            }
            char pct[32];
            std::snprintf(pct, sizeof pct, "%.3g", total > 0 ? 100.0 * left / total : 0.0);
            out.warnings.push_back(scene.name + ": " + std::to_string(regions.size()) +
                                   " emissive regions; the brightest " + std::to_string(cap) +
                                   " are area lights (emissive.max_lights=" + std::to_string(cap) + "), the other " +
                                   std::to_string(regions.size() - cap) + " (" + pct +
                                   " % of the emitted power) only emit and light nothing in the real-time path");
        }
        // emissive.split: each kept region's rectangle is cut into n × n
        // rectangles of its radiance (the diffuse term sums to the whole
        // rectangle's exactly); every piece is a light with its own cube
        // shadow map and RSM, so the penumbrae are searched from n² origins.
        const std::size_t kept = std::size_t(std::count(keep.begin(), keep.end(), char(1)));
        int n = settings.light.emissiveSplit;
        if (n == 0) n = kept > 0 && kept * 4 <= cap ? 2 : 1;
        out.emissiveSplit = n;
        int r = 0;
        for (std::size_t k = 0; k < regions.size(); ++k) {
            const EmissiveRegion& reg = regions[k];
            if (!keep[k]) continue;
            const std::string region = "emissive region " + std::to_string(r++);
            const glm::dvec3 halfU = reg.halfU / double(n), halfV = reg.halfV / double(n);
            const double area = reg.area / double(n * n);
            glm::vec3 nrm(reg.normal);
            for (int piece = 0; piece < n * n; ++piece) {
                const int a = piece % n, b = piece / n;
                const glm::dvec3 centre = reg.centroid + reg.halfU * (double(2 * a + 1) / n - 1.0) +
                                          reg.halfV * (double(2 * b + 1) / n - 1.0);
                LocalLight L;
                L.name = n > 1 ? region + " piece " + std::to_string(piece) : region;
                // Slightly in front of the emitting surface, so the region itself
                // (behind the light, where the cosine lobe is 0) never shadows it.
                glm::vec3 p = glm::vec3(centre) + nrm * float(0.01 * std::sqrt(area));
                glm::vec3 i0 = glm::vec3(reg.radiance * area);  // I(θ) = Le·A·cos θ
                L.gpu.positionRange = glm::vec4(p, 0);
                L.gpu.colorIntensity = glm::vec4(i0, 0);
                L.gpu.directionType = glm::vec4(nrm, RTGI_LIGHT_AREA);
                L.gpu.cone = glm::vec4(0, 0, -1, 0);
                L.shape.centerRadius = glm::vec4(glm::vec3(centre), 0);
                L.shape.halfU = glm::vec4(glm::vec3(halfU), 0);
                // Soft-shadow rays per side: 4 for a whole panel, 2 for a piece (2 x 2 pieces sample the
                // panel's 4x4 grid together; finer splits trace more).
                L.shape.halfV = glm::vec4(glm::vec3(halfV), n == 1 ? 4.0f : 2.0f);
                L.peak = maxComponent(i0);
                // The pieces reach as far as the whole region would: the
                // cut must not move where the panel's light is culled.
                L.influence = influenceRadius(0.0f, maxComponent(glm::vec3(reg.radiance * reg.area)), cutoff);
                out.lights.push_back(L);
            }
        }
    }
    // Faces, and shadow layers for the brightest lights first.
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < out.lights.size(); ++i) {
        LocalLight& L = out.lights[i];
        L.faces = int(L.gpu.directionType.w) == RTGI_LIGHT_SPOT ? 1 : 6;
        L.firstFace = out.faces;
        out.faces += L.faces;
        if (L.peak > 0.0f) order.push_back(i);
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](auto a, auto b) { return out.lights[a].peak > out.lights[b].peak; });
    int unshadowed = 0;
    for (std::size_t i : order) {
        LocalLight& L = out.lights[i];
        if (out.shadowLayers + L.faces <= maxLayers) {
            L.firstLayer = out.shadowLayers;
            out.shadowLayers += L.faces;
        } else {
            ++unshadowed;
        }
    }
    if (unshadowed > 0)
        out.warnings.push_back(scene.name + ": " + std::to_string(unshadowed) +
                               " local lights get no shadow map: the shadow array holds " + std::to_string(maxLayers) +
                               " layers (GL_MAX_ARRAY_TEXTURE_LAYERS of GL 4.5) and the brighter lights take them; "
                               "those lights are drawn unshadowed");
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

int maxShadowLayers(const LocalLights& ll) { return ll.faces; }

int localRsmSize(const Settings& s, int faces) {
    int n = s.lpv.rsm;
    const double limit = double(s.light.budget) * double(s.lpv.rsm) * double(s.lpv.rsm);
    while (s.light.budget > 0 && n > 16 && double(faces) * double(n) * double(n) > limit) n = std::max(16, n / 2);
    return n;
}

namespace {
// The face's part of the influence region (apex, and the far corners of its
// square frustum at distance `far`, which holds every point of the sphere in
// the face's pyramid) against the camera frustum's planes, widened by
// `margin`: false when all five points lie outside one plane.
bool faceInView(const glm::mat4& cameraViewProj, glm::vec3 apex, glm::vec3 axis, glm::vec3 up, float tanHalf,
                float far, float margin) {
    const glm::vec3 right = glm::normalize(glm::cross(axis, up)), u = glm::cross(right, axis);
    glm::vec3 pts[5] = {apex};
    int k = 1;
    for (int sx = -1; sx <= 1; sx += 2)
        for (int sy = -1; sy <= 1; sy += 2)
            pts[k++] = apex + far * (axis + tanHalf * (float(sx) * right + float(sy) * u));
    const glm::mat4 t = glm::transpose(cameraViewProj);
    const glm::vec4 planes[6] = {t[3] + t[0], t[3] - t[0], t[3] + t[1], t[3] - t[1], t[3] + t[2], t[3] - t[2]};
    for (auto& p : planes) {
        const float len = glm::length(glm::vec3(p));
        if (!(len > 0.0f)) continue;
        bool allOut = true;
        for (auto& q : pts) allOut &= glm::dot(glm::vec3(p), q) + p.w < -margin * len;
        if (allOut) return false;
    }
    return true;
}
}  // namespace

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
            // Margin of the face culling: the direct pass looks a face up at
            // p + normal offset (1.5 texels), which can cross a face edge.
            const float margin = 0.02f * far;
            bool spot = int(g.directionType.w) == RTGI_LIGHT_SPOT;
            auto layer = [&](int k) { return L.firstLayer < 0 ? -1 : L.firstLayer + k; };
            float halfFov;
            if (spot) {
                // The cone plus one texel of margin for the PCF taps; beyond
                // 80° the texels stretch too much (wider cones clip there).
                halfFov = std::min(std::acos(std::clamp(g.cone.y, -1.0f, 1.0f)) * 1.02f + 1.0f / float(mapSize),
                                   glm::radians(80.0f));
                glm::vec3 d(g.directionType);
                glm::vec3 up = std::abs(d.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
                glm::mat4 vp = glm::perspective(2.0f * halfFov, 1.0f, near, far) * glm::lookAt(pos, pos + d, up);
                f.views.push_back({vp, int(i), layer(0), std::tan(halfFov), L.firstFace,
                                   faceInView(cameraViewProj, pos, d, up, std::tan(halfFov), far, margin)});
            } else {
                halfFov = glm::radians(45.0f);
                const glm::vec3 axis[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
                const glm::vec3 up[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
                glm::mat4 proj = glm::perspective(glm::radians(90.0f), 1.0f, near, far);
                for (int k = 0; k < 6; ++k)
                    f.views.push_back({proj * glm::lookAt(pos, pos + axis[k], up[k]), int(i), layer(k), 1.0f,
                                       L.firstFace + k, faceInView(cameraViewProj, pos, axis[k], up[k], 1.0f, far, margin)});
            }
            g.cone.z = float(L.firstLayer);
            // Normal offset: 1.5 texels at distance 1 (scaled by the distance in the shader).
            g.cone.w = 1.5f * 2.0f * std::tan(halfFov) / float(mapSize);
            if (L.firstLayer >= 0) ++f.shadowed;
        }
        f.gpu.push_back(g);
    }
    return f;
}

void LightSchedule::reset(const LocalLights& ll) {
    faces_.assign(std::size_t(ll.faces), FaceState{});
    changed_.clear();
}

void LightSchedule::lightChanged(int light) { changed_.push_back(light); }

void LightSchedule::invalidateAll() {
    for (auto& f : faces_) f.shadowValid = f.rsmValid = false;
}
void LightSchedule::shadowStorageLost() {
    for (auto& f : faces_) f.shadowValid = f.shadowHas = false;
}
void LightSchedule::rsmStorageLost() {
    for (auto& f : faces_) f.rsmValid = f.rsmHas = false;
}

LightSchedule::Frame LightSchedule::plan(const LocalLights& ll, FrameLights& shadow, const FrameLights* rsm,
                                         bool shadows, int budget, glm::vec3 camera) {
    Frame out;
    if (faces_.size() != std::size_t(ll.faces)) reset(ll);
    for (int light : changed_) {
        if (light < 0 || std::size_t(light) >= ll.lights.size()) continue;
        const LocalLight& L = ll.lights[std::size_t(light)];
        for (int k = 0; k < L.faces; ++k) faces_[std::size_t(L.firstFace + k)].shadowValid = faces_[std::size_t(L.firstFace + k)].rsmValid = false;
    }
    changed_.clear();
    const bool unbudgeted = budget <= 0;
    if (unbudgeted) invalidateAll();  // every needed face every frame, nothing cached
    // Per kept light: the faces it needs, how many are stale, how many have no map yet.
    struct Need {
        int light = 0;
        std::vector<const ShadowView*> shadowFaces, rsmFaces;
        int stale = 0, missing = 0;
        double priority = 0;
    };
    std::vector<Need> needs(ll.lights.size());
    for (std::size_t i = 0; i < needs.size(); ++i) needs[i].light = int(i);
    for (auto& v : shadow.views) {
        if (!shadows || v.layer < 0 || !(unbudgeted || v.inView)) continue;
        Need& n = needs[std::size_t(v.light)];
        const FaceState& f = faces_[std::size_t(v.face)];
        n.shadowFaces.push_back(&v);
        n.stale += f.shadowValid ? 0 : 1;
        n.missing += f.shadowHas ? 0 : 1;
    }
    if (rsm)
        for (auto& v : rsm->views) {
            Need& n = needs[std::size_t(v.light)];
            const FaceState& f = faces_[std::size_t(v.face)];
            n.rsmFaces.push_back(&v);
            n.stale += f.rsmValid ? 0 : 1;
            n.missing += f.rsmHas ? 0 : 1;
        }
    std::vector<Need*> pending;
    for (auto& n : needs) {
        if (n.stale == 0) continue;
        const LocalLight& L = ll.lights[std::size_t(n.light)];
        const double d2 = glm::length2(glm::vec3(L.gpu.positionRange) - camera);
        const double screen = std::min(1.0, double(L.influence) * double(L.influence) / std::max(d2, 1e-30));
        n.priority = screen * double(L.peak);
        pending.push_back(&n);
    }
    // Lights without maps (they wait) first, then the stale ones; each by priority.
    std::stable_sort(pending.begin(), pending.end(), [](const Need* a, const Need* b) {
        if ((a->missing > 0) != (b->missing > 0)) return a->missing > 0;
        return a->priority > b->priority;
    });
    int used = 0;
    for (Need* n : pending) {
        if (!unbudgeted && used > 0 && used + n->stale > budget) continue;  // a smaller one may still fit
        used += n->stale;
        for (auto* v : n->shadowFaces) {
            FaceState& f = faces_[std::size_t(v->face)];
            if (f.shadowValid) continue;
            out.drawShadows.push_back(*v);
            f.shadowValid = !unbudgeted;
            f.shadowHas = true;
            f.shadowViewProj = v->viewProj;
        }
        for (auto* v : n->rsmFaces) {
            FaceState& f = faces_[std::size_t(v->face)];
            if (f.rsmValid) continue;
            out.drawRsms.push_back(*v);
            f.rsmValid = !unbudgeted;
            f.rsmHas = true;
        }
        n->stale = n->missing = 0;
    }
    for (auto& n : needs) {
        gpu::GpuLight& g = shadow.gpu[std::size_t(n.light)];
        if (g.directionType.w == 0.0f) continue;  // culled
        if (n.missing > 0) {  // waits for its first maps: not lit, not injected
            g.directionType.w = 0.0f;
            ++out.waiting;
            continue;
        }
        for (auto* v : n.rsmFaces) {
            out.injectRsms.push_back(*v);
            out.injectRsms.back().valid = faces_[std::size_t(v->face)].rsmValid;
        }
        out.cachedFaces += n.stale;  // stale maps reused (over the budget this frame)
        for (auto* v : n.shadowFaces) out.cachedFaces += faces_[std::size_t(v->face)].shadowValid ? 1 : 0;
        for (auto* v : n.rsmFaces) out.cachedFaces += faces_[std::size_t(v->face)].rsmValid ? 1 : 0;
    }
    out.cachedFaces -= unbudgeted ? 0 : int(out.drawShadows.size() + out.drawRsms.size());
    return out;
}

glm::mat4 LightSchedule::shadowViewProj(int face) const {
    return std::size_t(face) < faces_.size() ? faces_[std::size_t(face)].shadowViewProj : glm::mat4(1.0f);
}

}  // namespace rtgi
