// Ray-traced AO (ao=rtao, compute/ao/rtao.comp) against the ray-traced
// reference AO (ref.ao, docs/reference.md): the same definition with few rays
// per frame, so the mean over many frames must equal the reference within
// the two estimates' noise; and through the filter chain (half resolution,
// blur, temporal, upsample) it must stay within the chain's own error.
#include "ao_test_util.h"

#include "render/reference/reference_passes.h"

#include <cmath>
#include <vector>

using namespace rtgi;
using namespace rtgi::test;

namespace {

struct Reference {
    FloatImage mean, se, depth;
};

Reference referenceAo(const Scene& scene, float radius, glm::ivec2 size, int spp) {
    Settings s;
    s.reference.kind = ReferenceSettings::Kind::Ao;
    s.reference.spp = spp;
    s.reference.cacheDir = "off";
    s.lpv.mode = Toggle::Off;
    s.ssr.tracer = SsrSettings::Tracer::Off;
    s.ao.radius = radius;
    gl::Profiler prof(false);
    auto r = renderFrames(scene, s, size, prof);
    auto* out = dynamic_cast<ReferenceOutput*>(r->findPass("ref.ao"));
    REQUIRE(out != nullptr);
    return {readTexture(out->mean()), readTexture(out->standardError()), readTexture(r->resources().gbuffer.linearDepth)};
}

}  // namespace

TEST_CASE("rtao: the mean of 32 frames x 4 rays equals ref.ao within the noise of both (box-on-plane)") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene s = loadBuiltin("box-on-plane");
    const glm::ivec2 size(48, 36);
    const float R = 1.0f;
    Reference ref = referenceAo(s, R, size, 512);
    Settings st = rawAoSettings(AoSettings::Variant::Rtao, 16, R);  // full resolution, no blur / temporal
    st.ao.rays = 4;
    const int frames = 32;
    auto imgs = frameReadbacks(s, st, size, prof, [](const FrameResources& r) -> const gl::Texture& { return r.ao; },
                               frames);
    double chi2 = 0, chi2Occluded = 0, diff = 0, var = 0;
    int n = 0, occluded = 0;
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
            if (!(ref.depth.at(x, y, 0) > 0)) continue;  // sky: both 1 by definition
            double m = 0, m2 = 0;
            for (auto& im : imgs) m += im.at(x, y, 0) / frames;
            for (auto& im : imgs) m2 += (im.at(x, y, 0) - m) * (im.at(x, y, 0) - m);
            double varRt = m2 / (frames - 1) / frames;  // variance of the 32-frame mean
            double se = ref.se.at(x, y, 0);
            double v = varRt + se * se + 1e-4 * 1e-4;    // + R16F rounding of the frames
            double d = m - ref.mean.at(x, y, 0);
            chi2 += d * d / std::max(v, 1e-8);
            diff += d;
            var += v;
            if (ref.mean.at(x, y, 0) < 0.9) ++occluded, chi2Occluded += d * d / std::max(v, 1e-8);
            ++n;
        }
    REQUIRE(n > 500);
    REQUIRE(occluded > 100);  // the box occludes: the comparison is not between two constants
    double bias = diff / n, biasSigma = std::sqrt(var) / n;
    MESSAGE("pixels " << n << " (occluded " << occluded << "), mean chi2 " << chi2 / n << " (occluded pixels "
                      << chi2Occluded / occluded << "), bias " << bias << " (sigma "
                   << biasSigma << ")");
    // Equal in distribution: the normalized squared difference averages ~1
    // (pixels where both are exactly 1 count 0); a wrong cosine weight, ray
    // length or origin offset shifts whole regions (chi2 >> 1, bias >> sigma).
    CHECK(chi2 / n < 1.5);
    CHECK(chi2Occluded / occluded < 1.5);  // where both are noisy (AO < 0.9): ~1 when equal
    CHECK(std::abs(bias) < 4.0 * biasSigma + 1e-3);
}

TEST_CASE("rtao through the default chain (half resolution, blur, temporal, upsample) stays within 0.05 of ref.ao") {
    // Composition with the neighbouring passes: the chain filters the 2-ray
    // estimate without moving its mean away from the reference (8x8 block
    // means away from depth edges, after 48 frames of temporal accumulation).
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene s = loadBuiltin("box-on-plane");
    const glm::ivec2 size(64, 48);
    const float R = 1.0f;
    Reference ref = referenceAo(s, R, size, 256);
    Settings st;
    st.lpv.mode = Toggle::Off;
    st.ssr.tracer = SsrSettings::Tracer::Off;
    st.ao.variant = AoSettings::Variant::Rtao;
    st.ao.radius = R;
    st.ao.rays = 2;
    auto r = renderFrames(s, st, size, prof, 48);
    FloatImage ao = readTexture(r->resources().ao);
    double worst = 0, sum2 = 0;
    int blocks = 0;
    for (int by = 0; by + 8 <= size.y; by += 8)
        for (int bx = 0; bx + 8 <= size.x; bx += 8) {
            double a = 0, b = 0;
            int n = 0;
            bool edge = false;
            for (int y = by; y < by + 8; ++y)
                for (int x = bx; x < bx + 8; ++x) {
                    float z = ref.depth.at(x, y, 0);
                    if (!(z > 0)) continue;
                    // A depth edge inside the block (relative jump > 5 % to a
                    // neighbour): the blur and the upsample mix the two sides there.
                    for (glm::ivec2 o : {glm::ivec2(1, 0), glm::ivec2(0, 1), glm::ivec2(-1, 0), glm::ivec2(0, -1)}) {
                        glm::ivec2 q = glm::clamp(glm::ivec2(x, y) + o, glm::ivec2(0), size - 1);
                        float zq = ref.depth.at(q.x, q.y, 0);
                        if (!(zq > 0) || std::abs(zq - z) > 0.05f * z) edge = true;
                    }
                    a += ao.at(x, y, 0);
                    b += ref.mean.at(x, y, 0);
                    ++n;
                }
            if (n < 64 || edge) continue;  // blocks with sky or a depth edge
            double d = (a - b) / n;
            worst = std::max(worst, std::abs(d));
            sum2 += d * d;
            ++blocks;
        }
    REQUIRE(blocks >= 16);
    MESSAGE("blocks " << blocks << ", worst block difference " << worst << ", rms " << std::sqrt(sum2 / blocks));
    CHECK(worst < 0.05);
    CHECK(std::sqrt(sum2 / blocks) < 0.02);
}
