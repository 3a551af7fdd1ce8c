// Visibility-bitmask AO (vbao, docs/ao.md "Visibility bitmask") against
// closed-form cosine-weighted visible solid angles, and against GTAO with
// infinite thickness: a CPU double implementation of the documented
// estimator and the GLSL library (lib/ao_estimators.glsl aoVbao / aoGtao) on
// analytic depth buffers.
//
// Both scenes are rotationally symmetric about the view axis and the
// receiver P sits on it (uv = centre, normal = V), so every slice sees the
// same 2D profile and the slice quadrature is exact: what remains is the
// estimator's march and its sector quantization.
//  - well: floor at depth Z0, a circular wall of radius rho and height H
//    around P (solid ground above, beyond the wall): visible fraction
//    sin^2(max(atan(rho/H), asin(rho/R))) (rays hit the wall below its rim
//    and within R). Any thickness > 0 gives it (the wall's columns reach the
//    floor's horizon), so constant, depth-scaled and infinite must agree.
//  - slab: a floating annulus whose front face (towards the camera) lies at
//    depth df = Z0 - h - T, inner/outer radii a, b there, extending T in
//    depth along the view rays (its sides are view rays: the depth buffer
//    holds only its front face and the floor, as a slab of known thickness
//    T seen by a depth buffer). From P it covers tan(theta) in
//    [a/(h+T), b (Z0-h)/(df h)]: visible 1 - (sin^2 t2 - sin^2 t1); with
//    infinite thickness (GTAO) everything below t1 is occluded: sin^2 t1.
#include "ao_test_util.h"
#include "gpu_fixture.h"

#include "gl/program.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

using namespace rtgi;
using namespace rtgi::test;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTanHalf = 0.57735026918962576;  // fovY 60 degrees
constexpr double kAspect = 1.5;
constexpr int kSectors = 32;

// Scene description shared with the GLSL side: kind 0 well (Z0, rho, H),
// kind 1 slab (Z0, h, T, a, b).
struct SceneDesc {
    int kind;
    double Z0, rho, H;  // well
    double h, T, a, b;  // slab
};

glm::dvec3 viewPos(glm::dvec2 uv, double d) {
    glm::dvec2 ndc = uv * 2.0 - 1.0;
    return {ndc.x * kTanHalf * kAspect * d, ndc.y * kTanHalf * d, -d};
}

// Linear depth of the first surface along the camera ray through uv.
double sceneDepth(const SceneDesc& s, glm::dvec2 uv) {
    glm::dvec3 r = viewPos(uv, 1.0);
    double rxy = std::sqrt(r.x * r.x + r.y * r.y);
    if (s.kind == 0) {
        double rim = s.Z0 - s.H;
        if (rim * rxy >= s.rho) return rim;                // ground above, beyond the wall
        double tWall = rxy > 0 ? s.rho / rxy : 1e30;         // the wall's inside
        return std::min(tWall, s.Z0);
    }
    double df = s.Z0 - s.h - s.T;
    double rf = df * rxy;
    return (rf >= s.a && rf <= s.b) ? df : s.Z0;
}

double closedForm(const SceneDesc& s, double R, bool infinite) {
    auto sin2 = [](double t) { return t * t / (1 + t * t); };  // sin^2 of atan(t)
    if (s.kind == 0) {
        double t = std::max(std::atan(s.rho / s.H), std::asin(std::min(s.rho / R, 1.0)));
        return std::sin(t) * std::sin(t);
    }
    double df = s.Z0 - s.h - s.T;
    double t1 = s.a / (s.h + s.T), t2 = s.b * (s.Z0 - s.h) / (df * s.h);
    return infinite ? sin2(t1) : 1.0 - (sin2(t2) - sin2(t1));
}

// Cosine-weighted measure of the slice arc [lo, hi] (view angles, n the
// projected normal's angle): the integral of |sin t| cos(t - n), by Simpson's
// rule on each side of 0 (independent of the shader's closed form).
double arcMeasure(double lo, double hi, double n) {
    auto f = [n](double t) { return std::abs(std::sin(t)) * std::cos(t - n); };
    auto simpson = [&](double a, double b) {
        if (b <= a) return 0.0;
        const int m = 64;
        double h = (b - a) / m, sum = f(a) + f(b);
        for (int i = 1; i < m; ++i) sum += f(a + i * h) * (i % 2 ? 4 : 2);
        return sum * h / 3;
    };
    if (lo < 0 && hi > 0) return simpson(lo, 0) + simpson(0, hi);
    return simpson(lo, hi);
}

struct Estimate {
    double vbao, gtao;
};

