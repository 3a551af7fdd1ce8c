#include "gpu_fixture.h"
#include <cstdio>
using namespace rtgi;
using namespace rtgi::test;
TEST_CASE("DIAG ao plane") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene s = floorScene(30, glm::vec3(0.5f), false);
    using V = AoSettings::Variant;
    for (glm::ivec2 res : {glm::ivec2(48, 32), glm::ivec2(96, 64)})
    for (int cfg = 0; cfg < 3; ++cfg)
    for (auto v : {V::SsaoDisk, V::SsaoSphere, V::SsaoHemisphere, V::Vo, V::Hbao, V::Gtao}) {
        Settings st; st.lpv.mode = Toggle::Off; st.ao.variant = v; st.ao.samples = 16; st.ao.radius = 0.5f;
        st.camera.target = glm::vec3(0, 1.2f, 0);
        if (cfg == 0) { st.ao.blur = false; st.ao.temporal = false; }
        if (cfg == 1) { st.ao.blur = false; st.ao.temporal = false; st.ao.halfResolution = false; }
        auto r = renderFrames(s, st, res, prof, cfg == 2 ? 3 : 1);
        FloatImage ao = readTexture(r->resources().ao);
        FloatImage depth = readTexture(r->resources().gbuffer.linearDepth);
        double mx = 0, mean = 0; int n = 0, wx=0, wy=0;
        for (int y = 1; y < res.y - 1; ++y) for (int x = 2; x < res.x - 2; ++x) {
            if (depth.at(x, y, 0) <= 0 || y >= res.y * 12 / 32) continue;
            double e = 1.0 - ao.at(x, y, 0); mean += e; ++n;
            if (std::abs(e) > mx) mx = std::abs(e), wx = x, wy = y;
        }
        std::printf("res %dx%d cfg %d %-16s max %.4f at %d,%d mean %.4f\n", res.x, res.y, cfg, toString(v), mx, wx, wy, mean / n);
    }
}
