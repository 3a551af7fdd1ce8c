// LPV light leaks through thin walls (issue 22; docs/lpv.md, "Leaks"):
// - the closed room of builtin:leak, whose exact interior light is 0, against the LPV's light
//   on the sunlit outside wall, with the default remedies;
// - the geometry-aware lookup weights (compute/lib/lpv_lookup.glsl) on a hand-built geometry
//   volume with a wall, against a CPU double implementation of the documented weights;
// - the derivative damping on a uniform and a stepped SH field, against a CPU double one;
// - the visibility-moment weights (lpv.lookup=visibility) on a hand-built moments volume of a
//   wall, moments and Chebyshev weights written out here in double from the documented
//   definitions (docs/lpv.md, "Visibility moments").
#include "gpu_fixture.h"

#include "gl/program.h"
#include "compute/lib/lpv_shared.h"
#include "render/lpv/lpv_math.h"

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <map>
#include <string>
#include <cmath>
#include <vector>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const double kPi = 3.14159265358979323846;

// Band-1 SH of the documented convention (docs/lpv.md "Conventions"), written out here in
// double from the definitions, not taken from the code.
std::array<double, 4> basis(glm::dvec3 d) {
    const double y00 = 0.5 / std::sqrt(kPi), y1 = std::sqrt(3.0) / (2.0 * std::sqrt(kPi));
    return {y00, -y1 * d.y, y1 * d.z, -y1 * d.x};
}
std::array<double, 4> cosLobe(glm::dvec3 n) {
    const double c0 = std::sqrt(kPi) / 2.0, c1 = std::sqrt(kPi / 3.0);
    return {c0, -c1 * n.y, c1 * n.z, -c1 * n.x};
}
double evaluate(const std::array<double, 4>& c, glm::dvec3 d) {
    auto b = basis(d);
    return c[0] * b[0] + c[1] * b[1] + c[2] * b[2] + c[3] * b[3];
}

// Trilinear interpolation of a (w, h, d) field of vec4 texels at texel-space point t (texel i
// centred at i; clamped to the edge, as GL_CLAMP_TO_EDGE).
std::array<double, 4> trilinear(const std::vector<glm::vec4>& f, glm::ivec3 size, glm::dvec3 t) {
    glm::dvec3 b = glm::floor(t), fr = t - b;
    std::array<double, 4> out{0, 0, 0, 0};
    for (int k = 0; k < 8; ++k) {
        glm::ivec3 o(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        glm::ivec3 g = glm::clamp(glm::ivec3(b) + o, glm::ivec3(0), size - 1);
        double w = (o.x ? fr.x : 1 - fr.x) * (o.y ? fr.y : 1 - fr.y) * (o.z ? fr.z : 1 - fr.z);
        const glm::vec4& v = f[std::size_t(g.x + size.x * (g.y + size.y * g.z))];
        for (int c = 0; c < 4; ++c) out[std::size_t(c)] += w * double(v[c]);
    }
    return out;
}

gl::Texture volume3d(gl::MemoryLedger& ledger, const char* label, glm::ivec3 size, const std::vector<glm::vec4>& data) {
    gl::Texture t(ledger, label, {GL_TEXTURE_3D, GL_RGBA32F, size.x, size.y, size.z});
    t.setSampling(GL_LINEAR, GL_LINEAR);
    glTextureSubImage3D(t.id(), 0, 0, 0, 0, size.x, size.y, size.z, GL_RGBA, GL_FLOAT, data.data());
    return t;
}

// Documented weights (docs/lpv.md, "Leaks"), in double: stencil of q, front test against the
// surface point x with normal n, blocking from the corner lattice at the midpoints.
struct CpuWeights {
    std::array<double, 8> w{}, blocked{};
    int mode = 2;
};
CpuWeights cpuWeights(const std::vector<glm::vec4>& gv, const std::vector<glm::vec4>& axes, bool twoSided, glm::ivec3 corners,
                      glm::dvec3 q, glm::dvec3 x, glm::dvec3 n) {
    CpuWeights r;
    glm::dvec3 base = glm::floor(q - 0.5), f = q - 0.5 - base;
    std::array<double, 8> t{}, front{};
    double sum = 0, sumFront = 0;
    for (int k = 0; k < 8; ++k) {
        glm::ivec3 o(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        glm::dvec3 c = base + glm::dvec3(o) + 0.5;
        t[std::size_t(k)] = (o.x ? f.x : 1 - f.x) * (o.y ? f.y : 1 - f.y) * (o.z ? f.z : 1 - f.z);
        glm::dvec3 mid = 0.5 * (q + c);  // corner g sits at cell coordinate g
        glm::dvec3 d = glm::normalize(c - q);
        double beta;
        if (twoSided) {  // projected area across d: sum_i axes_i |d_i|
            auto a = trilinear(axes, corners, mid);
            beta = std::clamp(a[0] * std::abs(d.x) + a[1] * std::abs(d.y) + a[2] * std::abs(d.z), 0.0, 1.0);
        } else {  // oriented: B(d), surfaces facing the light that arrives from the cell
            auto b = trilinear(gv, corners, mid);
            beta = std::clamp(evaluate({b[0], b[1], b[2], b[3]}, d), 0.0, 1.0);
        }
        r.blocked[std::size_t(k)] = beta;
        front[std::size_t(k)] = glm::dot(c - x, n) > 0 ? t[std::size_t(k)] : 0.0;
        r.w[std::size_t(k)] = front[std::size_t(k)] * (1 - beta);
        sum += r.w[std::size_t(k)];
        sumFront += front[std::size_t(k)];
    }
    if (!(sum > 1e-6)) {
        r.mode = sumFront > 0 ? 1 : 0;
        sum = 0;
        for (int k = 0; k < 8; ++k) sum += (r.w[std::size_t(k)] = r.mode == 1 ? front[std::size_t(k)] : t[std::size_t(k)]);
    }
    for (auto& w : r.w) w /= sum;
    return r;
}

const char* kLookupSource = R"(
#include "lib/lpv_lookup.glsl"
layout(local_size_x = 1) in;
struct Case { vec4 q; vec4 x; vec4 n; };
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Out { vec4 results[]; };  // 5 per case
layout(binding = 0) uniform sampler3D uGeometry;
layout(binding = 1) uniform sampler3D uGeometryAxes;
layout(location = 0) uniform int uTwoSided;
void main() {
    uint i = gl_GlobalInvocationID.x;
    Case c = cases[i];
    float blocked[8], w[8];
    lpvGeometryBlocking(uGeometry, uGeometryAxes, uTwoSided != 0, c.q.xyz, blocked);
    int mode = lpvGeometryWeights(c.q.xyz, c.x.xyz, c.n.xyz, blocked, w);
    results[5u * i] = vec4(w[0], w[1], w[2], w[3]);
    results[5u * i + 1u] = vec4(w[4], w[5], w[6], w[7]);
    results[5u * i + 2u] = vec4(blocked[0], blocked[1], blocked[2], blocked[3]);
    results[5u * i + 3u] = vec4(blocked[4], blocked[5], blocked[6], blocked[7]);
    results[5u * i + 4u] = vec4(float(mode), 0.0, 0.0, 0.0);
}
)";

struct LookupCase {
    glm::vec4 q, x, n;
};

}  // namespace

