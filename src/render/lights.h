#pragma once
// The lights of the real-time path besides the sun (docs/lights.md): the
// scene's point and spot lights, plus one area light per connected emissive
// region (src/scene/emitters.h); per frame, the ones whose influence sphere
// misses the view frustum are culled, the others get shadow-map layers
// (spot: 1 perspective map, point / area: a cube of 6), and the light budget
// (LightSchedule) decides which of them are drawn this frame and which are
// reused from earlier frames (docs/lights.md "Light budget").
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
    float peak = 0;       // largest colour component of its intensity (the budget's priority)
    // Faces: 1 for a spot light, 6 for a point / area light. Every face has a
    // fixed index (firstFace + k, into the RSMs and the light budget's cache)
    // and, while the shadow array has room, a fixed layer (firstLayer + k;
    // -1: no layer, the light is drawn without shadows).
    int faces = 1, firstFace = 0, firstLayer = -1;
};

// Layers of the local-light shadow array at most: GL 4.5's minimum of
// GL_MAX_ARRAY_TEXTURE_LAYERS (what NVIDIA and llvmpipe report), fixed so the
// frame is the same on every device. 342 point lights need 2052.
inline constexpr int kMaxShadowLayers = 2048;

struct LocalLights {
    std::vector<LocalLight> lights;  // scene point/spot lights first, then the area lights
    int emissiveSplit = 1;           // pieces per side of each emissive region (emissive.split, resolved)
    int sceneLights = 0;             // how many of them are the scene's own (the reference's lights)
    std::vector<std::pair<std::string, std::string>> leftOut;  // (light, reason): zero intensity
    int faces = 0;         // of every light (RSM faces, the budget's cache)
    int shadowLayers = 0;  // layers given out (<= kMaxShadowLayers)
    // Lights the real-time path leaves out or draws without shadows
    // (emissive.max_lights, kMaxShadowLayers); stderr and results.json "warnings".
    std::vector<std::string> warnings;
};

// Irradiance below which a light adds nothing visible: reflected radiance
// ρ/π·E × exposure below 2⁻¹⁰ even for ρ = 1 (linear, before tonemapping).
float lightCutoffIrradiance(float exposure);

// `maxLayers`: the shadow array's layer limit (tests pass a small one). The
// brightest lights get layers first; a light whose faces no longer fit is
// drawn without shadows, with a warning.
LocalLights resolveLocalLights(const Scene& scene, const Settings& settings, int maxLayers = kMaxShadowLayers);

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

// One face of a light: its view-projection, the light index, its fixed face
// index and shadow layer (-1: none), and whether the face's part of the
// influence region (the frustum up to the influence radius) can be seen by
// the camera (a shadow face that cannot is not needed this frame).
struct ShadowView {
    glm::mat4 viewProj{1.0f};
    int light = 0;
    int layer = 0;
    float tanHalfFov = 1.0f;
    int face = 0;
    bool inView = true;
    // LightSchedule::Frame::injectRsms: the face's RSM is up to date (drawn since its light and the
    // geometry last changed; never with light.budget=0). A stale map is injected until it is redrawn;
    // the LPV's injection cache keeps only up-to-date faces (docs/lights.md "Injection cache").
    bool valid = false;
};

// Per-frame culling and shadow layout: lights outside the frustum get type
// 0 (the direct pass skips them); with `shadows`, each kept light gets its
// faces (cone.z = its fixed first layer, or -1 without one; cone.w =
// normal-offset texel size per unit distance for a map of `mapSize`).
// `bounds`: the scene box (far planes never reach past it). Views are made
// for every face of a kept light, also those without a layer (the RSMs).
struct FrameLights {
    std::vector<gpu::GpuLight> gpu;  // one per LocalLights entry
    std::vector<gpu::GpuLightShape> shapes;  // parallel to gpu
    std::vector<ShadowView> views;   // every face of the kept lights, in light order
    int culled = 0, shadowed = 0;
};
FrameLights frameLights(const LocalLights& ll, const glm::mat4& cameraViewProj, const Aabb& bounds, bool shadows,
                        int mapSize);
// Faces of every light (spot 1, point / area 6): the number of RSMs.
int maxShadowLayers(const LocalLights& ll);

// Side of each local-light RSM face: lpv.rsm, halved (not below 16) until the
// faces of all lights hold at most light.budget x lpv.rsm² texels, so the
// injection of local lights costs at most what `budget` full RSMs cost
// (light.budget=0: lpv.rsm).
int localRsmSize(const Settings& settings, int faces);

// The per-frame light budget (docs/lights.md "Light budget"): which faces are
// drawn this frame, which reuse their cached maps, which lights wait.
// A face's cached map stays valid until its light changes (lightChanged), the
// geometry changes (invalidateAll) or its storage is reallocated. Each frame
// the kept lights with stale or never-drawn faces it needs (shadow faces whose
// region the camera sees, every RSM face) are taken whole, by priority —
// never-drawn before stale, then by screen influence (min(1, (r/d)²), r the
// influence radius, d the camera distance) times peak intensity — while their
// faces fit light.budget (at least one light per frame). A kept light is lit
// only when every face it needs holds a map (otherwise it waits: nothing
// uninitialized is read). light.budget=0: every needed face every frame.
class LightSchedule {
public:
    void reset(const LocalLights& ll);  // nothing cached
    // The hook for moving lights (dynamic scenes): light `light` (index into
    // LocalLights::lights) moved or changed; its maps are redrawn by
    // priority, and reused (with the view they were drawn with) until then.
    void lightChanged(int light);
    void invalidateAll();      // the geometry moved: every map is stale (still usable until redrawn)
    void shadowStorageLost();  // the shadow array was reallocated: no face has a map
    void rsmStorageLost();     // the RSMs were reallocated

    struct Frame {
        std::vector<ShadowView> drawShadows;  // shadow faces to draw now
        std::vector<ShadowView> drawRsms;     // RSM faces to draw now
        std::vector<ShadowView> injectRsms;   // RSM faces of the lit lights (cached or drawn now)
        int waiting = 0;                      // kept lights not lit yet (a needed face has no map)
        int cachedFaces = 0;                  // needed faces reused from earlier frames
    };
    // Updates `shadow.gpu` (type 0 for waiting lights). `shadow` / `rsm`:
    // frameLights at the shadow map's / the RSM's size (rsm null: no LPV).
    Frame plan(const LocalLights& ll, FrameLights& shadow, const FrameLights* rsm, bool shadows, int budget,
               glm::vec3 camera);
    // The view-projection face `face`'s shadow map was drawn with (the
    // direct pass projects with it, so a stale map stays consistent).
    glm::mat4 shadowViewProj(int face) const;

private:
    struct FaceState {
        bool shadowValid = false, shadowHas = false, rsmValid = false, rsmHas = false;
        glm::mat4 shadowViewProj{1.0f};
    };
    std::vector<FaceState> faces_;
    std::vector<int> changed_;  // lightChanged since the last plan
};

}  // namespace rtgi
