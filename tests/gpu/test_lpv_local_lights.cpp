// RSMs of local lights (lpv.rsm with RTGI_RSM_LOCAL, docs/lpv.md "RSMs of
// local lights") against closed forms in double: in a closed box every bit
// of a light's flux lands on a wall, so the flux injected into the LPV must
// equal ρ·Φ, with Φ = 4π·I for a point light and
// Φ = 2π·I·[(1 − cos θi) + (cos θi − cos θo)/3] for a KHR spot cone
// (∫ t² over the cone, t linear in cos θ between the outer and inner angle).
#include "gpu_fixture.h"

#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

// Total flux in the injection accumulation of cascade `cascade` (lpv.pack
// off keeps it): every texel added Φ/π·cosLobe(n), whose Y00 coefficient is
// Φ/(2√π).
glm::dvec3 injectedFlux(Renderer& r, int cascades, int cascade) {
    Pass* inject = r.findPass("lpv.inject");
    REQUIRE(inject != nullptr);
    std::vector<Renderer::Output> outs;  // the accumulation, not the local lights' injection cache (lpv.inject_cache)
    for (auto& o : r.checkedOutputs(*inject))
        if (o.name.find("inject_cache") == std::string::npos) outs.push_back(o);
    REQUIRE(outs.size() == std::size_t(3 * cascades));  // R, G, B per cascade, finest first
    glm::dvec3 sum(0.0);
    for (int c = 0; c < 3; ++c) {
        const gl::Texture& t = *outs[std::size_t(3 * cascade + c)].tex;
        std::vector<float> v(std::size_t(t.width()) * t.height() * t.depth());
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
        glGetTextureImage(t.id(), 0, GL_RED, GL_FLOAT, GLsizei(v.size() * 4), v.data());
        for (int z = 0; z < t.depth(); ++z)
            for (int y = 0; y < t.height(); ++y)
                for (int x = 0; x < t.width(); x += 4) sum[c] += v[(std::size_t(z) * t.height() + y) * t.width() + x];
    }
    return sum * (2.0 * std::sqrt(M_PI));
}

Settings fluxSettings() {
    Settings st;
    st.lpv.mode = Toggle::On;
    st.lpv.grid = glm::ivec3(8);
    st.lpv.iterations = 1;
    st.lpv.rsm = 128;
    st.lpv.format = LpvSettings::Format::Rgba32f;
    st.post.passesOff = "lpv.pack";  // keep the accumulation for the readback
    st.light.localShadowSize = 64;
    return st;
}

}  // namespace

// With cascades, every RSM is injected into every cascade (issue 13, "and its
// cascades"); the coarsest cascade covers the scene bounds (lpv.cell = 0), so
// it holds all of ρ·Φ, and a finer one, half as large and inside the box
// (it may hold no wall at all), at most that.
TEST_CASE("LPV local lights: injected flux of a point and a spot light in a closed box equals rho * Phi (double)") {
    GpuFixture fx;
    gl::Profiler prof(false);
    const double rho = 0.5, I = 2.0;
    for (int cascades = 1; cascades <= 2; ++cascades)
    for (int kind = 0; kind < 2; ++kind) {
        Scene s = closedBoxScene(float(rho), 0.0f);
        Light l;
        l.position = {0.1f, 0.2f, -0.15f};
        l.intensity = float(I);
        l.color = {1.0f, 0.5f, 0.25f};
        double phi;
        if (kind == 0) {
            l.type = LightType::Point;
            phi = 4.0 * M_PI * I;
        } else {
            l.type = LightType::Spot;
            l.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
            const double inner = glm::radians(20.0), outer = glm::radians(40.0);
            l.innerCone = float(inner);
            l.outerCone = float(outer);
            phi = 2.0 * M_PI * I * ((1.0 - std::cos(inner)) + (std::cos(inner) - std::cos(outer)) / 3.0);
        }
        s.lights.push_back(l);
        Settings st = fluxSettings();
        st.lpv.cascades = cascades;
        auto r = renderFrames(s, st, {32, 32}, prof);
        glm::dvec3 got = injectedFlux(*r, cascades, cascades - 1);
        glm::dvec3 finest = injectedFlux(*r, cascades, 0);
        auto stats = r->findPass("lpv.inject")->stats();
        REQUIRE(!stats.empty());
        CHECK(stats[0].second == 0.0);  // no texel fell outside the grid
        for (int c = 0; c < 3; ++c) {
            double expect = rho * phi * double(l.color[c]);
            INFO((kind == 0 ? "point" : "spot") << " cascades " << cascades << " channel " << c << ": injected "
                                                << got[c] << " (finest " << finest[c] << "), rho*Phi " << expect);
            // Point: the texels' exact solid angles tile the sphere (float
            // rounding only; measured 1e-5). Spot: the cone's falloff is
            // sampled at texel centres, 128² per RSM (measured 2.4e-5).
            CHECK(got[c] == doctest::Approx(expect).epsilon(kind == 0 ? 5e-4 : 2e-3));
            CHECK(finest[c] <= expect * (1.0 + 2e-3));
        }
    }
}
