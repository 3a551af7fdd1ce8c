// lpv.coarse_iterations=auto (docs/lpv.md, "Closed scenes"): a renderer resolves it from the enclosure
// measure of its scene (scene/enclosure.h, closed forms in tests/unit/test_enclosure.cpp): the closed
// reach in a closed box, the open one in an open scene, an explicit value always wins, and no measure is
// taken where the count is not used (LPV off or without light, one cascade, the raster path).
#include "gpu_fixture.h"
#include "test_enclosure_scenes.h"

using namespace rtgi;
using namespace rtgi::test;

namespace {
Settings autoSettings() {
    Settings st;
    st.ao.variant = AoSettings::Variant::Off;
    st.ssr.tracer = SsrSettings::Tracer::Off;
    st.lpv.mode = Toggle::On;
    st.lpv.grid = glm::ivec3(8);
    st.lpv.rsm = 64;
    return st;
}
}  // namespace

TEST_CASE("lpv auto settings: a closed room propagates its coarse cascade longer, an open scene keeps the default") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    const LpvSettings defaults;
    REQUIRE(defaults.coarseIterationsAuto);
    REQUIRE(defaults.coarseIterations != LpvSettings::kClosedCoarseIterations);
    const Scene room = enclosureRoom();
    {
        Renderer r(room, autoSettings(), prof);
        REQUIRE(r.enclosure().has_value());
        CHECK(r.enclosure()->escaped == 0.0);
        CHECK(r.settings().lpv.coarseIterations == LpvSettings::kClosedCoarseIterations);
        CHECK_FALSE(r.settings().lpv.coarseIterationsAuto);  // settings() shows what took effect
        // The closed configuration renders (kClosedCoarseIterations coarse steps), its light stays finite.
        Camera cam;
        cam.position = {1.0f, 0.75f, 1.9f};
        cam.target = {1.0f, 0.5f, 0.0f};
        r.setCheck(true);
        r.render(makeView(cam, {16, 12}, nullptr, 0));
        CHECK_FALSE(r.finiteCounts().empty());
        for (auto& f : r.finiteCounts()) CHECK_MESSAGE(f.nan + f.inf == 0, std::string(f.pass + ":" + f.resource));
    }
    {   // An explicit value wins.
        Settings st = autoSettings();
        st.lpv.coarseIterationsAuto = false;
        st.lpv.coarseIterations = 20;
        Renderer r(room, st, prof);
        CHECK(r.settings().lpv.coarseIterations == 20);
        CHECK_FALSE(r.enclosure().has_value());  // nothing asked for the measure
    }
    {   // The threshold decides: nothing is closed under lpv.closed_escape = 0.
        Settings st = autoSettings();
        st.lpv.closedEscape = 0.0f;
        Renderer r(room, st, prof);
        CHECK(r.settings().lpv.coarseIterations == defaults.coarseIterations);
    }
    {   // Open: a box without its lid, 0.25 high, under a vertical sun: its floor sees mostly the opening
        // (view factor 0.66, tests/unit/test_enclosure.cpp's closed form): open under the default threshold.
        Scene open = enclosureBox(1.0f, 0.25f, false);
        open.lights.push_back(enclosureSun());
        Renderer r(open, autoSettings(), prof);
        REQUIRE(r.enclosure().has_value());
        CHECK(r.enclosure()->escaped > double(defaults.closedEscape));
        CHECK(r.settings().lpv.coarseIterations == defaults.coarseIterations);
    }
    // No measure (a BVH build) where the count is not used: LPV off, one cascade, the raster path (one
    // volume), a scene without light (no LPV pass runs).
    for (int c = 0; c < 4; ++c) {
        CAPTURE(c);
        Settings st = autoSettings();
        Scene scene = room;
        if (c == 0) st.lpv.mode = Toggle::Off;
        if (c == 1) st.lpv.cascades = 1;
        if (c == 2) st.lpv.path = LpvSettings::Path::Raster;
        if (c == 3) {
            scene.lights.clear();
            st.lpv.mode = Toggle::Auto;  // "on" without light is a configuration error
        }
        Renderer r(scene, st, prof);
        CHECK_FALSE(r.enclosure().has_value());
        CHECK(r.settings().lpv.coarseIterations == defaults.coarseIterations);
        CHECK_FALSE(r.settings().lpv.coarseIterationsAuto);
    }
}
