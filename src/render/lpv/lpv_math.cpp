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

std::vector<Placement> placeCascades(const LpvSettings& s, int cascades, const Aabb& bounds, glm::vec3 cameraPos,
                                     glm::vec3 cameraForward) {
    if (cascades <= 1) return {placeVolume(s, bounds, cameraPos, cameraForward)};
    glm::ivec3 grid = glm::max(s.grid, glm::ivec3(1));
    glm::vec3 g(grid);
    float cell0 = s.cell;
    if (cell0 <= 0.0f) {
        // Snapping moves the box down by less than a cell: the coarsest extent
        // g s >= bounds + 2 s holds the bounds wherever the snap lands.
        glm::vec3 ext = bounds.empty() ? glm::vec3(1.0f) : bounds.extent();
        glm::vec3 usable = glm::max(g - 2.0f, glm::vec3(1.0f));
        float coarsest = std::max({ext.x / usable.x, ext.y / usable.y, ext.z / usable.z});
        if (!(coarsest > 0.0f)) coarsest = 1.0f;
        cell0 = coarsest * (1.0f + 1e-3f) / float(1 << (cascades - 1));
    }
    glm::vec3 f = glm::length(cameraForward) > 0.0f ? glm::normalize(cameraForward) : glm::vec3(0, 0, -1);
    std::vector<Placement> out;
    for (int i = 0; i < cascades; ++i) {
        Placement p;
        p.grid = grid;
        p.cell = cell0 * float(1 << i);
        glm::vec3 extent = g * p.cell;
        glm::vec3 centre = cameraPos + 0.3f * f * extent;
        if (!bounds.empty())
            for (int a = 0; a < 3; ++a) {
                // No cells outside the scene where the cascade is smaller than it; centred where larger.
                float lo = bounds.lo[a] + 0.5f * extent[a], hi = bounds.hi[a] - 0.5f * extent[a];
                centre[a] = lo <= hi ? std::clamp(centre[a], lo, hi) : 0.5f * (bounds.lo[a] + bounds.hi[a]);
            }
        glm::vec3 lo = glm::floor((centre - 0.5f * extent) / p.cell);
        p.originCells = glm::ivec3(lo);
        p.origin = lo * p.cell;
        out.push_back(p);
    }
    return out;
}

double cascadeNearWeight(int step, int iterations) {
    double t = 0.5 * double(iterations + 1);
    return 1.0 - std::clamp(double(step) + 1.0 - t, 0.0, 1.0);
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
    int count = in.cascades.empty() ? 1 : int(in.cascades.size());
    u.cascade = glm::ivec4(in.cascade, count, in.cascade == count - 1, s.reemit == LpvSettings::Reemit::Flow);
    u.cascadeParams = glm::vec4(kCascadeBlendCells, 0, 0, 0);
    for (int i = 0; i < RTGI_LPV_MAX_CASCADES; ++i) {
        const Placement& p = in.cascades.empty() ? in.placement : in.cascades[std::size_t(std::min(i, count - 1))];
        u.cascadeOrigin[i] = glm::vec4(p.origin, p.cell);
    }
    return u;
}

}  // namespace rtgi::lpv