TEST_CASE("LPV leaks: geometry-aware lookup weights match a CPU double implementation on a walled 2x2x2 volume") {
    GpuFixture gpu;
    // 2x2x2 cells, corner lattice 3x3x3. A wall in the corner plane x = 1 (between the cells
    // x = 0 and x = 1), seen from both sides as by the RSM and the G-buffer: blocking SH
    // a (cosLobe(+x) + cosLobe(-x)) with a = A / s^2 = 2 per corner (a wall filling the corner's
    // dual cell, counted by both sources) plus, for the opaque one-sided test below, a * cosLobe(-x).
    const glm::ivec3 corners(3);
    auto makeVolume = [&](double aBoth, double aFacing) {
        std::vector<glm::vec4> gv(27, glm::vec4(0));
        auto lp = cosLobe({1, 0, 0}), lm = cosLobe({-1, 0, 0});
        for (int z = 0; z < 3; ++z)
            for (int y = 0; y < 3; ++y) {
                glm::vec4 v;
                for (int c = 0; c < 4; ++c) v[c] = float(aBoth * (lp[std::size_t(c)] + lm[std::size_t(c)]) + aFacing * lm[std::size_t(c)]);
                gv[std::size_t(1 + 3 * (y + 3 * z))] = v;
            }
        return gv;
    };
    std::vector<LookupCase> cases;
    std::vector<int> volumeOf;
    // Receivers on the x > 1 side of the wall: floors (+y), the wall's own face (+x) and oblique
    // normals; q = x + n / 2 as the apply does (half a cell along the normal).
    const glm::vec3 normals[] = {{0, 1, 0}, {1, 0, 0}, glm::normalize(glm::vec3(1, 1, 0.3f)), glm::normalize(glm::vec3(-0.4f, 1, -0.5f)), {0, 0, 1}};
    const glm::vec3 points[] = {{1.4f, 0.6f, 1.0f}, {1.05f, 0.9f, 0.7f}, {1.8f, 0.55f, 1.3f}, {1.25f, 0.8f, 0.6f}};
    for (int vol = 0; vol < 3; ++vol)
        for (auto n : normals)
            for (auto x : points) {
                cases.push_back({glm::vec4(x + 0.5f * n, 0), glm::vec4(x, 0), glm::vec4(n, 0)});
                volumeOf.push_back(vol);
            }
    gl::MemoryLedger ledger;
    gl::ProgramCache cache;
    const gl::Program& p = cache.computeFromSource("test/lpv_lookup.comp", kLookupSource);
    // Volume 2: lpv.blocking=two-sided, the same both-sided wall as axis blocking: a |n_x| = 2.
    std::vector<std::vector<glm::vec4>> volumes = {makeVolume(1.0, 0.0), makeVolume(0.0, 8.0), std::vector<glm::vec4>(27, glm::vec4(0))};
    std::vector<glm::vec4> axes(27, glm::vec4(0));
    for (int z = 0; z < 3; ++z)
        for (int y = 0; y < 3; ++y) axes[std::size_t(1 + 3 * (y + 3 * z))] = glm::vec4(2, 0, 0, 0);
    int behindZero = 0, plainWouldRead = 0;
    for (int vol = 0; vol < 3; ++vol) {
        const bool twoSided = vol == 2;
        std::vector<LookupCase> cs;
        for (std::size_t i = 0; i < cases.size(); ++i)
            if (volumeOf[i] == vol) cs.push_back(cases[i]);
        gl::Texture gv = volume3d(ledger, "test.geometry", corners, volumes[std::size_t(vol)]);
        gl::Texture gvAxes = volume3d(ledger, "test.geometry_axes", corners, twoSided ? axes : std::vector<glm::vec4>(27, glm::vec4(0)));
        gl::Buffer bc(ledger, "test.cases", std::int64_t(cs.size() * sizeof(LookupCase)), cs.data());
        gl::Buffer out(ledger, "test.out", std::int64_t(cs.size() * 5 * sizeof(glm::vec4)));
        glUseProgram(p.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, bc.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
        glBindTextureUnit(0, gv.id());
        glBindTextureUnit(1, gvAxes.id());
        p.set(0, twoSided ? 1 : 0);
        gl::dispatch(p, int(cs.size()));
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<glm::vec4> r(cs.size() * 5);
        out.download(r.data(), std::int64_t(r.size() * sizeof(glm::vec4)));
        for (std::size_t i = 0; i < cs.size(); ++i) {
            glm::dvec3 q(cs[i].q), x(cs[i].x), n(cs[i].n);
            CpuWeights cpu = cpuWeights(volumes[std::size_t(vol)], axes, twoSided, corners, q, x, n);
            double sum = 0;
            glm::dvec3 base = glm::floor(q - 0.5);
            for (int k = 0; k < 8; ++k) {
                double w = r[5 * i + std::size_t(k / 4)][k % 4], b = r[5 * i + 2 + std::size_t(k / 4)][k % 4];
                sum += w;
                // GL_LINEAR filters with reduced-precision weights (8 fractional bits on many
                // GPUs, llvmpipe included): 1/256 of the blocking, passed on to the weights.
                CHECK(b == doctest::Approx(cpu.blocked[std::size_t(k)]).scale(1).epsilon(0.01));
                CHECK(w == doctest::Approx(cpu.w[std::size_t(k)]).epsilon(0.01).scale(1));
                glm::dvec3 c = base + glm::dvec3(k & 1, (k >> 1) & 1, (k >> 2) & 1) + 0.5;
                // The cells behind the wall (x < 1) hold the outside's light: behind the opaque
                // wall (volume 1) every one the plain trilinear lookup would read from the
                // receiver's front side gets weight 0.
                double t = (k & 1) ? q.x - 0.5 - base.x : 1 - (q.x - 0.5 - base.x);
                if (vol == 1 && c.x < 1.0 && glm::dot(c - x, n) > 0 && t > 0 && cpu.mode == 2) {
                    ++plainWouldRead;
                    CHECK(cpu.blocked[std::size_t(k)] == 1.0);
                    CHECK(w == 0.0f);
                    behindZero += w == 0.0f;
                }
            }
            CHECK(int(r[5 * i + 4].x) == cpu.mode);
            CHECK(sum == doctest::Approx(1.0).epsilon(1e-5));
        }
    }
    MESSAGE(plainWouldRead << " stencil cells behind the opaque wall in front of their receiver (read by the plain "
                           << "trilinear lookup), " << behindZero << " of them at weight 0");
    CHECK(plainWouldRead >= 10);
}

namespace {

const char* kDampingSource = R"(
#include "lib/lpv_lookup.glsl"
layout(local_size_x = 1) in;
struct Case { vec4 x; vec4 n; };
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Out { vec4 results[]; };  // front E, back E, factor
layout(binding = 0) uniform sampler3D uLight;  // one channel's SH, 4^3 cells, cell i centred at i + 1/2
float irradiance(vec3 cellCoord, vec3 n) {
    return shCosineIntegral(shMirror(texture(uLight, cellCoord / vec3(textureSize(uLight, 0)))), n);
}
void main() {
    uint i = gl_GlobalInvocationID.x;
    vec3 x = cases[i].x.xyz, n = cases[i].n.xyz;
    float front = irradiance(x + 0.5 * n, n), back = irradiance(x - 0.5 * n, n);
    results[i] = vec4(front, back, lpvDamping(front, back), front * lpvDamping(front, back));
}
)";

struct DampCase {
    glm::vec4 x, n;
};

}  // namespace

