#include "render/lpv/lpv_math.h"

#include <algorithm>
#include <cmath>

namespace rtgi::lpv {

Placement placeVolume(const LpvSettings& s, const Aabb& sceneBounds, glm::vec3 cameraPos, glm::vec3 cameraForward) {
    Placement p;
    p.grid = glm::max(s.grid, glm::ivec3(1));
    glm::vec3 g(p.grid);
    if (s.cell <= 0.0f) {
        p.fitted = true;
        glm::vec3 ext = sceneBounds.empty() ? glm::vec3(1.0f) : sceneBounds.extent();
        float cell = std::max({ext.x / g.x, ext.y / g.y, ext.z / g.z});
        // A flat or point-like scene still needs a finite cell; 1e-3 of the
        // largest extent keeps the margin below relative to the scene scale.
        p.cell = cell > 0.0f ? cell * (1.0f + 1e-3f) : 1.0f;
        glm::vec3 c = sceneBounds.empty() ? glm::vec3(0.0f) : sceneBounds.center();
        p.origin = c - 0.5f * g * p.cell;
        return p;
    }
    p.cell = s.cell;
    glm::vec3 f = glm::length(cameraForward) > 0.0f ? glm::normalize(cameraForward) : glm::vec3(0, 0, -1);
    glm::vec3 extent = g * p.cell;
    glm::vec3 centre = cameraPos + 0.3f * f * extent;
    glm::vec3 lo = glm::floor((centre - 0.5f * extent) / p.cell);
    p.originCells = glm::ivec3(lo);
    p.origin = lo * p.cell;
    return p;
}

double rsmTexelArea(const glm::mat4& m, int rsmSize) {
    // Rows 0/1 of an orthographic P*V scale light-space x/y by 2/width, 2/height.
    glm::dvec3 rx(m[0][0], m[1][0], m[2][0]), ry(m[0][1], m[1][1], m[2][1]);
    double w = 2.0 / glm::length(rx), h = 2.0 / glm::length(ry);
    return w * h / (double(rsmSize) * double(rsmSize));
}

glm::ivec3 temporalShift(const Placement& cur, const Placement& prev) { return cur.originCells - prev.originCells; }

bool historyCompatible(const Placement& cur, const Placement& prev) {
    return cur.grid == prev.grid && cur.cell == prev.cell && cur.fitted == prev.fitted &&
           (!cur.fitted || cur.origin == prev.origin);
}

gpu::LpvUniforms makeUniforms(const LpvSettings& s, const UniformInputs& in) {
    gpu::LpvUniforms u{};
    u.rsmViewProj = in.rsmViewProj;
    u.rsmInvViewProj = glm::inverse(in.rsmViewProj);
    u.origin = glm::vec4(in.placement.origin, in.placement.cell);
    u.grid = glm::ivec4(in.placement.grid, s.rsm);
    float cell = in.placement.cell;
    u.rsm = glm::vec4(float(rsmTexelArea(in.rsmViewProj, s.rsm)), 1.0f / (cell * cell), s.strength, kMinAreaCos);
    u.flags = glm::ivec4(s.occlusion, s.bounce, s.energyConserving, in.specular);
    u.temporalShift = glm::ivec4(in.shift, in.historyValid && s.temporal > 0.0f);
    u.temporal = glm::vec4(s.temporal, 0, 0, 0);
    return u;
}

}  // namespace rtgi::lpv
