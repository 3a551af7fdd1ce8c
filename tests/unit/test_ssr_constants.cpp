// SSR settings -> GPU constants and pruning, without GL.
#include "render/ssr/ssr_constants.h"
#include "render/ssr/ssr_passes.h"

#include <doctest/doctest.h>

using namespace rtgi;

namespace {
std::string tracer(const Scene& s, const Settings& st) { return toString(effectiveSsrTracer(s, st)); }
}  // namespace

TEST_CASE("SSR trace size: half resolution rounds up, never zero") {
    CHECK(ssrTraceSize({1920, 1080}, true) == glm::ivec2(960, 540));
    CHECK(ssrTraceSize({45, 29}, true) == glm::ivec2(23, 15));
    CHECK(ssrTraceSize({1, 1}, true) == glm::ivec2(1, 1));
    CHECK(ssrTraceSize({45, 29}, false) == glm::ivec2(45, 29));
}

TEST_CASE("SSR Hi-Z pyramid levels go down to 1x1, halving with floor") {
    CHECK(hizLevelCount({1920, 1080}) == 11);  // 1920 -> 960 -> ... -> 1 (2^10 <= 1920 < 2^11)
    CHECK(hizLevelCount({1, 1}) == 1);
    CHECK(hizLevelCount({45, 29}) == 6);
    CHECK(hizLevelSize({45, 29}, 1) == glm::ivec2(22, 14));
    CHECK(hizLevelSize({45, 29}, 5) == glm::ivec2(1, 1));
    CHECK(hizLevelSize({45, 3}, 3) == glm::ivec2(5, 1));
}

TEST_CASE("SSR constant block follows the settings") {
    SsrSettings s;
    s.steps = 32;
    s.thickness = 0.5f;
    s.roughnessCutoff = 0.3f;
    auto u = makeSsrUniforms(s, SsrSettings::Tracer::Hiz, {100, 50});
    CHECK(u.sizes == glm::ivec4(50, 25, 100, 50));
    CHECK(u.params == glm::ivec4(32, RTGI_SSR_HIZ, 7, 2));
    CHECK(u.trace.x == 0.5f);
    CHECK(u.trace.y == 0.3f);
    s.halfResolution = false;
    u = makeSsrUniforms(s, SsrSettings::Tracer::Dda, {100, 50});
    CHECK(u.sizes == glm::ivec4(100, 50, 100, 50));
    CHECK(u.params.y == RTGI_SSR_DDA);
    CHECK(u.params.w == 1);
    CHECK_THROWS(ssrTracerId(SsrSettings::Tracer::Auto));
}

TEST_CASE("ssr=auto runs only when a drawn material is at most ssr.roughness_cutoff rough") {
    Scene s;
    Material rough;
    rough.roughness = 0.8f;
    Material glossy;
    glossy.roughness = 0.2f;
    s.materials = {rough, glossy};
    s.vertices = {{{0, 0, 0}, {0, 1, 0}, {0, 0}}, {{1, 0, 0}, {0, 1, 0}, {0, 0}}, {{0, 0, 1}, {0, 1, 0}, {0, 0}}};
    s.indices = {0, 1, 2};
    s.draws = {{0, 3, 0}};  // only the rough material is drawn
    Settings st;
    CHECK(tracer(s, st) == "off");
    st.floorRoughness = 0.1f;  // the override is what the GPU sees
    CHECK(tracer(s, st) == "linear");
    st.floorRoughness.reset();
    st.ssr.roughnessCutoff = 0.9f;
    CHECK(tracer(s, st) == "linear");
    st.ssr.roughnessCutoff = 0.5f;
    st.ssr.tracer = SsrSettings::Tracer::Dda;  // forced by the user
    CHECK(tracer(s, st) == "dda");
    st.ssr.tracer = SsrSettings::Tracer::Off;
    st.floorRoughness = 0.0f;
    CHECK(tracer(s, st) == "off");
}
