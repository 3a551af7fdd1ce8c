// A history image that holds garbage (NVIDIA does not zero new textures) must
// never leak into the temporal filter's output: on a reset, and when the
// history texel is not finite, the output is the current value.
#include "gpu_fixture.h"

#include "render/filter.h"

#include <cmath>
#include <limits>

using namespace rtgi;
using namespace rtgi::test;

TEST_CASE("temporal filter: NaN/Inf history is rejected, with and without a reset") {
    GpuFixture gpu;
    gl::MemoryLedger ledger;
    gl::ProgramCache programs;
    const int w = 8, h = 4;
    const FilterFormat fmt{GL_R16F, "r16f"};
    gl::Texture current(ledger, "test.current", {GL_TEXTURE_2D, GL_R16F, w, h});
    gl::Texture depth(ledger, "test.depth", {GL_TEXTURE_2D, GL_R32F, w, h});
    gl::Texture velocity(ledger, "test.velocity", {GL_TEXTURE_2D, GL_RG16F, w, h});
    current.clear(0.25f);
    depth.clear(3.0f);  // geometry everywhere, static: alpha would be 0.05 with a valid history
    velocity.clear(0.0f);
    TemporalFilter filter;
    filter.run(programs, ledger, "test.temporal", fmt, current, depth, velocity, true);
    // Plant non-finite values in what becomes the history of the next run.
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<float> bad(std::size_t(w * h), nan);
    for (int i = 0; i < w * h; i += 2) bad[std::size_t(i)] = inf;
    glTextureSubImage2D(filter.output().id(), 0, 0, 0, w, h, GL_RED, GL_FLOAT, bad.data());
    for (bool reset : {false, true}) {
        // Plant again before the second run (the first one overwrote the other buffer).
        glTextureSubImage2D(filter.output().id(), 0, 0, 0, w, h, GL_RED, GL_FLOAT, bad.data());
        const gl::Texture& out = filter.run(programs, ledger, "test.temporal", fmt, current, depth, velocity, reset);
        FloatImage img = readTexture(out);
        INFO("reset " << reset);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) CHECK(img.at(x, y, 0) == doctest::Approx(0.25f).epsilon(1e-3));
    }
}
