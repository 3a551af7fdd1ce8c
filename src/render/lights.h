#pragma once
// The lights of the real-time path besides the sun (docs/lights.md): the
// scene's point and spot lights, plus one area light per connected emissive
// region (src/scene/emitters.h); per frame, the ones whose influence sphere
// misses the view frustum are culled, the others get shadow-map layers
// (spot: 1 perspective map, point / area: a cube of 6).
#include "render/gpu_types.h"
#include "render/settings.h"
#include "scene/scene.h"

#include <string>
#include <vector>

namespace rtgi {

struct LocalLight {
    std::string name;
    gpu::GpuLight gpu{};  // cone.z/.w (shadow layer, texel size) are filled per frame
    gpu::GpuLightShape shape{};  // rectangle (area) or source radius (point/spot); halfU.w (far plane) per frame
    float influence = 0;  // radius beyond which its irradiance is below the cutoff (or its range)
};

struct LocalLights {
    std::vector<LocalLight> lights;  // scene point/spot lights first, then the area lights
    int sceneLights = 0;             // how many of them are the scene's own (the reference's lights)
    std::vector<std::pair<std::string, std::string>> leftOut;  // (light, reason): zero intensity
};

// Irradiance below which a light adds nothing visible: reflected radiance
// ρ/π·E × exposure below 2⁻¹⁰ even for ρ = 1 (linear, before tonemapping).
float lightCutoffIrradiance(float exposure);

LocalLights resolveLocalLights(const Scene& scene, const Settings& settings);

// Radiometric range of the products the passes form, in double before any
// float exists (docs/STABILITY.md "Radiometric range"): emission x
// emissive.scale and sun irradiance x sun.scale at most kMaxRadiance; an
// emissive region's intensity Le·A and a point/spot light's colour x intensity
// at most kMaxRadiance; the flux all lights can put into the RSMs and the LPV,
// sum of 4π·I plus E_sun·D² (D: the scene's bounding diagonal, which bounds
// the sun RSM's footprint), at most kMaxLightFlux. Throws SceneError naming
// the scene and the light or material when the scene alone is beyond, and
// ConfigError naming the setting when emissive.scale / sun.* push it beyond.
// kMaxRadiance: scene/scene.h. The flux bound leaves the fp32 LPV volumes
// a factor 64 (propagation steps) x 4 pi (SH lobe sums) x 400 below FLT_MAX.
inline constexpr double kMaxLightFlux = 1e33;
void checkRadiometricRange(const Scene& scene, const Settings& settings);
// Cheap test (no region extraction): a point/spot light with intensity > 0,
// or with emissive.lights=on an emissive material that a draw uses.
bool hasLocalLights(const Scene& scene, const Settings& settings);

// Sphere (world centre, radius) against the frustum of viewProj (planes of
// Gribb & Hartmann 2001); true when it may intersect.
bool sphereInFrustum(const glm::mat4& viewProj, glm::vec3 centre, float radius);

// One shadow-map layer of a light: its view-projection and the light index.
struct ShadowView {
    glm::mat4 viewProj{1.0f};
    int light = 0;
    int layer = 0;
    float tanHalfFov = 1.0f;
};

// Per-frame culling and shadow layout: lights outside the frustum get type
// 0 (the direct pass skips them); with `shadows`, each kept light gets its
// layers (cone.z = first layer, cone.w = normal-offset texel size per unit
// distance for a map of `mapSize`). `bounds`: the scene box (far planes
// never reach past it).
struct FrameLights {
    std::vector<gpu::GpuLight> gpu;  // one per LocalLights entry
    std::vector<gpu::GpuLightShape> shapes;  // parallel to gpu
    std::vector<ShadowView> views;   // in layer order
    int culled = 0, shadowed = 0;
};
FrameLights frameLights(const LocalLights& ll, const glm::mat4& cameraViewProj, const Aabb& bounds, bool shadows,
                        int mapSize);
// Layers needed when every light is kept (the shadow array's size).
int maxShadowLayers(const LocalLights& ll);

}  // namespace rtgi