// The documented estimators in double (docs/ao.md): slices k rotated by
// noise.x, steps jittered by noise.y, sector jitter noise.z; thickness < 0 =
// infinite. Returns vbao and gtao (hard cut at R) for P at uv with normal n.
Estimate estimateCpu(const SceneDesc& s, glm::dvec2 uv, glm::dvec3 n, double R, glm::dvec3 noise, int slices,
                     int steps, double thickness, bool depthScaled) {
    double d = sceneDepth(s, uv);
    glm::dvec3 P = viewPos(uv, d), V = glm::normalize(-P);
    double cot = 1.0 / kTanHalf;
    glm::dvec2 rUv = 0.5 * R * glm::dvec2(cot / kAspect, cot) / d;
    double visB = 0, visG = 0, open = 0;
    for (int k = 0; k < slices; ++k) {
        std::optional<AoSliceGeometry> sl = aoSliceGeometry(k, slices, noise.x, V, n);
        if (!sl) continue;
        const glm::dvec3 dir = sl->dir;
        const double projLen = sl->projLen, nAngle = sl->nAngle;
        double lo = nAngle - kPi / 2, hi = nAngle + kPi / 2;
        bool occluded[kSectors] = {};
        double horizon[2] = {lo, hi};  // gtao: the visible arc [side-1 horizon, side-0 horizon]
        for (int j = 0; j < steps; ++j) {
            glm::dvec2 off = glm::dvec2(dir) * rUv * ((j + noise.y) / steps);
            for (int side = 0; side < 2; ++side) {
                double sgn = side == 0 ? 1.0 : -1.0;
                glm::dvec2 uvS = uv + sgn * off;
                double zS = sceneDepth(s, uvS);
                glm::dvec3 S = viewPos(uvS, zS), D = S - P;
                double dist = glm::length(D);
                auto angle = [&](glm::dvec3 v) { return sgn * std::acos(std::clamp(glm::dot(glm::normalize(v), V), -1.0, 1.0)); };
                // gtao: the horizon of the samples within R.
                if (dist < R && dist > 1e-9) {
                    if (side == 0) horizon[1] = std::min(horizon[1], angle(D));
                    else horizon[0] = std::max(horizon[0], angle(D));
                }
                // vbao: the column S + t s, t in [0, T |S| / zS], clipped to |X - P| < R.
                double a0, a1;
                if (thickness < 0) {
                    if (!(dist < R && dist > 1e-9)) continue;
                    a0 = angle(D);
                    a1 = sgn * kPi;
                } else {
                    double T = depthScaled ? thickness * zS : thickness;
                    glm::dvec3 sh = glm::normalize(S);
                    double tMax = T * glm::length(S) / zS;
                    double b = glm::dot(D, sh), c = glm::dot(D, D) - R * R, disc = b * b - c;
                    if (disc <= 0) continue;
                    double t0 = std::max(-b - std::sqrt(disc), 0.0), t1 = std::min(-b + std::sqrt(disc), tMax);
                    if (!(t0 < t1)) continue;
                    a0 = angle(D + t0 * sh);
                    a1 = angle(D + t1 * sh);
                }
                double x0 = (std::min(a0, a1) - lo) / kPi, x1 = (std::max(a0, a1) - lo) / kPi;
                for (int q = 0; q < kSectors; ++q) {
                    double x = (q + noise.z) / kSectors;
                    if (x >= x0 && x <= x1) occluded[q] = true;
                }
            }
        }
        double full = arcMeasure(lo, hi, nAngle), occ = 0;
        for (int q = 0; q < kSectors; ++q)
            if (occluded[q]) occ += arcMeasure(lo + q * kPi / kSectors, lo + (q + 1) * kPi / kSectors, nAngle);
        visB += projLen * (full - occ);
        // gtao: visible between the side-1 horizon (horizon[0]) and the side-0 one (horizon[1]).
        visG += projLen * arcMeasure(horizon[0], horizon[1], nAngle);
        open += projLen * full;
    }
    return {visB / open, visG / open};
}

const char* kSource = R"(
// The near-field gather hooks (docs/ao.md "Bitmask near-field light"): every sender of
// radiance 1, so the gathered (1/pi) E over the slices' open measure is the occluded fraction.
#define AO_VBAO_GATHER 1
float gGather, gOpen;
void aoVbaoGather(vec2 uvS, vec3 S, float zS, float w) { gGather += w; }
void aoVbaoGatherOpen(float open) { gOpen += open; }
#include "lib/ao_estimators.glsl"
layout(local_size_x = 1) in;
// scene: x kind, y Z0, z rho | h, w H | T; extra: x a, y b; params: x R, y slices, z steps, w thickness (< 0 infinite)
struct Case { vec4 scene; vec4 extra; vec4 params; vec4 noise; };  // noise.w: depth-scaled
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Out { vec4 results[]; };

