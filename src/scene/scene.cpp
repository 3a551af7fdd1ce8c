#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rtgi {

Aabb Scene::bounds() const {
    Aabb b;
    for (auto& v : vertices) b.grow(v.position);
    return b;
}

Aabb Scene::focusBounds() const {
    if (groundVertices.empty()) return bounds();
    std::vector<char> ground(vertices.size(), 0);
    for (auto [first, end] : groundVertices)
        for (std::uint32_t i = first; i < end && i < vertices.size(); ++i) ground[i] = 1;
    Aabb rest;
    for (std::size_t i = 0; i < vertices.size(); ++i)
        if (!ground[i]) rest.grow(vertices[i].position);
    const Aabb all = bounds();
    if (rest.empty()) return all;
    const glm::vec3 e = rest.extent();
    const float margin = std::max({e.x, e.y, e.z});
    Aabb b;
    b.lo = glm::max(rest.lo - glm::vec3(margin), all.lo);
    b.hi = glm::min(rest.hi + glm::vec3(margin), all.hi);
    return b;
}

const Light* Scene::sun() const {
    for (auto& l : lights)
        if (l.type == LightType::Directional) return &l;
    return nullptr;
}

float Scene::minRoughness() const {
    float r = 1.0f;
    for (auto& d : draws) r = std::min(r, materials[std::size_t(d.material)].roughness);
    return r;
}

void Scene::merge(const Scene& o) {
    auto vOff = std::uint32_t(vertices.size());
    for (auto [first, end] : o.groundVertices) groundVertices.push_back({first + vOff, end + vOff});
    auto iOff = std::uint32_t(indices.size());
    int mOff = int(materials.size());
    int tOff = int(images.size());
    {  // the other scene's animated nodes, re-indexed into this one
        SceneAnimation a = o.animation;
        a.offset(vOff, int(lights.size()), int(cameras.size()));
        const int nOff = int(animation.nodes.size()), kOff = int(animation.tracks.size());
        for (auto& n : a.nodes) {
            if (n.parent >= 0) n.parent += nOff;
            for (int& k : n.track)
                if (k >= 0) k += kOff;
        }
        animation.nodes.insert(animation.nodes.end(), a.nodes.begin(), a.nodes.end());
        animation.tracks.insert(animation.tracks.end(), a.tracks.begin(), a.tracks.end());
    }
    vertices.insert(vertices.end(), o.vertices.begin(), o.vertices.end());
    for (auto i : o.indices) indices.push_back(i + vOff);
    for (auto d : o.draws) {
        d.firstIndex += iOff;
        d.material += mOff;
        draws.push_back(d);
    }
    for (auto m : o.materials) {
        if (m.baseColorTexture >= 0) m.baseColorTexture += tOff;
        materials.push_back(m);
    }
    images.insert(images.end(), o.images.begin(), o.images.end());
    lights.insert(lights.end(), o.lights.begin(), o.lights.end());
    cameras.insert(cameras.end(), o.cameras.begin(), o.cameras.end());
    sky = glm::max(sky, o.sky);
    warnings.insert(warnings.end(), o.warnings.begin(), o.warnings.end());
    suggestedSettings.insert(suggestedSettings.end(), o.suggestedSettings.begin(), o.suggestedSettings.end());
    name = name.empty() ? o.name : name + "+" + o.name;
}

Scene loadSceneSpec(const std::string& spec) {
    if (spec.rfind("builtin:", 0) == 0) return loadBuiltin(spec.substr(8));
    return loadGltf(spec);
}

void validateAndRepair(Scene& s, const std::string& source) {
    for (auto& v : s.vertices)
        if (!std::isfinite(v.position.x) || !std::isfinite(v.position.y) || !std::isfinite(v.position.z))
            throw SceneError(source + ": a vertex position is NaN or infinite");
    for (auto i : s.indices)
        if (i >= s.vertices.size())
            throw SceneError(source + ": index " + std::to_string(i) + " is out of range (" +
                             std::to_string(s.vertices.size()) + " vertices)");
    std::size_t fixedNormals = 0, dropped = 0;
    std::vector<std::uint32_t> kept;
    kept.reserve(s.indices.size());
    std::vector<DrawRange> draws;
    for (auto d : s.draws) {
        DrawRange nd = d;
        nd.firstIndex = std::uint32_t(kept.size());
        for (std::uint32_t t = 0; t + 2 < d.indexCount; t += 3) {
            std::uint32_t a = s.indices[d.firstIndex + t], b = s.indices[d.firstIndex + t + 1],
                          c = s.indices[d.firstIndex + t + 2];
            // In double: the float cross product overflows for edges beyond
            // ~4e9 (a valid triangle would be dropped as degenerate).
            glm::dvec3 pa(s.vertices[a].position), pb(s.vertices[b].position), pc(s.vertices[c].position);
            glm::dvec3 dn = glm::cross(pb - pa, pc - pa);
            double len = glm::length(dn);
            if (!(len > 0.0) || !std::isfinite(len)) {
                ++dropped;
                continue;
            }
            glm::vec3 n(dn / len);
            for (auto k : {a, b, c}) {
                glm::vec3& vn = s.vertices[k].normal;
                float l = glm::length(vn);
                if (!(l > 1e-12f) || !std::isfinite(l)) {
                    vn = n;
                    ++fixedNormals;
                } else if (std::abs(l - 1.0f) > 1e-3f) {
                    vn /= l;
                }
            }
            kept.insert(kept.end(), {a, b, c});
        }
        nd.indexCount = std::uint32_t(kept.size()) - nd.firstIndex;
        if (nd.indexCount > 0) draws.push_back(nd);
    }
    s.indices = std::move(kept);
    s.draws = std::move(draws);
    if (fixedNormals)
        s.warnings.push_back(source + ": replaced " + std::to_string(fixedNormals) +
                             " zero-length or non-finite normals by face normals");
    if (dropped)
        s.warnings.push_back(source + ": dropped " + std::to_string(dropped) + " degenerate triangles");
    if (s.indices.empty()) throw SceneError(source + ": the scene contains no triangles");
}

std::uint64_t sceneHostMemoryLimit() {
    // Half of MemAvailable (the scene exists twice: the loaded Scene and the
    // renderer's copy, plus the BVH); 8 GiB when /proc/meminfo says nothing.
    std::uint64_t limit = std::uint64_t(8) << 30;
    if (std::FILE* f = std::fopen("/proc/meminfo", "r")) {
        char line[256];
        while (std::fgets(line, sizeof line, f)) {
            unsigned long long kib = 0;
            if (std::sscanf(line, "MemAvailable: %llu kB", &kib) == 1) {
                limit = std::uint64_t(kib) * 1024 / 2;
                break;
            }
        }
        std::fclose(f);
    }
    return limit;
}

Camera defaultCamera(const Scene& s) {
    Camera c;
    Aabb b = s.bounds();
    glm::vec3 ctr = b.center();
    float radius = 0.5f * glm::length(b.extent());
    radius = std::max(radius, 1e-3f);
    c.fovY = glm::radians(50.0f);
    float dist = radius / std::sin(0.5f * c.fovY);
    glm::vec3 dir = glm::normalize(glm::vec3(0.35f, 0.45f, 1.0f));
    c.position = ctr + dir * dist;
    c.target = ctr;
    c.near = std::max(dist - radius, dist * 1e-3f) * 0.5f;
    c.near = std::min(c.near, radius * 0.05f);
    c.far = dist + 2.0f * radius;
    c.name = "default";
    return c;
}

}  // namespace rtgi
