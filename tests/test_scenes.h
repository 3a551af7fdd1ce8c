#pragma once
// Scene-building helpers shared by the unit and GPU test tiers (no GL).
#include "scene/scene.h"

#include <glm/glm.hpp>

#include <cstdint>

namespace rtgi::test {

// Appends a quad (two triangles) with corners a, b, c, d (counter-clockwise
// seen from the side the normal points to) and material m.
inline void addQuad(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, int m) {
    glm::vec3 n = glm::normalize(glm::cross(b - a, d - a));
    auto base = std::uint32_t(s.vertices.size());
    for (auto p : {a, b, c, d}) s.vertices.push_back({p, n, {0, 0}});
    DrawRange r{std::uint32_t(s.indices.size()), 6, m};
    for (auto i : {0u, 1u, 2u, 0u, 2u, 3u}) s.indices.push_back(base + i);
    s.draws.push_back(r);
}

}  // namespace rtgi::test