TEST_CASE("LPV leaks: derivative damping leaves a uniform field unchanged and damps a field stepping across a wall") {
    GpuFixture gpu;
    const glm::ivec3 size(4);
    // Light flowing towards -x (arriving at a surface facing +x), as the outside of a sunlit
    // wall at x = 2 sends it: I = k cosLobe(-x). Uniform: k everywhere; stepped: k behind the
    // wall (cells x < 2), k / 10 in front of it.
    auto field = [&](double behind, double front) {
        std::vector<glm::vec4> f(64);
        auto l = cosLobe({-1, 0, 0});
        for (int z = 0; z < 4; ++z)
            for (int y = 0; y < 4; ++y)
                for (int x = 0; x < 4; ++x) {
                    double k = x < 2 ? behind : front;
                    f[std::size_t(x + 4 * (y + 4 * z))] = glm::vec4(float(k * l[0]), float(k * l[1]), float(k * l[2]), float(k * l[3]));
                }
        return f;
    };
    std::vector<DampCase> cs;
    for (float px : {2.02f, 2.2f, 2.45f})
        for (glm::vec3 n : {glm::vec3(1, 0, 0), glm::normalize(glm::vec3(1, 0.3f, -0.2f))})
            cs.push_back({glm::vec4(px, 1.7f, 2.1f, 0), glm::vec4(n, 0)});
    gl::MemoryLedger ledger;
    gl::ProgramCache cache;
    const gl::Program& p = cache.computeFromSource("test/lpv_damping.comp", kDampingSource);
    int damped = 0;
    for (int stepped = 0; stepped < 2; ++stepped) {
        std::vector<glm::vec4> f = stepped ? field(1.0, 0.1) : field(1.0, 1.0);
        gl::Texture light = volume3d(ledger, "test.light", size, f);
        gl::Buffer bc(ledger, "test.cases", std::int64_t(cs.size() * sizeof(DampCase)), cs.data());
        gl::Buffer out(ledger, "test.out", std::int64_t(cs.size() * sizeof(glm::vec4)));
        glUseProgram(p.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, bc.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
        glBindTextureUnit(0, light.id());
        gl::dispatch(p, int(cs.size()));
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<glm::vec4> r(cs.size());
        out.download(r.data(), std::int64_t(r.size() * sizeof(glm::vec4)));
        for (std::size_t i = 0; i < cs.size(); ++i) {
            glm::dvec3 x(cs[i].x), n(cs[i].n);
            // E = <mirror(I), cosLobe(n)>, the documented irradiance, at x + n/2 and x - n/2
            // (texel-space: cell i at i + 1/2, so texel coordinate = cell coordinate - 1/2).
            auto E = [&](glm::dvec3 at) {
                auto I = trilinear(f, size, at - 0.5);
                auto lobe = cosLobe(n);
                return I[0] * lobe[0] - I[1] * lobe[1] - I[2] * lobe[2] - I[3] * lobe[3];
            };
            double front = E(x + 0.5 * n), back = E(x - 0.5 * n);
            double factor = back > front && back > 0 ? std::max(front, 0.0) / back : 1.0;
            CHECK(r[i].x == doctest::Approx(front).epsilon(0.01));
            CHECK(r[i].y == doctest::Approx(back).epsilon(0.01));
            CHECK(r[i].z == doctest::Approx(factor).epsilon(0.02));
            if (!stepped) {
                // No derivative: unchanged (up to the float rounding of two equal filtered fetches).
                CHECK(r[i].z == doctest::Approx(1.0).epsilon(1e-5));
                CHECK(r[i].w == doctest::Approx(r[i].x).epsilon(1e-5));
            } else if (factor < 0.9) {
                ++damped;
            }
        }
    }
    CHECK(damped >= 3);  // the receivers within half a cell of the wall read the step
}

namespace {

// Octahedral map (docs/lpv.md, "Visibility moments"), written out in double.
glm::dvec2 octEncode(glm::dvec3 w) {
    glm::dvec3 a = w / (std::abs(w.x) + std::abs(w.y) + std::abs(w.z));
    glm::dvec2 e(a.x, a.y);
    if (a.z < 0) e = glm::dvec2((1 - std::abs(a.y)) * (a.x >= 0 ? 1 : -1), (1 - std::abs(a.x)) * (a.y >= 0 ? 1 : -1));
    return e * 0.5 + 0.5;
}
glm::dvec3 octDecode(glm::dvec2 uv) {
    glm::dvec2 e = uv * 2.0 - 1.0;
    glm::dvec3 w(e.x, e.y, 1 - std::abs(e.x) - std::abs(e.y));
    if (w.z < 0) w = glm::dvec3((1 - std::abs(e.y)) * (e.x >= 0 ? 1 : -1), (1 - std::abs(e.x)) * (e.y >= 0 ? 1 : -1), w.z);
    return glm::normalize(w);
}
double chebyshev(glm::dvec2 m, double r) {
    if (r <= m.x) return 1.0;
    double var = std::max(m.y - m.x * m.x, double(RTGI_LPV_VIS_MIN_VARIANCE)), d = r - m.x;
    return var / (var + d * d);
}

// lpv.visibility_exponent of the kernel below and of the oracle (the default, DDGI's 3).
const int kVisExponent = 3;
const char* kVisibilitySource = R"(
#define RTGI_LPV_VIS_EXPONENT 3
#include "lib/lpv_lookup.glsl"
layout(local_size_x = 1) in;
struct Case { vec4 q; vec4 x; vec4 n; vec4 t; };
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Out { vec4 results[]; };  // 4 per case
layout(binding = 0) uniform sampler3D uMoments;
void main() {
    uint i = gl_GlobalInvocationID.x;
    Case c = cases[i];
    float blocked[8], w[8];
    lpvVisibilityBlockingAt(uMoments, c.q.xyz, c.t.xyz, ivec3(2), blocked);
    lpvGeometryWeights(c.q.xyz, c.x.xyz, c.n.xyz, blocked, w);
    results[4u * i] = vec4(w[0], w[1], w[2], w[3]);
    results[4u * i + 1u] = vec4(w[4], w[5], w[6], w[7]);
    results[4u * i + 2u] = vec4(blocked[0], blocked[1], blocked[2], blocked[3]);
    results[4u * i + 3u] = vec4(blocked[4], blocked[5], blocked[6], blocked[7]);
}
)";

}  // namespace

