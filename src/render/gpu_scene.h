#pragma once
// The scene on the GPU: one vertex buffer (position, normal, uv, material id
// per vertex), one index buffer, the material table, punctual lights and the
// base-colour textures resampled into one 2D array. One draw call renders
// the whole scene (G-buffer, shadow map, RSM).
#include "gl/resources.h"
#include "render/gpu_types.h"
#include "render/settings.h"
#include "scene/scene.h"

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

namespace rtgi {

namespace gl {
class ProgramCache;
}

struct GpuVertex {
    float position[3];
    float normal[3];
    float uv[2];
    std::uint32_t material;
};
static_assert(sizeof(GpuVertex) == 36);

// The effective sun after settings overrides.
struct Sun {
    glm::vec3 towardSun{0, 1, 0};  // unit, world
    glm::vec3 irradiance{0.0f};    // E⊥ rgb
};
std::optional<Sun> resolveSun(const Scene& scene, const Settings& settings);
glm::vec3 resolveSky(const Scene& scene, const Settings& settings);
// Camera after the scene's own, a named view and --set camera.* overrides.
Camera resolveCamera(const Scene& scene, const Settings& settings);
// Names of the views of benchmarks/views/ that apply to the scene (setting `view`).
std::vector<std::string> namedViews(const Scene& scene);
// Materials after settings overrides (floor.roughness, emissive.scale).
std::vector<Material> resolveMaterials(const Scene& scene, const Settings& settings);

class GpuScene {
public:
    // restPose: `scene` holds its rest pose (false: a moved state, which the
    // transform path replaces by a full upload before it first moves objects).
    GpuScene(gl::MemoryLedger& ledger, const Scene& scene, const Settings& settings, bool restPose = true);
    // A moving scene (issue 23): rewrites the vertex buffer (positions,
    // normals) or the punctual lights from the scene's current state; the
    // counts must not change.
    // Object motion: before the first rewrite after a rendered frame, the
    // buffer is copied on the GPU into previousVertices() (allocated on the
    // first move), so the G-buffer velocity holds camera and object motion.
    void updateVertices(const Scene& scene);
    // Object motion by transforms (docs/temporal.md, "Object motion"): `scene`
    // is a state whose vertices are `rest` moved by scene.motions (and rest
    // elsewhere; without motions: the rest pose itself, every object at the
    // identity). Only the objects' matrices are uploaded (ObjectTransform,
    // 144 bytes per object); the object-space vertices of an object are
    // uploaded once, when it first moves. applyTransforms (Renderer::render,
    // profiled as "scene.transform") then writes the moved vertices into the
    // vertex buffer and their previous positions into previousVertices().
    // Returns false (nothing changed) when the motions cannot be applied this
    // way (ranges out of bounds, an object overlapping another one); the caller
    // then re-uploads with updateVertices.
    bool setTransforms(const Scene& scene, const std::vector<Vertex>& rest);
    // The pending transform dispatch (no-op when none is pending).
    void applyTransforms(gl::ProgramCache& programs);
    bool transformsPending() const { return transformPending_; }
    // Objects moved by transforms so far (0 in a static scene).
    int transformObjectCount() const { return int(objectMatrices_.size()); }
    // Bytes this GpuScene uploaded (buffer sub-data) since it was built, for
    // the cost of a moving scene's update (lastSceneUpdate).
    std::int64_t uploadedBytes() const { return uploadedBytes_; }
    void updateLights(const Scene& scene);
    // Brackets one rendered frame: beginFrame points previousVertices() (and
    // the VAO's RTGI_ATTR_PREV_POSITION) at the geometry the last frame
    // rendered: the copy when it has moved since, else the vertex buffer itself.
    void beginFrame();
    void endFrame();
    const gl::Buffer& previousVertices() const { return prevDistinct_ ? prevVbo_ : vbo_; }
    // True while this frame's geometry differs from the last frame's (beginFrame).
    bool objectMotion() const { return prevDistinct_; }
    // Counts updateVertices calls: a pass that built something from the
    // geometry (the reference's BVH) rebuilds it when this changed.
    std::uint64_t geometryVersion() const { return geometryVersion_; }
    // Counts updateVertices and updateLights calls: an image of the scene
    // (the reference) is still valid only while this is unchanged.
    std::uint64_t stateVersion() const { return stateVersion_; }
    // Binds the VAO and issues the one indexed draw (the caller binds the program).
    void draw() const;
    GLuint vao() const { return vao_.id(); }
    const gl::Buffer& vertices() const { return vbo_; }
    const gl::Buffer& indices() const { return ibo_; }
    const gl::Buffer& materials() const { return materials_; }
    const gl::Buffer& lights() const { return lights_; }
    const gl::Texture& textures() const { return textures_; }
    int indexCount() const { return indexCount_; }
    int punctualLightCount() const { return lightCount_; }
    int materialCount() const { return materialCount_; }
    // Binds materials, lights and the texture array at their shared bindings.
    void bindTables() const;
    // The buffers of the transform path (null until an object moves by transforms).
    const gl::Buffer& movableVertices() const { return movable_; }
    const gl::Buffer& objectTransforms() const { return transforms_; }

private:
    using Ranges = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
    // Copies the vertex buffer (the last rendered frame's geometry) into prevVbo_.
    void copyToPrevious();
    // Replaces the whole vertex buffer (a staging buffer and a GPU copy).
    void uploadVertices(const std::vector<GpuVertex>& verts);
    void uploadTransforms();
    bool registerObjects(const Scene& scene, const std::vector<Vertex>& rest);
    gl::VertexArrayHandle vao_;
    gl::MemoryLedger* ledger_ = nullptr;
    gl::Buffer vbo_, ibo_, materials_, lights_;
    gl::Buffer prevVbo_;  // the last rendered frame's vertices while they differ from vbo_
    bool rendered_ = false, prevDistinct_ = false;
    std::uint64_t renderedVersion_ = 0;  // geometryVersion_ of the last rendered frame
    // Transform path: the objects (by their vertex ranges), each vertex's owner
    // (-1: none; sized on the first move), the matrices of the current state
    // and of the last rendered frame (double, rest -> world).
    std::map<Ranges, int> objects_;
    std::vector<int> owner_;
    std::vector<glm::dmat4> objectMatrices_, renderedMatrices_;
    gl::Buffer movable_, transforms_;
    std::uint32_t movableCount_ = 0;
    // rigid_: the vertex buffer holds the rest pose outside the objects (no
    // direct rewrite since); prevRigid_: so does prevVbo_.
    bool rigid_ = true, prevRigid_ = false;
    // copyPrevious_: applyTransforms copies the vertex buffer into prevVbo_
    // (a dispatch) before the transform.
    bool transformPending_ = false, writePrevious_ = false, copyPrevious_ = false;
    std::int64_t uploadedBytes_ = 0;
    gl::Texture textures_;
    int indexCount_ = 0, lightCount_ = 0, materialCount_ = 0;
    std::uint64_t geometryVersion_ = 0, stateVersion_ = 0;
};

}  // namespace rtgi
