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
