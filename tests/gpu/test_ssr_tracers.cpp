// The pure tracer functions of compute/lib/ssr.glsl called directly from a
// test shader on degenerate inputs (NaN / Inf / zero / back-facing normals,
// grazing rays, zero thickness, rays that leave the frustum at once): every
// output must be finite, confidences in [0, 1], invalid normals rejected.
#include "gpu_fixture.h"

#include "gl/program.h"

#include <cmath>
#include <limits>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const char* kSource = R"(
#include "lib/ssr.glsl"
layout(local_size_x = 1) in;
layout(binding = 0) uniform sampler2D uDepth;  // also the level-0-only Hi-Z pyramid
struct Case { vec4 pos; vec4 normal; vec4 params; };  // params.x = thickness
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Results { vec4 results[]; };  // 3 tracers x (hit, u, v, depth) + dir/conf
void main() {
    uint i = gl_GlobalInvocationID.x;
    SsrCamera cam = SsrCamera(0.57735, 1.0, 0.1, 50.0, vec2(textureSize(uDepth, 0)));
    vec3 dir;
    bool valid = ssrReflectionRay(cases[i].pos.xyz, cases[i].normal.xyz, dir);
    float th = cases[i].params.x;
    SsrHit h[3];
    h[0] = ssrTraceLinear(uDepth, cases[i].pos.xyz, dir, cam, 32, th, 0.5);
    h[1] = ssrTraceDda(uDepth, cases[i].pos.xyz, dir, cam, 32, th, 0.5);
    h[2] = ssrTraceHiz(uDepth, 1, cases[i].pos.xyz, dir, cam, 64, th);
    for (int k = 0; k < 3; ++k)
        results[i * 4u + uint(k)] = vec4(h[k].hit ? 1.0 : 0.0, h[k].uv, h[k].rayDepth);
    results[i * 4u + 3u] = vec4(valid ? 1.0 : 0.0, ssrConfidence(h[0], dir, 0.1), ssrConfidence(h[1], dir, 0.1),
                                ssrConfidence(h[2], dir, 0.1));
}
)";

struct Case {
    float pos[4], normal[4], params[4];
};

}  // namespace

TEST_CASE("SSR tracer functions stay finite on NaN normals, back faces, grazing rays and zero thickness") {
    GpuFixture gpu;
    // A 16x16 depth buffer of a plane receding upwards (depth 2..6) with sky
    // (0) in the top rows: sky, surfaces and frustum exits are all reachable.
    const int n = 16;
    std::vector<float> depth(std::size_t(n * n));
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) depth[std::size_t(y * n + x)] = y >= 13 ? 0.0f : 2.0f + 0.3f * float(y);
    gl::MemoryLedger ledger;
    gl::Texture tex(ledger, "test.depth", {GL_TEXTURE_2D, GL_R32F, n, n});
    glTextureSubImage2D(tex.id(), 0, 0, 0, n, n, GL_RED, GL_FLOAT, depth.data());

    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<Case> cases = {
        {{0, -0.5f, -3, 1}, {0, 1, 0, 0}, {0.2f}},            // ordinary upward normal
        {{0, -0.5f, -3, 1}, {nan, nan, nan, 0}, {0.2f}},      // NaN normal: invalid, miss
        {{0, -0.5f, -3, 1}, {inf, 0, 0, 0}, {0.2f}},          // Inf normal: invalid, miss
        {{0, -0.5f, -3, 1}, {0, 0, 0, 0}, {0.2f}},            // zero normal: invalid, miss
        {{0, -0.5f, -3, 1}, {0, 0, -1, 0}, {0.2f}},           // faces away from the eye: invalid
        {{0, -0.5f, -3, 1}, {0, 1, 0, 0}, {0.0f}},            // zero thickness
        {{0, -0.5f, -3, 1}, {0, 0.01f, 1, 0}, {0.0f}},        // reflection straight back at the camera
        {{0, -0.001f, -3, 1}, {0, 1, 0.0001f, 0}, {0.2f}},    // grazing: eye almost in the surface plane
        {{1.7f, 1.7f, -3, 1}, {-1, -1, 0.2f, 0}, {0.2f}},     // origin at the frustum corner
        {{0, 0, -0.1f, 1}, {0, 0, 1, 0}, {0.2f}},             // origin on the near plane
    };
    gl::Buffer in(ledger, "test.cases", std::int64_t(cases.size() * sizeof(Case)), cases.data());
    gl::Buffer out(ledger, "test.results", std::int64_t(cases.size() * 4 * 16));
    gl::ProgramCache cache;
    const gl::Program& p = cache.computeFromSource("test/ssr_tracers.comp", kSource);
    glUseProgram(p.id());
    glBindTextureUnit(0, tex.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    gl::dispatch(p, int(cases.size()));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> r(cases.size() * 16);
    out.download(r.data(), std::int64_t(r.size() * sizeof(float)));
    for (std::size_t i = 0; i < cases.size(); ++i) {
        INFO("case " << i);
        for (int k = 0; k < 16; ++k) CHECK(std::isfinite(r[i * 16 + std::size_t(k)]));
        for (int k = 0; k < 3; ++k) {
            float conf = r[i * 16 + 13 + std::size_t(k)];
            CHECK(conf >= 0.0f);
            CHECK(conf <= 1.0f);
        }
    }
    CHECK(r[0 * 16 + 12] > 0.5f);   // the ordinary case is a valid ray
    for (int i : {1, 2, 3, 4}) CHECK(r[std::size_t(i) * 16 + 12] < 0.5f);
    // The camera-facing reflection gets no confidence even if it hits.
    for (int k = 0; k < 3; ++k) CHECK(r[6 * 16 + 13 + std::size_t(k)] == 0.0f);
}