TEST_CASE("LPV leaks: visibility-moment lookup weights match a CPU double implementation on a 2x2x2 volume with a wall") {
    GpuFixture gpu;
    // 2x2x2 cells (cell coordinates), a wall in the plane x = 1.3: the cells x = 0 (centre 0.5)
    // and x = 1 (centre 1.5) lie on its two sides. Each cell's N x N octahedral map holds the
    // mean and mean square over S x S strata of the exact distance from its centre to the plane,
    // clamped to the maximum distance (computed here, the hand-built volume).
    const int N = RTGI_LPV_VIS_RES, S = RTGI_LPV_VIS_SUBSAMPLES;
    const double D = RTGI_LPV_VIS_MAX_DISTANCE, wall = 1.3;
    const glm::ivec3 tex(2 * N, 2 * N, 2);
    std::vector<glm::dvec2> moments(std::size_t(tex.x * tex.y * tex.z));
    for (int cz = 0; cz < 2; ++cz)
        for (int cy = 0; cy < 2; ++cy)
            for (int cx = 0; cx < 2; ++cx)
                for (int v = 0; v < N; ++v)
                    for (int u = 0; u < N; ++u) {
                        const double c = cx + 0.5;
                        glm::dvec2 m(0);
                        for (int j = 0; j < S * S; ++j) {
                            glm::dvec3 w = octDecode((glm::dvec2(u, v) + (glm::dvec2(j % S, j / S) + 0.5) / double(S)) / double(N));
                            double t = (wall - c) / w.x;
                            double d = w.x != 0 && t > 0 ? std::min(t, D) : D;
                            m += glm::dvec2(d, d * d);
                        }
                        moments[std::size_t(cx * N + u + tex.x * (cy * N + v + tex.y * cz))] = m / double(S * S);
                    }
    std::vector<glm::vec2> upload(moments.size());
    for (std::size_t i = 0; i < moments.size(); ++i) upload[i] = glm::vec2(moments[i]);
    gl::MemoryLedger ledger;
    gl::Texture mt(ledger, "test.visibility", {GL_TEXTURE_3D, GL_RG32F, tex.x, tex.y, tex.z});
    mt.setSampling(GL_LINEAR, GL_LINEAR);
    glTextureSubImage3D(mt.id(), 0, 0, 0, 0, tex.x, tex.y, tex.z, GL_RG, GL_FLOAT, upload.data());
    // Bilinear filter of a cell's tile at the clamped octahedral coordinate (texel centres at i + 1/2).
    auto fetch = [&](glm::ivec3 cell, glm::dvec3 w) {
        glm::dvec2 t = glm::clamp(octEncode(w) * double(N), glm::dvec2(0.5), glm::dvec2(N - 0.5)) - 0.5;
        glm::dvec2 b = glm::floor(t), f = t - b;
        glm::dvec2 m(0);
        for (int k = 0; k < 4; ++k) {
            glm::ivec2 o(k & 1, k >> 1);
            glm::ivec2 g = glm::min(glm::ivec2(b) + o, glm::ivec2(N - 1));
            double wt = (o.x ? f.x : 1 - f.x) * (o.y ? f.y : 1 - f.y);
            m += wt * moments[std::size_t(cell.x * N + g.x + tex.x * (cell.y * N + g.y + tex.y * cell.z))];
        }
        return m;
    };
    // Receivers on the x < 1.3 side: floors and ceilings beside the wall (normal +-y: the side
    // test keeps the cells beyond the wall, only the visibility can drop them), the wall's
    // own face (-x) and oblique normals; q = x + n / 2 as the apply does. The moments are tested
    // against t: q itself, or q + b v with a view direction v away from the wall (the apply's view
    // bias b = lpv.visibility_view_bias).
    struct Case {
        glm::vec4 q, x, n, t;
    };
    std::vector<Case> cases;
    const glm::vec3 normals[] = {{0, 1, 0}, {0, -1, 0}, {-1, 0, 0}, glm::normalize(glm::vec3(-0.3f, 1, 0.4f))};
    const glm::vec3 points[] = {{0.9f, 0.3f, 0.8f}, {1.1f, 0.6f, 1.2f}, {1.25f, 1.4f, 0.7f}, {0.7f, 1.1f, 1.05f}};
    const glm::vec3 view = glm::normalize(glm::vec3(-1, 0.3f, 0.2f));
    const float viewBias = Settings{}.lpv.visibilityViewBias;  // the default
    REQUIRE(viewBias > 0.0f);
    for (float bias : {0.0f, viewBias})
        for (auto n : normals)
            for (auto x : points) {
                glm::vec3 q = x + 0.5f * n;
                cases.push_back({glm::vec4(q, 0), glm::vec4(x, 0), glm::vec4(n, 0), glm::vec4(q + bias * view, 0)});
            }
    // Creases: floor and ceiling points 0.02 cells from the wall, whose q lies next to the wall's plane
    // (in the Chebyshev bound's soft tail), each unbiased and with the view bias.
    const std::size_t creaseFirst = cases.size();
    for (float bias : {0.0f, viewBias})
        for (float ny : {1.0f, -1.0f})
            for (glm::vec2 yz : {glm::vec2(0.35f, 0.9f), glm::vec2(1.2f, 0.6f)}) {
                glm::vec3 x(1.28f, yz.x, yz.y), n(0, ny, 0), q = x + 0.5f * n;
                cases.push_back({glm::vec4(q, 0), glm::vec4(x, 0), glm::vec4(n, 0), glm::vec4(q + bias * view, 0)});
            }
    gl::ProgramCache cache;
    const gl::Program& p = cache.computeFromSource("test/lpv_visibility.comp", kVisibilitySource);
    gl::Buffer bc(ledger, "test.cases", std::int64_t(cases.size() * sizeof(Case)), cases.data());
    gl::Buffer out(ledger, "test.out", std::int64_t(cases.size() * 4 * sizeof(glm::vec4)));
    glUseProgram(p.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, bc.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    glBindTextureUnit(0, mt.id());
    gl::dispatch(p, int(cases.size()));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> r(cases.size() * 4);
    out.download(r.data(), std::int64_t(r.size() * sizeof(glm::vec4)));
    int beyond = 0, steep = 0, same = 0, free = 0;  // cells checked by the invariants below
    double sumBeyond = 0, sumSame = 0;
    double creaseUnbiased = 0, creaseBiased = 0;  // the crease cases' weight of the cells beyond the wall
    for (std::size_t i = 0; i < cases.size(); ++i) {
        glm::dvec3 q(cases[i].q), x(cases[i].x), n(cases[i].n), tq(cases[i].t);
        glm::dvec3 base = glm::floor(q - 0.5), f = q - 0.5 - base;
        std::array<double, 8> w{}, blocked{};
        double sum = 0, gpuSum = 0;
        for (int k = 0; k < 8; ++k) {
            glm::ivec3 o(k & 1, (k >> 1) & 1, (k >> 2) & 1);
            glm::dvec3 c = base + glm::dvec3(o) + 0.5;
            glm::ivec3 cell = glm::clamp(glm::ivec3(base) + o, glm::ivec3(0), glm::ivec3(1));
            double rr = glm::length(tq - c);
            blocked[std::size_t(k)] = rr > 0 ? 1 - std::pow(chebyshev(fetch(cell, (tq - c) / rr), rr), kVisExponent) : 0.0;
            double t = (o.x ? f.x : 1 - f.x) * (o.y ? f.y : 1 - f.y) * (o.z ? f.z : 1 - f.z);
            w[std::size_t(k)] = (glm::dot(c - x, n) > 0 ? t : 0.0) * (1 - blocked[std::size_t(k)]);
            sum += w[std::size_t(k)];
        }
        REQUIRE(sum > 1e-6);  // q = x + n / 2 on the wall's near side: a front cell is visible
        for (int k = 0; k < 8; ++k) {
            glm::dvec3 c = base + glm::dvec3(k & 1, (k >> 1) & 1, (k >> 2) & 1) + 0.5;
            double gw = r[4 * i + std::size_t(k / 4)][k % 4], gb = r[4 * i + 2 + std::size_t(k / 4)][k % 4];
            gpuSum += gw;
            // GL_LINEAR's reduced-precision filter weights (1/256) move the mean distance by up
            // to 1/256 of a texel step, which the Chebyshev bound amplifies near r = mean.
            CHECK(gb == doctest::Approx(blocked[std::size_t(k)]).scale(1).epsilon(0.02));
            CHECK(gw == doctest::Approx(w[std::size_t(k)] / sum).scale(1).epsilon(0.02));
            // A cell beyond the wall from t (the segment crosses x = 1.3): the bound only blocks
            // where the filtered texels' mean distance is short of r, i.e. where the direction to t
            // is steep to the wall (a texel spans ~30 degrees; towards grazing directions its rays run
            // past t and the mean exceeds r: the Chebyshev bound's known softness, docs/lpv.md).
            glm::dvec3 omega = (tq - c) / glm::length(tq - c);
            if (i >= creaseFirst && c.x > wall) (tq == q ? creaseUnbiased : creaseBiased) += gw;
            if ((c.x - wall) * (tq.x - wall) < 0) {
                ++beyond;
                sumBeyond += gb;
                if (std::abs(omega.x) > 0.8) {
                    ++steep;
                    CHECK(gb > 0.5);
                }
            } else {
                ++same;
                sumSame += gb;
            }
            // A cell on t's side looking away from the wall (every ray of the filtered texels
            // misses it within the maximum distance): moments (D, D^2), r < D, visible.
            if ((c.x - wall) * (tq.x - wall) > 0 && tq.x - c.x < -0.3 * glm::length(tq - c)) {
                ++free;
                CHECK(gb == 0.0f);
            }
        }
        CHECK(gpuSum == doctest::Approx(1.0).epsilon(1e-5));
    }
    MESSAGE(beyond << " stencil cells beyond the wall from their lookup point (" << steep << " steep, mean blocked "
                   << sumBeyond / std::max(beyond, 1) << "), " << same << " on its side (mean blocked "
                   << sumSame / std::max(same, 1) << "), " << free << " with a free view");
    CHECK(beyond >= 8);
    CHECK(steep >= 4);
    // On average the wall blocks what lies beyond it more than what lies on t's side.
    CHECK(sumBeyond / beyond > sumSame / std::max(same, 1) + 0.1);
    // At the creases (4 cases each): tested at q, which lies on the wall's plane up to 0.02 cells, the
    // cells beyond the wall keep a large weight (the bound cannot tell q from the wall); tested the default
    // bias towards the camera they keep clearly less (what remains: diagonal cells whose filtered texel mixes
    // in grazing directions, the bound's softness above; 0.5 cells leave 0.21 of the weight, 0.35 leave 0.45).
    MESSAGE("crease: weight beyond the wall " << creaseUnbiased / 4 << " at q, " << creaseBiased / 4 << " with the view bias");
    CHECK(creaseUnbiased / 4 > 0.5);
    CHECK(creaseBiased < 0.7 * creaseUnbiased);
}

TEST_CASE("LPV leaks: the traced face openness of builtin:leak equals a CPU double ray cast against its boxes") {
    // lpv.blocking=visibility (docs/lpv.md, "Face openness"): per cell and axis a = +x, +y, +z, the
    // fraction of F x F rays parallel to a, from the strata centres of the cell's cross-section
    // through its centre to the plane of the next centre, that meet no surface. The oracle casts
    // the same segments in double against the scene's boxes (scenes/leak.json), analytically: a
    // segment meets a closed box's surface iff it enters it within its length or starts inside
    // and leaves it within its length.
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = loadBuiltin("leak");
    Settings s = smallLpvSettings();
    s.lpv.grid = glm::ivec3(11);  // cells of ~0.8 m: the 0.1 m walls cross slabs at various depths
    s.lpv.blocking = LpvSettings::Blocking::Visibility;
    s.lpv.lookup = LpvSettings::Lookup::Geometry;
    s.lpv.sky = LpvSettings::Sky::Ambient;
    auto r = renderFrames(scene, s, {32, 24}, prof);
    Pass* vis = r->findPass("lpv.visibility");
    REQUIRE(vis != nullptr);
    const gl::Texture* faces = nullptr;
    for (auto& o : r->checkedOutputs(*vis))
        if (o.name.substr(o.name.find(':') + 1) == "lpv.face_visibility") faces = o.tex;
    REQUIRE(faces != nullptr);
    Camera cam = resolveCamera(scene, s);
    View v = makeView(cam, {32, 24}, nullptr, 0);
    auto placements = lpv::placeCascades(s.lpv, 1, scene.bounds(), v.position, v.forward());
    REQUIRE(placements.size() == 1);
    const lpv::Placement& pl = placements[0];
    REQUIRE(faces->width() == pl.grid.x);
    struct Box {
        glm::dvec3 lo, hi;
    };
    const std::vector<Box> boxes = {{{-4.0, -0.1, -4.0}, {4.0, 0.0, 4.0}},  {{-2.1, 0.0, -2.1}, {-2.0, 2.6, 2.1}},
                                    {{2.0, 0.0, -2.1}, {2.1, 2.6, 2.1}},    {{-2.1, 0.0, -2.1}, {2.1, 2.6, -2.0}},
                                    {{-2.1, 0.0, 2.0}, {2.1, 2.6, 2.1}},    {{-2.1, 2.5, -2.1}, {2.1, 2.6, 2.1}}};
    const int F = RTGI_LPV_VIS_FACE_RAYS;
    const double cell = pl.cell, eps = 1e-4;
    int cells = 0, partial = 0, closed = 0, ambiguous = 0;
    for (int z = 0; z < pl.grid.z; ++z) {
        FloatImage img = readTexture(*faces, z);
        for (int y = 0; y < pl.grid.y; ++y)
            for (int x = 0; x < pl.grid.x; ++x) {
                glm::dvec3 centre = glm::dvec3(pl.origin) + (glm::dvec3(x, y, z) + 0.5) * cell;
                for (int a = 0; a < 3; ++a) {
                    glm::dvec3 d(a == 0, a == 1, a == 2), u(a == 1, a == 2, a == 0), w(a == 2, a == 0, a == 1);
                    int open = 0;
                    bool unclear = false;
                    for (int j = 0; j < F * F; ++j) {
                        glm::dvec3 o = centre + cell * (((j % F) + 0.5) / F - 0.5) * u + cell * (((j / F) + 0.5) / F - 0.5) * w;
                        bool hit = false;
                        for (const Box& b : boxes) {
                            // Across the ray: inside the box's extent (a ray within eps of a side plane is ambiguous).
                            bool across = true;
                            for (int k = 0; k < 3; ++k) {
                                if (k == a) continue;
                                if (std::abs(o[k] - b.lo[k]) < eps || std::abs(o[k] - b.hi[k]) < eps) unclear = true;
                                across = across && o[k] > b.lo[k] && o[k] < b.hi[k];
                            }
                            if (!across) continue;
                            double t0 = b.lo[a] - o[a], t1 = b.hi[a] - o[a];  // entry and exit along +d
                            for (double t : {t0, t1})
                                if (std::abs(t) < eps || std::abs(t - cell) < eps) unclear = true;
                            hit = hit || (t0 >= 0 && t0 <= cell) || (t0 < 0 && t1 >= 0 && t1 <= cell);
                        }
                        open += hit ? 0 : 1;
                    }
                    if (unclear) {
                        ++ambiguous;
                        continue;
                    }
                    double expected = double(open) / (F * F);
                    double got = img.at(x, y, a);
                    INFO("cell " << x << "," << y << "," << z << " axis " << a);
                    CHECK(std::abs(got - expected) <= 0.5 / 255.0 + 1e-6);  // RGBA8 storage
                    ++cells;
                    partial += expected > 0 && expected < 1;
                    closed += expected == 0;
                }
            }
    }
    MESSAGE(cells << " (cell, axis) pairs checked, " << closed << " closed, " << partial << " partly open, " << ambiguous
                  << " left out (a ray within 1e-4 of a box's plane)");
    CHECK(cells >= 3 * pl.grid.x * pl.grid.y * pl.grid.z * 3 / 4);
    CHECK(closed >= 20);
    CHECK(partial >= 10);
}

TEST_CASE("LPV leaks: the axis blocking and the visibility volumes are allocated only by the settings that read them") {
    // lpv.blocking=two-sided alone reads lpv.geometry_axes and the 3 extra accumulation channels;
    // lpv.lookup / lpv.blocking / lpv.sky = visibility alone read lpv.visibility, lpv.sky_visibility
    // and the BVH. The oracle is the ledger: what each frame allocated, by name and size.
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = loadBuiltin("leak");
    const glm::ivec2 size(32, 24);
    auto allocated = [&](const Settings& s) {
        auto r = renderFrames(scene, s, size, prof);
        std::map<std::string, std::int64_t> m;
        for (auto& [name, bytes] : r->ledger().entries()) m[name] += bytes;
        return m;
    };
    auto has = [](const std::map<std::string, std::int64_t>& m, const std::string& prefix) {
        for (auto& [name, bytes] : m)
            if (name.rfind(prefix, 0) == 0 && bytes > 0) return true;
        return false;
    };
    Settings oriented;
    oriented.lpv.mode = Toggle::On;
    oriented.lpv.grid = glm::ivec3(8);
    oriented.lpv.lookup = LpvSettings::Lookup::Geometry;
    oriented.lpv.sky = LpvSettings::Sky::Ambient;
    oriented.lpv.blocking = LpvSettings::Blocking::Oriented;
    auto a = allocated(oriented);
    CHECK(has(a, "lpv.geometry_accum"));
    CHECK_FALSE(has(a, "lpv.geometry_axes"));
    CHECK_FALSE(has(a, "lpv.visibility"));
    CHECK_FALSE(has(a, "lpv.sky_visibility"));
    Settings twoSided = oriented;
    twoSided.lpv.blocking = LpvSettings::Blocking::TwoSided;
    auto b = allocated(twoSided);
    CHECK(has(b, "lpv.geometry_axes"));
    // 8 vs 11 R32F channels per corner of the (grid + 1)^3 lattice, per cascade.
    const std::int64_t corners = 9 * 9 * 9;
    const std::int64_t cascades = oriented.lpv.cascades;
    CHECK(a["lpv.geometry_accum"] == cascades * corners * 8 * 4);
    CHECK(b["lpv.geometry_accum"] == cascades * corners * 11 * 4);
    Settings visibility = oriented;
    visibility.lpv.lookup = LpvSettings::Lookup::Visibility;
    visibility.lpv.sky = LpvSettings::Sky::Visibility;
    auto c = allocated(visibility);
    CHECK(has(c, "lpv.visibility.bvh"));
    CHECK(c["lpv.visibility"] == cascades * 8 * 8 * 8 * RTGI_LPV_VIS_RES * RTGI_LPV_VIS_RES * 4);
    CHECK(c["lpv.sky_visibility"] == cascades * 8 * 8 * 8 * 8);
    CHECK_FALSE(has(c, "lpv.geometry_axes"));
    CHECK_FALSE(has(c, "lpv.face_visibility"));
    CHECK_FALSE(has(a, "lpv.face_visibility"));
    // lpv.blocking=visibility alone: the face openness (RGBA8 per cell) and the BVH, no moments.
    Settings faces = oriented;
    faces.lpv.blocking = LpvSettings::Blocking::Visibility;
    auto f = allocated(faces);
    CHECK(f["lpv.face_visibility"] == cascades * 8 * 8 * 8 * 4);
    CHECK(has(f, "lpv.visibility.bvh"));
    CHECK_FALSE(has(f, "lpv.sky_visibility"));
    CHECK(f.count("lpv.visibility") == 0);
}

TEST_CASE("LPV leaks: closed thin-walled room (builtin:leak) receives < 1 % of the outside wall's LPV light with the defaults") {
    // builtin:leak: a closed box of 0.1 m walls (less than a cell), sunlit outside. The exact
    // indirect light inside is 0 (nothing enters); the LPV's is leakage. Its mean over the
    // interior surfaces seen from inside must stay below 1 % of the mean LPV indirect light on
    // the sunlit outside walls (x = 2.1 and z = 2.1 faces, lit by the ground's bounce).
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = loadBuiltin("leak");
    const glm::ivec2 size(64, 40);
    auto meanIndirect = [&](const Settings& s, const std::string& view, auto&& keep) {
        auto run = renderFrames(scene, s, size, prof);
        FloatImage img = readTexture(run->resources().indirectDiffuse);
        FloatImage depth = readTexture(run->resources().gbuffer.linearDepth);
        double sum = 0;
        int n = 0;
        for (int y = 0; y < size.y; ++y)
            for (int x = 0; x < size.x; ++x) {
                if (!(depth.at(x, y, 0) > 0)) continue;
                glm::dvec3 p = worldPosition(scene, s, size, depth, x, y);
                if (!keep(p)) continue;
                sum += (img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2)) / 3.0;
                ++n;
            }
        MESSAGE(view << ": " << n << " pixels, mean LPV indirect " << (n ? sum / n : 0.0));
        REQUIRE(n > 100);
        return sum / n;
    };
    auto run = [&](Settings s) {
        s.lpv.mode = Toggle::On;
        s.ao.variant = AoSettings::Variant::Off;  // the LPV's own lookup, no bent normals
        s.camera.view = "outside";
        double outside = meanIndirect(s, "outside", [](glm::dvec3 p) {
            return (std::abs(p.x - 2.1) < 1e-2 || std::abs(p.z - 2.1) < 1e-2) && p.y > 0.1 && p.y < 2.5;
        });
        s.camera.view = "inside";
        double inside = meanIndirect(s, "inside", [](glm::dvec3 p) {
            return std::abs(p.x) < 2.0 && std::abs(p.z) < 2.0 && p.y >= -1e-3 && p.y <= 2.5 + 1e-3;
        });
        return inside / outside;
    };
    if (const char* sets = std::getenv("RTGI_LEAK_SETS")) {  // ';'-separated configs of ','-separated key=value
        std::string all(sets);
        std::size_t a = 0;
        while (a <= all.size()) {
            std::size_t b = all.find(';', a);
            std::string cfg = all.substr(a, b == std::string::npos ? std::string::npos : b - a);
            Settings e;
            std::size_t i = 0;
            while (i < cfg.size()) {
                std::size_t j = cfg.find(',', i);
                std::string kv = cfg.substr(i, j == std::string::npos ? std::string::npos : j - i);
                if (!kv.empty()) applyAssignment(e, kv);
                i = j == std::string::npos ? cfg.size() : j + 1;
            }
            MESSAGE("EXPLORE [" << cfg << "] ratio " << run(e));
            if (b == std::string::npos) break;
            a = b + 1;
        }
        return;
    }
    if (std::getenv("RTGI_LEAK_EXPLORE")) {
        for (int m = 0; m < 32; ++m) {
            if ((m & 4) != 0) continue;  // inject_side: no effect on axis-aligned walls
            Settings e;
            e.lpv.lookup = (m & 1) ? LpvSettings::Lookup::Geometry : LpvSettings::Lookup::Trilinear;
            e.lpv.damping = (m & 2) != 0;
            e.lpv.injectSide = (m & 4) ? LpvSettings::InjectSide::Front : LpvSettings::InjectSide::Offset;
            e.lpv.firstStepBlocked = (m & 8) != 0;
            e.lpv.blocking = (m & 16) ? LpvSettings::Blocking::TwoSided : LpvSettings::Blocking::Oriented;
            e.lpv.injectSide = LpvSettings::InjectSide::Offset;
            e.lpv.reflect = LpvSettings::Reflect::Destination;
            MESSAGE("combo " << m << " ratio " << run(e));
        }
    }
    // The defaults since the fifth pass (docs/lpv.md, "Fifth pass"): the traced face openness
    // stops the flux that crosses the walls (lpv.blocking=visibility) and the sharpened visibility-moment
    // lookup (lpv.visibility_exponent=3) the cells beyond them, on 16^3 cells per cascade.
    Settings defaults;
    double ratio = run(defaults);
    MESSAGE("inside / outside LPV indirect with the defaults: " << ratio);
    CHECK(ratio < 0.01);
    // The same remedies on the previous default grid (24^3): the walls stay thinner than a cell.
    Settings fine;
    fine.lpv.grid = glm::ivec3(24);
    double fineRatio = run(fine);
    MESSAGE("inside / outside with lpv.grid=24: " << fineRatio);
    CHECK(fineRatio < 0.01);
    // The blocking before the fifth pass (oriented geometry-volume blocking) lets the walls leak.
    Settings oriented;
    oriented.lpv.blocking = LpvSettings::Blocking::Oriented;
    oriented.lpv.visibilityExponent = 1;
    oriented.lpv.grid = glm::ivec3(24);
    MESSAGE("inside / outside with lpv.blocking=oriented lpv.visibility_exponent=1 lpv.grid=24: " << run(oriented));
    // Positive control: the seed's scheme without the remedies leaks visibly into the same room.
    Settings plain;
    plain.lpv.lookup = LpvSettings::Lookup::Trilinear;
    plain.lpv.damping = false;
    plain.lpv.injectSide = LpvSettings::InjectSide::Offset;
    plain.lpv.firstStepBlocked = false;
    plain.lpv.blocking = LpvSettings::Blocking::Oriented;
    plain.lpv.reflect = LpvSettings::Reflect::Destination;
    double leak = run(plain);
    MESSAGE("inside / outside without the remedies: " << leak);
    CHECK(leak > 0.01);
}