const float kTanHalf = 0.57735027;
const float kAspect = 1.5;
uint gCase;

float aoSceneDepth(vec2 uv) {
    Case c = cases[gCase];
    vec3 r = viewPositionFromDepth(uv, 1.0, kTanHalf, kAspect);
    float rxy = length(r.xy);
    if (c.scene.x < 0.5) {
        float rim = c.scene.y - c.scene.w;
        if (rim * rxy >= c.scene.z) return rim;
        return rxy > 0.0 ? min(c.scene.z / rxy, c.scene.y) : c.scene.y;
    }
    float df = c.scene.y - c.scene.z - c.scene.w;
    float rf = df * rxy;
    return (rf >= c.extra.x && rf <= c.extra.y) ? df : c.scene.y;
}
AoCamera camera() {
    float cot = 1.0 / kTanHalf;
    return AoCamera(vec2(cot / kAspect, cot), kTanHalf, kAspect, vec2(480.0, 320.0));
}
float aoPointOcclusion(vec3 P, vec3 S, float R) { return aoCameraPointOcclusion(camera(), P, S, R); }
vec3 aoKernel(int i) { return vec3(0.0); }
float aoSceneDepth2(vec2 uv) { return 0.0; }
vec4 aoVoSample(int i) { return vec4(0.0); }

void main() {
    gCase = gl_GlobalInvocationID.x;
    Case c = cases[gCase];
    vec2 uv = vec2(0.5);
    float d = aoSceneDepth(uv);
    vec3 P = viewPositionFromDepth(uv, d, kTanHalf, kAspect);
    vec3 n = vec3(0.0, 0.0, 1.0);
    AoCamera cam = camera();
    int slices = int(c.params.y), steps = int(c.params.z);
    gGather = 0.0;
    gOpen = 0.0;
    float vb = aoVbao(cam, uv, P, n, d, c.params.x, c.noise.xyz, slices, steps, c.params.w, c.noise.w > 0.5, false);
    float gt = aoGtao(cam, uv, P, n, d, c.params.x, c.noise.xy, slices, steps);
    results[gCase] = vec4(vb, gt, gOpen > 0.0 ? gGather / gOpen : -1.0, 0.0);
}
)";

struct GpuCase {
    glm::vec4 scene, extra, params, noise;
};

struct Config {
    const char* name;
    SceneDesc scene;
    double R;
    double thickness;  // < 0 infinite
    bool depthScaled;
};

std::vector<Config> configs() {
    SceneDesc well{0, 1.0, 0.3, 0.4, 0, 0, 0, 0};
    SceneDesc slab{1, 1.5, 0, 0, 0.4, 0.15, 0.25, 0.5};
    double df = slab.Z0 - slab.h - slab.T;
    return {
        {"well R 1 (rim) constant 0.2", well, 1.0, 0.2, false},
        {"well R 1 (rim) depth 0.07", well, 1.0, 0.07, true},
        {"well R 1 (rim) infinite", well, 1.0, -1.0, false},
        {"well R 0.45 (radius cut) constant 0.2", well, 0.45, 0.2, false},
        {"well R 0.45 (radius cut) infinite", well, 0.45, -1.0, false},
        {"slab constant T", slab, 1.0, slab.T, false},
        {"slab depth-scaled T/df", slab, 1.0, slab.T / df, true},
        {"slab infinite", slab, 1.0, -1.0, false},
    };
}

// 16 stratified jitters of (slice rotation, step offset, sector offset).
glm::dvec3 jitter(int i) { return {std::fmod(0.618034 * i + 0.1, 1.0), (i + 0.5) / 16.0, ((7 * i) % 16 + 0.5) / 16.0}; }

}  // namespace