namespace {

const char* kThinSource = R"(
#include "lib/ssr.glsl"
layout(local_size_x = 1) in;
layout(binding = 0) uniform sampler2D uDepth;  // also the level-0-only Hi-Z pyramid
layout(std430, binding = 1) writeonly buffer Results { vec4 results[]; };  // per case: hit, u, v, depth
layout(location = 0) uniform vec3 uOrigin;
layout(location = 1) uniform vec3 uDir;
void main() {
    uint i = gl_GlobalInvocationID.x;  // tracer (3) x steps (8) x jitter (4)
    SsrCamera cam = SsrCamera(0.57735, 1.0, 0.1, 50.0, vec2(textureSize(uDepth, 0)));
    int tracer = int(i % 3u), steps = 3 + 5 * int((i / 3u) % 8u);
    float jitter = 0.1 + 0.25 * float(i / 24u);
    SsrHit h = tracer == 0 ? ssrTraceLinear(uDepth, uOrigin, uDir, cam, steps, 0.2, jitter)
             : tracer == 1 ? ssrTraceDda(uDepth, uOrigin, uDir, cam, steps, 0.2, jitter)
                           : ssrTraceHiz(uDepth, 1, uOrigin, uDir, cam, 256, 0.2);
    results[i] = vec4(h.hit ? 1.0 : 0.0, h.uv, h.rayDepth);
}
)";

}  // namespace

TEST_CASE("SSR tracers pass behind a thin post at any stride and hit the wall behind it") {
    GpuFixture gpu;
    // 64x64 depth: a wall at depth 10 and a post at depth 2.5 over pixel columns
    // [24, 32). The ray starts at uv (0.2, 0.5), depth 2, and runs right and
    // away; over the post's columns it is more than 0.4 behind the post (more than
    // the thickness 0.2), so the only hit is the wall. Coarse strides land
    // samples on the post while the ray is behind it: a hit there is wrong.
    const int n = 64;
    const double tanHalf = 0.57735, wall = 10.0;
    std::vector<float> depth(std::size_t(n * n), float(wall));
    for (int y = 0; y < n; ++y)
        for (int x = 24; x < 32; ++x) depth[std::size_t(y * n + x)] = 2.5f;
    gl::MemoryLedger ledger;
    gl::Texture tex(ledger, "test.depth", {GL_TEXTURE_2D, GL_R32F, n, n});
    glTextureSubImage2D(tex.id(), 0, 0, 0, n, n, GL_RED, GL_FLOAT, depth.data());
    const glm::dvec3 o((0.2 * 2 - 1) * tanHalf * 2.0, 0.0, -2.0);
    const glm::dvec3 d = glm::normalize(glm::dvec3(0.3, 0.0, -1.0));
    // CPU oracle (double): where the ray meets the wall plane, and the ray
    // depth over the post's columns.
    const double tWall = (wall + o.z) / -d.z;
    const glm::dvec3 h = o + d * tWall;
    const double wallPixel = (h.x / (tanHalf * wall) * 0.5 + 0.5) * n;
    for (double t = 0; t < tWall; t += 1e-3) {
        glm::dvec3 q = o + d * t;
        double px = (q.x / (tanHalf * -q.z) * 0.5 + 0.5) * n;
        if (px >= 24 && px < 32) REQUIRE(-q.z > 2.5 + 0.2);  // the scene is as described: behind the post
    }
    REQUIRE(wallPixel > 33.0);

    gl::Buffer out(ledger, "test.results", 96 * 16);
    gl::ProgramCache cache;
    const gl::Program& p = cache.computeFromSource("test/ssr_thin.comp", kThinSource);
    glUseProgram(p.id());
    p.set(0, glm::vec3(o));
    p.set(1, glm::vec3(d));
    glBindTextureUnit(0, tex.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    gl::dispatch(p, 96);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> r(96 * 4);
    out.download(r.data(), std::int64_t(r.size() * sizeof(float)));
    int hits[3] = {0, 0, 0};
    for (int i = 0; i < 96; ++i) {
        INFO("tracer " << i % 3 << " steps " << 3 + 5 * ((i / 3) % 8) << " jitter " << 0.1 + 0.25 * (i / 24));
        if (r[std::size_t(i * 4)] < 0.5f) continue;
        ++hits[i % 3];
        // One pixel: the wall crossing is found by a 6-step bisection inside the
        // last stride, or by the one-pixel DDA / Hi-Z level-0 steps.
        CHECK(std::abs(double(r[std::size_t(i * 4 + 1)]) * n - wallPixel) < 1.0);
        CHECK(double(r[std::size_t(i * 4 + 3)]) == doctest::Approx(wall).epsilon(0.05));  // fp32 bisection in depth
    }
    // Every combination of linear / DDA and every Hi-Z run finds the wall
    // (the wall spans the rest of the screen; nothing else can stop the ray).
    CHECK(hits[0] == 32);
    CHECK(hits[1] == 32);
    CHECK(hits[2] == 32);
}
