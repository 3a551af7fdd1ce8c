// Key handling of rtgi-view (no window): every key changes what the help says.
#include "view/controls.h"

#include <doctest/doctest.h>

#include <set>

using namespace rtgi;
using namespace rtgi::view;

TEST_CASE("view keys: O cycles every AO variant of the settings table and back") {
    Settings s;
    s.ao.variant = AoSettings::Variant::Off;  // from off, Shift+O wraps to the last variant
    std::set<std::string> seen;
    std::string first = toString(s.ao.variant);
    for (int i = 0; i < 9; ++i) {
        KeyAction a = handleKey('O', 0, s);
        CHECK(a.reconfigure);
        CHECK(a.message == std::string("ao=") + toString(s.ao.variant));
        seen.insert(toString(s.ao.variant));
    }
    CHECK(seen.size() == 9u);  // off + six screen-space variants (SPEC 12) + vbao + rtao (issue 25)
    CHECK(toString(s.ao.variant) == first);
    handleKey('O', key::ModShift, s);  // Shift goes backwards
    CHECK((s.ao.variant == AoSettings::Variant::Rtao));
}

TEST_CASE("view keys: SSR tracers, LPV toggle, directional AO cycle") {
    Settings s;
    s.ao.directional = AoSettings::Directional::Off;  // B steps off -> bent-normals -> s3ho
    std::set<std::string> tracers;
    for (int i = 0; i < 5; ++i) {
        handleKey('R', 0, s);
        tracers.insert(toString(s.ssr.tracer));
    }
    CHECK(tracers == std::set<std::string>{"auto", "off", "linear", "dda", "hiz"});
    CHECK((s.lpv.mode == Toggle::Auto));
    handleKey('L', 0, s);
    CHECK((s.lpv.mode == Toggle::On));
    handleKey('L', 0, s);
    CHECK((s.lpv.mode == Toggle::Off));
    handleKey('B', 0, s);
    CHECK((s.ao.directional == AoSettings::Directional::BentNormals));
    handleKey('G', 0, s);
    CHECK(!s.ao.halfResolution);
}

TEST_CASE("view keys: LPV iterations and AO samples step within their ranges") {
    Settings s;
    s.lpv.iterations = 2;
    handleKey(key::LeftBracket, 0, s);
    CHECK(s.lpv.iterations == 1);
    KeyAction a = handleKey(key::LeftBracket, 0, s);
    CHECK(s.lpv.iterations == 1);  // lower bound of lpv.iterations
    CHECK(a.reconfigure);
    s.lpv.iterations = 64;
    handleKey(key::RightBracket, 0, s);
    CHECK(s.lpv.iterations == 64);  // upper bound
    s.ao.samples = 16;
    handleKey(key::Period, 0, s);
    CHECK(s.ao.samples == 24);
    handleKey(key::Comma, 0, s);
    handleKey(key::Comma, 0, s);
    CHECK(s.ao.samples == 8);
    s.ao.samples = 10;  // between steps: up goes to the next step, down to the previous
    handleKey(key::Period, 0, s);
    CHECK(s.ao.samples == 16);
    s.ao.samples = 10;
    handleKey(key::Comma, 0, s);
    CHECK(s.ao.samples == 8);
    s.ao.samples = 64;
    handleKey(key::Period, 0, s);
    CHECK(s.ao.samples == 64);
}

TEST_CASE("view keys: host actions, and unknown keys change nothing") {
    Settings s;
    CHECK(handleKey(key::Tab, 0, s).imageStep == 1);
    CHECK(handleKey(key::Tab, key::ModShift, s).imageStep == -1);
    CHECK(handleKey('1', 0, s).finalImage);
    CHECK(handleKey('V', 0, s).viewStep == 1);
    CHECK(handleKey('P', 0, s).screenshot);
    CHECK(handleKey('J', 0, s).dumpConfig);
    CHECK(handleKey('H', 0, s).toggleHelp);
    CHECK(handleKey('Y', 0, s).toggleVsync);
    CHECK(handleKey(key::Escape, 0, s).quit);
    auto before = describe(s);
    KeyAction a = handleKey('Z', 0, s);
    CHECK(!a.reconfigure);
    CHECK(describe(s) == before);
    CHECK(keyHelp().size() >= 15u);
}

TEST_CASE("view: the camera/config dump replays through --config to the same settings") {
    Settings s;
    applySetting(s, "ao", "hbao");
    applySetting(s, "ao.samples", "24");
    applySetting(s, "lpv.iterations", "5");
    applySetting(s, "view", "court");
    Camera c;
    c.position = {1.25f, 2.5f, -3.75f};
    c.target = {0.5f, 1.0f, 0.0f};
    c.fovY = 0.9f;
    c.near = 0.02f;
    c.far = 321.0f;
    Settings replay;
    applyJsonConfig(replay, dumpConfig(s, c), "dump.json");
    CHECK((replay.ao.variant == AoSettings::Variant::Hbao));
    CHECK(replay.ao.samples == 24);
    CHECK(replay.lpv.iterations == 5);
    CHECK(replay.camera.view.empty());  // the explicit camera replaces the named view
    REQUIRE(replay.camera.position);
    CHECK(glm::length(*replay.camera.position - c.position) < 1e-5f);
    CHECK(glm::length(*replay.camera.target - c.target) < 1e-5f);
    CHECK(*replay.camera.fovDeg == doctest::Approx(glm::degrees(0.9f)).epsilon(1e-6));
    CHECK(*replay.camera.nearPlane == doctest::Approx(0.02f));
    CHECK(*replay.camera.farPlane == doctest::Approx(321.0f));
    // Every other key comes back unchanged.
    auto a = describe(s), b = describe(replay);
    for (auto& [k, v] : a)
        if (k.rfind("camera.", 0) != 0 && k != "view") CHECK_MESSAGE(b[k] == v, k);
}

