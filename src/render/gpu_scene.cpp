#include "render/gpu_scene.h"

#include "gl/embedded.h"
#include "gl/program.h"

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rtgi {

std::optional<Sun> resolveSun(const Scene& scene, const Settings& s) {
    const Light* l = scene.sun();
    if (!l && !s.light.sunIrradiance) return std::nullopt;
    Sun sun;
    glm::vec3 color = l ? l->color : glm::vec3(1.0f);
    float e = s.light.sunIrradiance ? *s.light.sunIrradiance : (l ? l->intensity : 0.0f);
    sun.irradiance = color * e * s.light.sunScale;
    glm::vec3 toward = l ? -l->direction : glm::vec3(0.3f, 1.0f, 0.2f);
    if (s.light.sunDirection) toward = *s.light.sunDirection;
    float len = glm::length(toward);
    sun.towardSun = len > 0 ? toward / len : glm::vec3(0, 1, 0);
    return sun;
}

glm::vec3 resolveSky(const Scene& scene, const Settings& s) {
    return s.light.sky ? glm::vec3(*s.light.sky) : scene.sky;
}

namespace {

// The view files of benchmarks/views/ (embedded) that apply to a scene:
// {"scene": "atrium", "views": {"name": {"position": [..], "target": [..], "fov": deg}}};
// "scene" is matched as a substring of the scene name ("builtin:" removed, "/+:" -> "_").
std::vector<nlohmann::json> viewFilesFor(const Scene& scene) {
    std::string sceneKey = scene.name;
    if (sceneKey.rfind("builtin:", 0) == 0) sceneKey = sceneKey.substr(8);
    for (char& ch : sceneKey)
        if (ch == '/' || ch == '+' || ch == ':') ch = '_';
    std::vector<nlohmann::json> out;
    for (int i = 0; i < kEmbeddedFileCount; ++i) {
        std::string path = kEmbeddedFiles[i].path;
        if (path.rfind("benchmarks/views/", 0) != 0) continue;
        auto j = nlohmann::json::parse(kEmbeddedFiles[i].text, nullptr, false);
        if (j.is_discarded() || !j.contains("views")) continue;
        std::string fileScene = j.value("scene", "");
        if (!fileScene.empty() && sceneKey.find(fileScene) == std::string::npos) continue;
        out.push_back(std::move(j));
    }
    return out;
}

}  // namespace

std::vector<std::string> namedViews(const Scene& scene) {
    std::vector<std::string> names;
    for (auto& j : viewFilesFor(scene))
        for (auto& [name, v] : j["views"].items()) names.push_back(name);
    return names;
}

Camera resolveCamera(const Scene& scene, const Settings& s) {
    Camera c = scene.cameras.empty() ? defaultCamera(scene) : scene.cameras.front();
    const bool framed = c.name == "default";  // rtgi::defaultCamera: near/far are automatic
    if (!s.camera.view.empty()) {
        bool found = false;
        for (auto& j : viewFilesFor(scene)) {
            if (found || !j["views"].contains(s.camera.view)) continue;
            auto v = j["views"][s.camera.view];
            auto vec = [](const nlohmann::json& a) { return glm::vec3(a[0].get<float>(), a[1].get<float>(), a[2].get<float>()); };
            c.position = vec(v["position"]);
            c.target = vec(v["target"]);
            if (v.contains("fov")) c.fovY = glm::radians(v["fov"].get<float>());
            c.name = s.camera.view;
            found = true;
        }
        if (!found)
            throw ConfigError("setting 'view': no view named '" + s.camera.view + "' for scene " + scene.name +
                              " in benchmarks/views/");
    }
    if (s.camera.position) c.position = *s.camera.position;
    if (s.camera.target) c.target = *s.camera.target;
    if (s.camera.fovDeg) c.fovY = glm::radians(*s.camera.fovDeg);
    if (framed && !s.camera.farPlane) {
        // The framed camera's far plane covers the framed bounds from where the
        // camera stood; a named view or a moved camera (and a floor ten times
        // wider than the model it carries, rtgi::mergeScenes) needs the farthest
        // corner of the whole scene from where it stands now, or the floor's far
        // part renders as sky.
        Aabb b = scene.bounds();
        float reach = 0.0f;
        for (int i = 0; i < 8; ++i) {
            glm::vec3 corner((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
            reach = std::max(reach, glm::length(corner - c.position));
        }
        c.far = std::max(c.far, 1.01f * reach);
    }
    if (s.camera.nearPlane) c.near = *s.camera.nearPlane;
    if (s.camera.farPlane) c.far = *s.camera.farPlane;
    // Named with the scene: the camera may be the file's (a node far from the
    // origin leaves no float between position and target) or the settings'.
    const std::string which = "camera '" + c.name + "' of " + scene.name;
    if (!(c.far > c.near)) throw ConfigError(which + ": far plane must lie beyond the near plane");
    if (glm::length(c.target - c.position) <= 0.0f)
        throw ConfigError(which + ": position and target coincide (in float)");
    return c;
}

std::vector<Material> resolveMaterials(const Scene& scene, const Settings& s) {
    std::vector<Material> mats = scene.materials;
    for (auto& m : mats) m.emissive *= s.light.emissiveScale;
    if (s.floorRoughness && !scene.draws.empty()) {
        // The material of the lowest upward-facing triangle is the floor.
        float lowest = 1e30f;
        int floorMat = -1;
        for (auto& d : scene.draws)
            for (std::uint32_t t = 0; t < d.indexCount; t += 3) {
                const Vertex& a = scene.vertices[scene.indices[d.firstIndex + t]];
                if (a.normal.y > 0.9f && a.position.y < lowest) {
                    lowest = a.position.y;
                    floorMat = d.material;
                }
            }
        if (floorMat >= 0) mats[std::size_t(floorMat)].roughness = *s.floorRoughness;
    }
    return mats;
}

namespace {

// Bilinear resample of an RGBA8 image to size x size (for the texture array).
std::vector<std::uint8_t> resample(const Image& img, int size) {
    std::vector<std::uint8_t> out(std::size_t(size * size * 4));
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            float fx = (x + 0.5f) * img.width / size - 0.5f, fy = (y + 0.5f) * img.height / size - 0.5f;
            int x0 = std::clamp(int(std::floor(fx)), 0, img.width - 1), y0 = std::clamp(int(std::floor(fy)), 0, img.height - 1);
            int x1 = std::min(x0 + 1, img.width - 1), y1 = std::min(y0 + 1, img.height - 1);
            float tx = std::clamp(fx - x0, 0.0f, 1.0f), ty = std::clamp(fy - y0, 0.0f, 1.0f);
            for (int c = 0; c < 4; ++c) {
                auto at = [&](int xx, int yy) { return float(img.rgba[std::size_t((yy * img.width + xx) * 4 + c)]); };
                float v = (at(x0, y0) * (1 - tx) + at(x1, y0) * tx) * (1 - ty) + (at(x0, y1) * (1 - tx) + at(x1, y1) * tx) * ty;
                out[std::size_t((y * size + x) * 4 + c)] = std::uint8_t(std::clamp(v + 0.5f, 0.0f, 255.0f));
            }
        }
    return out;
}

}  // namespace

namespace {

// The vertex buffer's contents (positions and normals of the scene's current state).
std::vector<GpuVertex> gpuVertices(const Scene& scene) {
    std::vector<GpuVertex> verts(scene.vertices.size());
    for (std::size_t i = 0; i < verts.size(); ++i) {
        const Vertex& v = scene.vertices[i];
        verts[i] = {{v.position.x, v.position.y, v.position.z}, {v.normal.x, v.normal.y, v.normal.z}, {v.uv.x, v.uv.y}, 0};
    }
    // Vertices are never shared between primitives (the loaders flatten each
    // primitive into its own range), so the material can live per vertex.
    for (auto& d : scene.draws)
        for (std::uint32_t k = 0; k < d.indexCount; ++k) verts[scene.indices[d.firstIndex + k]].material = std::uint32_t(d.material);
    return verts;
}

// The reference's punctual lights (the real-time path has its own list, render/lights.h).
std::vector<gpu::GpuLight> gpuLights(const Scene& scene) {
    std::vector<gpu::GpuLight> gls;
    for (auto& l : scene.lights) {
        if (l.type == LightType::Directional) continue;
        gpu::GpuLight g{};
        g.positionRange = glm::vec4(l.position, l.range);
        g.colorIntensity = glm::vec4(l.color * l.intensity, 0);
        glm::vec3 dir = glm::length(l.direction) > 0 ? glm::normalize(l.direction) : glm::vec3(0, -1, 0);
        g.directionType = glm::vec4(dir, l.type == LightType::Point ? RTGI_LIGHT_POINT : RTGI_LIGHT_SPOT);
        g.cone = glm::vec4(std::cos(l.innerCone), std::cos(l.outerCone), -1, 0);  // the reference has no shadow maps
        gls.push_back(g);
    }
    return gls;
}

}  // namespace

GpuScene::GpuScene(gl::MemoryLedger& ledger, const Scene& scene, const Settings& settings, bool restPose)
    : ledger_(&ledger), rigid_(restPose) {
    std::vector<GpuVertex> verts = gpuVertices(scene);
    // Dynamic storage: a moving scene rewrites it (updateVertices, setTransforms).
    vbo_ = gl::Buffer(ledger, "scene.vertices", std::int64_t(verts.size() * sizeof(GpuVertex)), verts.data(),
                      GL_DYNAMIC_STORAGE_BIT);
    // Only indices of kept draws (validateAndRepair may have dropped some).
    std::vector<std::uint32_t> idx;
    for (auto& d : scene.draws)
        idx.insert(idx.end(), scene.indices.begin() + d.firstIndex, scene.indices.begin() + d.firstIndex + d.indexCount);
    indexCount_ = int(idx.size());
    ibo_ = gl::Buffer(ledger, "scene.indices", std::int64_t(idx.size() * 4), idx.data(), 0);

    GLuint vao = 0;
    glCreateVertexArrays(1, &vao);
    vao_ = gl::VertexArrayHandle(vao);
    vao_.label("scene.vao");
    glVertexArrayVertexBuffer(vao, 0, vbo_.id(), 0, sizeof(GpuVertex));
    glVertexArrayElementBuffer(vao, ibo_.id());
    auto attrib = [&](GLuint loc, int n, GLenum type, std::size_t off) {
        glEnableVertexArrayAttrib(vao, loc);
        if (type == GL_UNSIGNED_INT)
            glVertexArrayAttribIFormat(vao, loc, n, type, GLuint(off));
        else
            glVertexArrayAttribFormat(vao, loc, n, type, GL_FALSE, GLuint(off));
        glVertexArrayAttribBinding(vao, loc, 0);
    };
    attrib(RTGI_ATTR_POSITION, 3, GL_FLOAT, offsetof(GpuVertex, position));
    attrib(RTGI_ATTR_NORMAL, 3, GL_FLOAT, offsetof(GpuVertex, normal));
    attrib(RTGI_ATTR_UV, 2, GL_FLOAT, offsetof(GpuVertex, uv));
    attrib(RTGI_ATTR_MATERIAL, 1, GL_UNSIGNED_INT, offsetof(GpuVertex, material));
    // The previous frame's position: its own buffer binding (beginFrame).
    glVertexArrayVertexBuffer(vao, 1, vbo_.id(), 0, sizeof(GpuVertex));
    glEnableVertexArrayAttrib(vao, RTGI_ATTR_PREV_POSITION);
    glVertexArrayAttribFormat(vao, RTGI_ATTR_PREV_POSITION, 3, GL_FLOAT, GL_FALSE, GLuint(offsetof(GpuVertex, position)));
    glVertexArrayAttribBinding(vao, RTGI_ATTR_PREV_POSITION, 1);

    std::vector<Material> mats = resolveMaterials(scene, settings);
    std::vector<gpu::GpuMaterial> gm;
    for (auto& m : mats)
        gm.push_back({m.baseColor, glm::vec4(m.emissive, m.doubleSided ? 1.0f : 0.0f), glm::vec4(m.roughness, m.metallic, float(m.baseColorTexture), 0)});
    if (gm.empty()) gm.push_back({});
    materialCount_ = int(mats.size());
    materials_ = gl::Buffer(ledger, "scene.materials", std::int64_t(gm.size() * sizeof(gpu::GpuMaterial)), gm.data(), 0);

    std::vector<gpu::GpuLight> gls = gpuLights(scene);
    lightCount_ = int(gls.size());
    if (gls.empty()) gls.push_back({});
    lights_ = gl::Buffer(ledger, "scene.lights", std::int64_t(gls.size() * sizeof(gpu::GpuLight)), gls.data(),
                         GL_DYNAMIC_STORAGE_BIT);

    // Base-colour textures: one 2D array at a common size (at least one layer
    // so the sampler is always complete).
    // Without images a 1x1 white layer keeps the sampler complete (never sampled:
    // every material's texture layer is -1).
    const int size = scene.images.empty() ? 1 : 512;
    int layers = std::max<int>(1, int(scene.images.size()));
    int levels = 1 + int(std::log2(size));
    textures_ = gl::Texture(ledger, "scene.textures", {GL_TEXTURE_2D_ARRAY, GL_SRGB8_ALPHA8, size, size, layers, levels});
    for (int i = 0; i < int(scene.images.size()); ++i) {
        auto px = resample(scene.images[std::size_t(i)], size);
        glTextureSubImage3D(textures_.id(), 0, 0, 0, i, size, size, 1, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
    }
    if (scene.images.empty()) {
        std::vector<std::uint8_t> white(std::size_t(size * size * 4), 255);
        glTextureSubImage3D(textures_.id(), 0, 0, 0, 0, size, size, 1, GL_RGBA, GL_UNSIGNED_BYTE, white.data());
    }
    glGenerateTextureMipmap(textures_.id());
    textures_.setSampling(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR, GL_REPEAT);
}

void GpuScene::copyToPrevious() {
    if (!prevVbo_) prevVbo_ = gl::Buffer(*ledger_, "scene.prev_vertices", vbo_.size(), nullptr, 0);
    glCopyNamedBufferSubData(vbo_.id(), prevVbo_.id(), 0, 0, vbo_.size());
    prevRigid_ = rigid_;
}

void GpuScene::uploadVertices(const std::vector<GpuVertex>& verts) {
    // A new buffer holding the data, copied on the GPU, not glNamedBufferSubData
    // into the vertex buffer: on NVIDIA (driver 580.159.04, H200) an update
    // made before the first frame was undone by that frame (the buffer held
    // the pose it was created with again, so the next frame's previous
    // positions were wrong), with a glFinish, any barrier or
    // glInvalidateBufferData around the update too; a staging copy was not
    // (docs/temporal.md, "Object motion in the velocity").
    gl::Buffer staging(*ledger_, "scene.vertices.staging", vbo_.size(), verts.data(), 0);
    glCopyNamedBufferSubData(staging.id(), vbo_.id(), 0, 0, vbo_.size());
    uploadedBytes_ += vbo_.size();
}

void GpuScene::updateVertices(const Scene& scene) {
    std::vector<GpuVertex> verts = gpuVertices(scene);
    if (std::int64_t(verts.size() * sizeof(GpuVertex)) != vbo_.size())
        throw std::logic_error("GpuScene::updateVertices: the vertex count changed");
    // The first rewrite since a rendered frame keeps that frame's geometry
    // (a GPU copy, ordered before the upload): later rewrites before the next
    // frame replace states that were never rendered. A transform state still
    // waiting for its dispatch to write the previous positions left the
    // vertex buffer as the last frame rendered it: copied the same way.
    if ((rendered_ && geometryVersion_ == renderedVersion_) || writePrevious_ || copyPrevious_) copyToPrevious();
    transformPending_ = writePrevious_ = copyPrevious_ = false;  // this upload replaces the pending state
    uploadVertices(verts);
    rigid_ = false;
    ++geometryVersion_;
    ++stateVersion_;
}

bool GpuScene::registerObjects(const Scene& scene, const std::vector<Vertex>& rest) {
    const std::size_t n = std::size_t(vbo_.size()) / sizeof(GpuVertex);
    // A state without motions is the rest pose (the caller checked): every object at the identity.
    if ((scene.motions.empty() && objects_.empty()) || rest.size() != n || scene.vertices.size() != n) return false;
    std::vector<const RigidMotion*> fresh;
    for (auto& m : scene.motions) {
        for (auto [first, count] : m.ranges)
            if (first > n || count > n - first) return false;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!std::isfinite(m.delta[c][r])) return false;
        if (objects_.count(m.ranges)) continue;
        bool seen = false;
        for (auto* f : fresh) seen = seen || f->ranges == m.ranges;
        if (!seen) fresh.push_back(&m);
    }
    if (fresh.empty()) return true;
    // A vertex belongs to one object: a new object overlapping another one
    // (two motions of one state on shared vertices) goes by re-upload.
    if (owner_.empty()) owner_.assign(n, -1);
    std::vector<std::uint32_t> marked;
    int id = int(objects_.size());
    for (auto* f : fresh) {
        for (auto [first, count] : f->ranges)
            for (std::uint32_t v = first; v < first + count; ++v) {
                if (owner_[v] != -1) {
                    for (std::uint32_t u : marked) owner_[u] = -1;
                    return false;
                }
                owner_[v] = id;
                marked.push_back(v);
            }
        ++id;
    }
    // The object-space (rest) vertices of the new objects, appended; uploaded once.
    std::vector<gpu::MovableVertex> added;
    added.reserve(marked.size());
    for (std::uint32_t v : marked) {
        const Vertex& r = rest[v];
        std::uint32_t obj = std::uint32_t(owner_[v]);
        float vf, of;
        std::memcpy(&vf, &v, 4);
        std::memcpy(&of, &obj, 4);
        added.push_back({glm::vec4(r.position, vf), glm::vec4(r.normal, of)});
    }
    const std::int64_t oldBytes = std::int64_t(movableCount_) * std::int64_t(sizeof(gpu::MovableVertex));
    const std::int64_t addBytes = std::int64_t(added.size() * sizeof(gpu::MovableVertex));
    gl::Buffer grown(*ledger_, "scene.movable_vertices", std::max<std::int64_t>(oldBytes + addBytes, 16), nullptr,
                     GL_DYNAMIC_STORAGE_BIT);
    if (oldBytes > 0) glCopyNamedBufferSubData(movable_.id(), grown.id(), 0, 0, oldBytes);
    if (addBytes > 0) grown.upload(added.data(), addBytes, oldBytes);
    uploadedBytes_ += addBytes;
    movable_ = std::move(grown);
    movableCount_ += std::uint32_t(added.size());
    for (auto* f : fresh) objects_.emplace(f->ranges, int(objects_.size()));
    return true;
}

void GpuScene::uploadTransforms() {
    std::vector<gpu::ObjectTransform> t(objectMatrices_.size());
    for (std::size_t o = 0; o < t.size(); ++o) {
        const glm::dmat4 &m = objectMatrices_[o], &p = renderedMatrices_[o];
        const glm::dmat3 nm = glm::transpose(glm::inverse(glm::dmat3(m)));
        for (int r = 0; r < 3; ++r) {
            t[o].current[r] = glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]);
            t[o].normal[r] = glm::vec4(nm[0][r], nm[1][r], nm[2][r], 0.0);
            t[o].previous[r] = glm::vec4(p[0][r], p[1][r], p[2][r], p[3][r]);
        }
    }
    const std::int64_t bytes = std::int64_t(t.size() * sizeof(gpu::ObjectTransform));
    if (transforms_.size() < bytes)
        transforms_ = gl::Buffer(*ledger_, "scene.transforms", bytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    transforms_.upload(t.data(), bytes);
    uploadedBytes_ += bytes;
}

bool GpuScene::setTransforms(const Scene& scene, const std::vector<Vertex>& rest) {
    if (!registerObjects(scene, rest)) return false;
    const std::size_t count = objects_.size();
    std::vector<glm::dmat4> m(count, glm::dmat4(1.0));  // objects not in this state are at rest
    for (auto& motion : scene.motions) m[std::size_t(objects_.at(motion.ranges))] = motion.delta;  // a later one wins
    // New objects stood at rest in the last rendered frame when it was a
    // transform state (the vertex buffer held the rest pose outside the objects).
    renderedMatrices_.resize(count, glm::dmat4(1.0));
    if (rendered_ && geometryVersion_ == renderedVersion_) {
        // The first change since a rendered frame: the previous positions of
        // the objects from that frame's matrices when the previous-vertex
        // buffer holds the rest pose elsewhere, else a copy of that frame's
        // geometry (the vertex buffer is unchanged until the dispatch).
        // The copy of a rigid buffer is a dispatch before the transform's
        // (applyTransforms: a buffer copy was not ordered before the
        // transform's stores on NVIDIA); a direct rewrite is copied now,
        // before the rest pose is uploaded over it below.
        if (rigid_ && prevRigid_ && prevVbo_) writePrevious_ = true;
        else if (rigid_) {
            if (!prevVbo_) prevVbo_ = gl::Buffer(*ledger_, "scene.prev_vertices", vbo_.size(), nullptr, 0);
            copyPrevious_ = true;
            prevRigid_ = true;
        } else copyToPrevious();
    }
    if (!rigid_) {  // a direct rewrite is in the buffer: back to rest + objects once
        uploadVertices(gpuVertices(scene));
        rigid_ = true;
    }
    objectMatrices_ = std::move(m);
    uploadTransforms();
    transformPending_ = true;
    ++geometryVersion_;
    ++stateVersion_;
    return true;
}

void GpuScene::applyTransforms(gl::ProgramCache& programs) {
    if (!transformPending_) return;
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SCENE_SSBO_VERTICES, vbo_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SCENE_SSBO_PREV_VERTICES, (prevVbo_ ? prevVbo_ : vbo_).id());
    if (copyPrevious_) {  // the last rendered frame's geometry first (setTransforms)
        const gl::Program& c = programs.compute("scene/transform.comp", {{"RTGI_SCENE_COPY", "1"}});
        const auto vertices = unsigned(vbo_.size() / std::int64_t(sizeof(GpuVertex)));
        c.set(RTGI_SCENE_LOC_COUNT, vertices);
        gl::dispatch(c, int(vertices));
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        copyPrevious_ = false;
    }
    const gl::Program& p = programs.compute("scene/transform.comp");
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SCENE_SSBO_MOVABLE, movable_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SCENE_SSBO_TRANSFORMS, transforms_.id());
    p.set(RTGI_SCENE_LOC_COUNT, unsigned(movableCount_));
    p.set(RTGI_SCENE_LOC_WRITE_PREVIOUS, writePrevious_ && prevVbo_ ? 1 : 0);
    gl::dispatch(p, int(movableCount_));
    // Read next as vertex attributes (hardware raster), storage (compute
    // raster, reference) and by buffer copies (the next previous-frame copy).
    glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    transformPending_ = writePrevious_ = false;
}