// Issue 22: the remedies must not darken what works. rtgi-bench end to end (its error.gain: the same frame
// composed without the LPV against the same full path-traced reference), llvmpipe at 96x54, 1024 paths:
// builtin:cornell (with its suggestions) and the dragon on builtin:plane (view=front, the suite's
// ao.radius) keep gain = 1 - rmse / rmse(lpv=off) >= 0.25, whole image and interior (measured 0.350 / 0.309
// and 0.373 / 0.381; on the device at 480x270: 0.390 and 0.399, docs/RESULTS.md "GI suite, fifth pass").
TEST_CASE("LPV gain: builtin:cornell and the dragon on builtin:plane keep gain >= 0.25 with the defaults") {
    namespace fs = std::filesystem;
    const std::string dragon = std::string(RTGI_SHARED_SCENES) + "/stanford-dragon/dragon.gltf";
    struct Case {
        const char* name;
        std::string args;
    };
    std::vector<Case> cases{{"cornell", "--scene builtin:cornell"}};
    if (std::ifstream(dragon))
        cases.push_back({"dragon", "--scene builtin:plane --scene " + dragon + " --set view=front --set ao.radius=0.4"});
    else
        MESSAGE("dragon skipped: " << dragon << " is not present");
    for (const Case& c : cases) {
        const fs::path dir = fs::temp_directory_path() / ("rtgi-gain-" + std::string(c.name) + "-" + std::to_string(getpid()));
        const std::string cmd = std::string(RTGI_BENCH_EXE) + " " + c.args +
                                " --res 96x54 --frames 1 --warmup 1 --no-images --reference --set reference=full"
                                " --set reference.spp=1024 --set reference.cache=off --out " + dir.string() +
                                " > /dev/null 2>&1";
        const int rc = std::system(cmd.c_str());
        REQUIRE((WIFEXITED(rc) && WEXITSTATUS(rc) == 0));
        const nlohmann::json j = nlohmann::json::parse(std::ifstream(dir / "results.json"));
        fs::remove_all(dir);
        const auto& e = j.at("error");
        const auto& g = e.at("gain").at("lpv");
        const double gain = g.at("gain").get<double>(), interior = g.at("interior").at("gain").get<double>();
        const double noise = e.at("reference").at("mean_stderr").get<double>(), rmse = e.at("rmse").get<double>();
        MESSAGE(std::string(c.name) << ": gain " << gain << ", interior " << interior << ", reference noise / error " << noise / rmse);
        CHECK(noise < 0.3 * rmse);  // the reference's noise cannot carry the gain
        CHECK(gain >= 0.25);
        CHECK(interior >= 0.25);
    }
}