TEST_CASE("vbao on analytic scenes: CPU double estimator vs closed-form visible solid angle; infinite thickness = GTAO") {
    // 4 slices (the scenes are symmetric) x 384 steps per side: the march
    // resolves the band edges to ~0.004; the sector quantization averages
    // out over the 16 stratified sector jitters (to ~0.006, 1/16 of a sector
    // per arc end).
    for (const Config& c : configs()) {
        double b = 0, g = 0;
        for (int i = 0; i < 16; ++i) {
            Estimate e = estimateCpu(c.scene, {0.5, 0.5}, {0, 0, 1}, c.R, jitter(i), 4, 384, c.thickness, c.depthScaled);
            b += e.vbao / 16;
            g += e.gtao / 16;
        }
        bool infinite = c.thickness < 0;
        double exact = closedForm(c.scene, c.R, infinite);
        double gtaoExact = closedForm(c.scene, c.R, true);
        MESSAGE(std::string(c.name) << ": vbao " << b << " gtao " << g << " closed form " << exact << " (infinite " << gtaoExact << ")");
        CHECK(std::abs(b - exact) < 0.01);
        CHECK(std::abs(g - gtaoExact) < 0.01);  // the horizon formula itself
        if (infinite) CHECK(std::abs(b - g) < 0.01);
    }
    // The slab separates the two definitions: the thickness lets the light
    // under the slab through (0.53 visible), GTAO's horizon closes it (0.17).
    auto all = configs();
    CHECK(closedForm(all[5].scene, 1.0, false) - closedForm(all[5].scene, 1.0, true) > 0.3);
}

TEST_CASE("vbao GLSL (lib/ao_estimators.glsl) on analytic depth buffers equals the CPU double estimator and the closed form") {
    GpuFixture gpu;
    std::vector<Config> cfg = configs();
    const int steps = 128, slices = 4;
    std::vector<GpuCase> cases;
    for (const Config& c : cfg)
        for (int i = 0; i < 16; ++i) {
            const SceneDesc& s = c.scene;
            glm::vec4 scene = s.kind == 0 ? glm::vec4(0, s.Z0, s.rho, s.H) : glm::vec4(1, s.Z0, s.h, s.T);
            glm::dvec3 j = jitter(i);
            cases.push_back({scene, {float(s.a), float(s.b), 0, 0}, {float(c.R), float(slices), float(steps), float(c.thickness)},
                             {float(j.x), float(j.y), float(j.z), c.depthScaled ? 1.0f : 0.0f}});
        }
    gl::MemoryLedger ledger;
    gl::Buffer bc(ledger, "test.cases", std::int64_t(cases.size() * sizeof(GpuCase)), cases.data());
    gl::Buffer out(ledger, "test.out", std::int64_t(cases.size() * sizeof(glm::vec4)));
    gl::ProgramCache cache;
    const gl::Program& p = cache.computeFromSource("test/ao_bitmask.comp", kSource);
    glUseProgram(p.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, bc.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    gl::dispatch(p, int(cases.size()));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> r(cases.size());
    out.download(r.data(), std::int64_t(r.size() * sizeof(glm::vec4)));
    for (std::size_t ci = 0; ci < cfg.size(); ++ci) {
        const Config& c = cfg[ci];
        double gpuB = 0, gpuG = 0, cpuB = 0, cpuG = 0, worst = 0, gather = 0;
        int far = 0;
        for (int i = 0; i < 16; ++i) {
            glm::vec4 v = r[ci * 16 + std::size_t(i)];
            // Near-field gather of unit radiance: each occluded sector counted once, at its first
            // sender (a sector counted again by a later sample would exceed 1 - visibility).
            CHECK(std::abs(v.z - (1.0 - v.x)) < 1e-5);
            gather += v.z / 16;
            // The CPU run with the float-rounded jitter the GPU saw.
            glm::vec4 jn = cases[ci * 16 + std::size_t(i)].noise;
            Estimate e = estimateCpu(c.scene, {0.5, 0.5}, {0, 0, 1}, c.R, glm::dvec3(jn), slices, steps, c.thickness, c.depthScaled);
            gpuB += v.x / 16, gpuG += v.y / 16, cpuB += e.vbao / 16, cpuG += e.gtao / 16;
            double dev = std::abs(v.x - e.vbao);
            worst = std::max(worst, dev);
            if (dev > 2e-3) ++far;  // a sector decided the other way by float rounding
        }
        double exact = closedForm(c.scene, c.R, c.thickness < 0);
        MESSAGE(std::string(c.name) << ": GPU vbao " << gpuB << " CPU " << cpuB << " (worst jitter " << worst << ", " << far
                    << " of 16 beyond 2e-3), GPU gtao " << gpuG << " CPU " << cpuG << ", closed form " << exact);
        CHECK(far <= 2);
        CHECK(std::abs(gpuB - cpuB) < 4e-3);
        CHECK(std::abs(gpuG - cpuG) < 2e-3);
        CHECK(std::abs(gpuB - exact) < 0.02);  // 128 steps: the band edges to ~half a step (CPU at 96: 0.015)
        CHECK(std::abs(gather - (1.0 - exact)) < 0.02);  // unit radiance: the occluded solid angle's cosine measure
        if (c.thickness < 0) CHECK(std::abs(gpuB - gpuG) < 0.01);
    }
}