void GpuScene::updateLights(const Scene& scene) {
    std::vector<gpu::GpuLight> gls = gpuLights(scene);
    if (int(gls.size()) != lightCount_) throw std::logic_error("GpuScene::updateLights: the light count changed");
    if (!gls.empty()) lights_.upload(gls.data(), std::int64_t(gls.size() * sizeof(gpu::GpuLight)));
    uploadedBytes_ += std::int64_t(gls.size() * sizeof(gpu::GpuLight));
    ++stateVersion_;  // also when only the sun changed (it lives in the frame uniforms)
}

void GpuScene::beginFrame() {
    prevDistinct_ = rendered_ && geometryVersion_ != renderedVersion_;
    glVertexArrayVertexBuffer(vao_.id(), 1, previousVertices().id(), 0, sizeof(GpuVertex));
}

void GpuScene::endFrame() {
    rendered_ = true;
    renderedVersion_ = geometryVersion_;
    renderedMatrices_ = objectMatrices_;
}

void GpuScene::draw() const {
    glBindVertexArray(vao_.id());
    glDrawElements(GL_TRIANGLES, indexCount_, GL_UNSIGNED_INT, nullptr);
}

void GpuScene::bindTables() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_MATERIALS, materials_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_LIGHTS, lights_.id());
    glBindTextureUnit(RTGI_TEX_MATERIALS, textures_.id());
}

}  // namespace rtgi
