#include "render/lpv/lpv_math.h"

#include <algorithm>
#include <cmath>

namespace rtgi::lpv {

namespace {
// The min corner of a camera-following volume: down to whole cells (snap), or as it is.
void snapOrigin(Placement& p, glm::vec3 corner, bool snap) {
    glm::vec3 lo = glm::floor(corner / p.cell);
    p.originCells = glm::ivec3(lo);
    p.origin = snap ? lo * p.cell : corner;
    p.snapped = snap;
}
}  // namespace

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
    snapOrigin(p, centre - 0.5f * extent, s.snap);
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
        snapOrigin(p, centre - 0.5f * extent, s.snap);
        out.push_back(p);
    }
    return out;
}

double cascadeNearWeight(int step, int iterations) {
    double t = 0.5 * double(iterations + 1);
    return 1.0 - std::clamp(double(step) + 1.0 - t, 0.0, 1.0);
}

namespace {
constexpr double kPi = 3.14159265358979323846;
const glm::dvec3 kAxes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
Sh9 scaled(Sh9 c, double s) {
    for (double& v : c) v *= s;
    return c;
}
void addScaled(Sh9& dst, const Sh9& c, double s) {
    for (std::size_t k = 0; k < 9; ++k) dst[k] += s * c[k];
}
glm::dvec3 sideDirection(glm::dvec3 t, glm::dvec3 d) { return RTGI_LPV_SIDE_DIR_T * t + RTGI_LPV_SIDE_DIR_D * d; }
}  // namespace

Sh9 shBasis9(glm::dvec3 d) {
    const double y0 = RTGI_SH_Y00, y1 = RTGI_SH_Y1, y2 = RTGI_SH_Y2;
    return {y0,
            -y1 * d.y,
            y1 * d.z,
            -y1 * d.x,
            y2 * d.x * d.y,
            -y2 * d.y * d.z,
            RTGI_SH_Y20 * (3.0 * d.z * d.z - 1.0),
            -y2 * d.x * d.z,
            RTGI_SH_Y22 * (d.x * d.x - d.y * d.y)};
}

Sh9 shCosineLobe9(glm::dvec3 n) {
    Sh9 c = scaled(shBasis9(n), RTGI_SH_COS_A2);
    c[0] = RTGI_SH_COS_C0;
    c[1] = -RTGI_SH_COS_C1 * n.y;
    c[2] = RTGI_SH_COS_C1 * n.z;
    c[3] = -RTGI_SH_COS_C1 * n.x;
    return c;
}

double shDot9(const Sh9& a, const Sh9& b) {
    double s = 0.0;
    for (std::size_t k = 0; k < 9; ++k) s += a[k] * b[k];
    return s;
}

Sh9 shTruncate(const Sh9& c, int order) {
    Sh9 t = c;
    if (order < 2)
        for (std::size_t k = 4; k < 9; ++k) t[k] = 0.0;
    return t;
}

double faceTransfer(const Sh9& I, glm::dvec3 d, double transmit, bool flow, int order, Sh9& dst) {
    double front = RTGI_LPV_FRONT_SOLID_ANGLE * std::max(0.0, shDot9(I, shBasis9(d)));
    double total = front;
    addScaled(dst, shTruncate(shCosineLobe9(d), order), front * transmit / kPi);
    for (const glm::dvec3& t : kAxes) {
        if (glm::dot(t, d) != 0.0) continue;
        glm::dvec3 w = sideDirection(t, d);
        double side = RTGI_LPV_SIDE_SOLID_ANGLE * std::max(0.0, shDot9(I, shBasis9(w)));
        total += side;
        addScaled(dst, shTruncate(shCosineLobe9(flow ? w : t), order), side * transmit / kPi);
    }
    return total;
}

double quadratureFlux(const Sh9& I) {
    double q = 0.0;
    for (const glm::dvec3& d : kAxes) {
        q += RTGI_LPV_FRONT_SOLID_ANGLE * std::max(0.0, shDot9(I, shBasis9(d)));
        for (const glm::dvec3& t : kAxes)
            if (glm::dot(t, d) == 0.0) q += RTGI_LPV_SIDE_SOLID_ANGLE * std::max(0.0, shDot9(I, shBasis9(sideDirection(t, d))));
    }
    return q;
}

double conservingScale(const Sh9& I) {
    double q = quadratureFlux(I);
    return q > 0.0 ? std::max(I[0], 0.0) / RTGI_SH_Y00 / q : 0.0;
}

int cascadeSteps(const LpvSettings& s, int cascade, int count) {
    return count > 1 && cascade == count - 1 && s.coarseIterations > 0 ? s.coarseIterations : s.iterations;
}

glm::dvec2 planeSelfIrradiance(int iterations, bool flow, bool conserving, int order, int nearIterations) {
    if (nearIterations <= 0) nearIterations = iterations;
    // Layer j holds the cells j + 1/2 cells above the plane (the injection offset puts
    // the plane's light into layer 0); the plane is uniform, so the 4 lateral neighbours
    // of a cell hold what the cell holds. Unit cells, M = 1: layer 0 starts at (1/pi) cosLobe(up).
    const int layers = iterations + 2;  // light moves one layer per step
    const glm::dvec3 up(0, 1, 0);
    std::vector<Sh9> cur(std::size_t(layers), Sh9{});
    cur[0] = shTruncate(shCosineLobe9(up), order);
    for (double& v : cur[0]) v /= kPi;
    const Sh9 down = shTruncate(shCosineLobe9(-up), order);
    auto receive = [&](const Sh9& i) { return shDot9(i, down); };  // <mirror(I), cosLobe(n)>
    double total = receive(cur[0]) * 1.0, near = receive(cur[0]) * cascadeNearWeight(0, nearIterations);
    for (int k = 1; k <= iterations; ++k) {
        std::vector<Sh9> next(cur.size(), Sh9{});
        for (int j = 0; j < layers; ++j)
            for (const glm::dvec3& a : kAxes) {
                int nb = j + int(a.y);
                if (nb < 0 || nb >= layers) continue;
                Sh9 in = cur[std::size_t(nb)];
                if (conserving) in = scaled(in, conservingScale(in));  // as lpvConservingScale
                faceTransfer(in, -a, 1.0, flow, order, next[std::size_t(j)]);
            }
        cur = std::move(next);
        total += receive(cur[0]);
        near += receive(cur[0]) * cascadeNearWeight(k, nearIterations);
    }
    return {total, near};
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
           cur.snapped == prev.snapped && (!(cur.fitted || !cur.snapped) || cur.origin == prev.origin);
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
    glm::dvec2 self = s.selfCorrection ? planeSelfIrradiance(cascadeSteps(s, in.cascade, count),
                                                             s.reemit == LpvSettings::Reemit::Flow, s.energyConserving,
                                                             s.shOrder, s.iterations)
                                       : glm::dvec2(0.0);
    u.cascadeParams = glm::vec4(kCascadeBlendCells, float(self.x), float(self.y), s.selfCorrection ? 1.0f : 0.0f);
    u.leak = glm::ivec4(s.injectSide == LpvSettings::InjectSide::Front, s.firstStepBlocked,
                        s.blocking == LpvSettings::Blocking::TwoSided, s.reflect == LpvSettings::Reflect::Source);
    for (int i = 0; i < RTGI_LPV_MAX_CASCADES; ++i) {
        const Placement& p = in.cascades.empty() ? in.placement : in.cascades[std::size_t(std::min(i, count - 1))];
        u.cascadeOrigin[i] = glm::vec4(p.origin, p.cell);
    }
    return u;
}

}  // namespace rtgi::lpv
