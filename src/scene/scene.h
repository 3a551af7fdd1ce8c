#pragma once
// The CPU scene: every glTF node's primitives flattened to world space (one
// vertex/index array, one draw range per primitive), materials, lights and
// cameras. Flattening keeps the rasterizer, the BVH and merging of several
// --scene inputs trivial; the scenes rtgi targets fit comfortably.
#include "scene/animation.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rtgi {

// Bad input: one sentence naming the file (or option) and the problem.
class SceneError : public std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Largest radiance, irradiance or intensity a scene may hold, after every
// multiplier (emissiveStrength, colour x intensity, emissive.scale, sun.scale,
// Le x area): the passes multiply it by at most 1e8 (1/d^2 with d >= 1e-4 in
// lib/lights.glsl) before a store, and 1e38 < FLT_MAX (docs/STABILITY.md
// "Radiometric range").
inline constexpr double kMaxRadiance = 1e30;

struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec2 uv;
};

struct Image {  // RGBA8, sRGB-encoded base colour
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;
    std::string name;
};

struct Material {
    std::string name;
    glm::vec4 baseColor{0.8f, 0.8f, 0.8f, 1.0f};  // linear
    float metallic = 0.0f;
    float roughness = 1.0f;
    glm::vec3 emissive{0.0f};  // linear radiance (emissiveFactor × strength)
    // glTF doubleSided: false (the default) = the surface emits only from its front face, the side
    // its triangles are counter-clockwise from (docs/reference.md, "Emitters").
    bool doubleSided = false;
    int baseColorTexture = -1;  // index into Scene::images
};

struct DrawRange {
    std::uint32_t firstIndex = 0;
    std::uint32_t indexCount = 0;
    int material = 0;
};

enum class LightType { Directional, Point, Spot };
struct Light {
    LightType type = LightType::Directional;
    std::string name;
    glm::vec3 color{1.0f};
    // Directional: irradiance E⊥ (W/m², KHR "lux"); point/spot: intensity (W/sr).
    float intensity = 1.0f;
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f};  // direction the light travels
    float range = 0.0f;                       // 0 = infinite
    float innerCone = 0.0f, outerCone = 0.7853982f;
    float radius = 0.0f;  // point/spot: radius of the emitting sphere (soft shadows; 0 = punctual)
};

struct Camera {
    std::string name;
    glm::vec3 position{0.0f, 1.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovY = 1.0471976f;  // radians
    float near = 0.05f, far = 200.0f;
};

struct Aabb {
    glm::vec3 lo{1e30f}, hi{-1e30f};
    void grow(glm::vec3 p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    bool empty() const { return lo.x > hi.x; }
    glm::vec3 center() const { return 0.5f * (lo + hi); }
    glm::vec3 extent() const { return hi - lo; }
};

struct Scene {
    std::string name;  // "builtin:atrium" or the file path(s)
    std::vector<Vertex> vertices;
    std::vector<std::uint32_t> indices;
    std::vector<DrawRange> draws;
    std::vector<Material> materials;
    std::vector<Image> images;
    std::vector<Light> lights;
    std::vector<Camera> cameras;
    // Constant sky radiance seen by rays that leave the scene (and the
    // ambient term of the real-time path when no indirect technique runs).
    glm::vec3 sky{0.0f};
    std::vector<std::string> warnings;  // repairs made while loading
    // Settings the scene's author suggests (e.g. exposure, LPV grid for its
    // scale), applied before --config / --set / sweep assignments, which win;
    // results.json records the effective values and lists these under
    // "scene_settings".
    std::vector<std::pair<std::string, std::string>> suggestedSettings;
    // The glTF node animations (empty for a still scene): the vertices, lights
    // and cameras above are the rest pose; applySceneAnimation moves them.
    SceneAnimation animation;
    // A scene state's rigid motions from the rest pose (transformVertices
    // records them; empty for a rest scene or vertices written directly):
    // `vertices` equal the rest pose's except in these ranges, which are the
    // rest vertices moved by the motion's matrix (a later motion wins).
    std::vector<RigidMotion> motions;

    // Vertex ranges [first, end) of planes marked "ground" (docs/scenes.md): finite stand-ins for an
    // unbounded floor, which focusBounds() leaves out.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> groundVertices;

    Aabb bounds() const;
    // The region a finite volume should hold (the LPV's auto-fit, docs/lpv.md "Auto-fit"): without ground
    // planes, bounds(); with them, the bounds of the other geometry grown by its largest extent on every
    // side and clipped to bounds() (the ground within one model size of the model); bounds() when the
    // scene is nothing but ground.
    Aabb focusBounds() const;
    std::size_t triangleCount() const { return indices.size() / 3; }
    const Light* sun() const;  // first directional light, or nullptr
    // Roughness of the glossiest material (1 when there are none).
    float minRoughness() const;
    // Appends another scene (offsets indices, materials and images).
    void merge(const Scene& other);
};

// Loads a .gltf / .glb (throws SceneError naming the file and the problem).
Scene loadGltf(const std::string& path);
// Built-in scene by name (scenes/NAME.json); throws SceneError for unknown names.
Scene loadBuiltin(const std::string& name);
std::vector<std::string> builtinSceneNames();
// "builtin:NAME" or a path.
Scene loadSceneSpec(const std::string& spec);

// Repairs applied by every loader: zero-length / non-finite normals are
// replaced by the face normal, degenerate triangles are dropped; each repair
// class adds one warning line. Throws SceneError on NaN/Inf positions.
void validateAndRepair(Scene& scene, const std::string& source);

// Host memory a loader may fill with one scene: half of MemAvailable
// (/proc/meminfo), 8 GiB where that is unknown. Checked before flattening.
std::uint64_t sceneHostMemoryLimit();

// When the scene has no camera: one looking at the bounds from the front,
// above, framing the whole box. When it has no sun: none is invented (a
// scene without a directional light is a valid configuration).
Camera defaultCamera(const Scene& scene);

}  // namespace rtgi
