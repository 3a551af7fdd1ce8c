// rtgi-view's path playback without a window (view/path_player.h): play,
// pause, step and scrub over a path's frames, which frames continue the last
// one (histories kept) and which jump (a cut), and the keys that drive it.
#include "view/controls.h"
#include "view/path_player.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>

using namespace rtgi;
using namespace rtgi::view;

TEST_CASE("view path: playing shows one path frame per rendered frame at t = i / fps and pauses on the last") {
    PathPlayer p(4, 30.0);  // frames 0..3
    CHECK(p.frame() == 0);
    CHECK_FALSE(p.playing());
    CHECK(p.jumped());  // nothing rendered yet: the first frame starts the histories
    p.rendered();
    p.advance();  // paused: stays
    CHECK(p.frame() == 0);
    CHECK_FALSE(p.jumped());  // the same frame again continues
    p.togglePlay();
    CHECK(p.playing());
    for (int expect = 1; expect <= 3; ++expect) {
        p.advance();
        CHECK(p.frame() == expect);
        CHECK(p.time() == doctest::Approx(expect / 30.0));
        CHECK_FALSE(p.jumped());  // the next path frame continues the last rendered one
        p.rendered();
    }
    p.advance();  // at the last frame: pauses there
    CHECK(p.frame() == 3);
    CHECK_FALSE(p.playing());
    p.togglePlay();  // play from the end restarts at frame 0: a jump
    CHECK(p.playing());
    CHECK(p.frame() == 0);
    CHECK(p.jumped());
}

TEST_CASE("view path: steps and scrubbing pause and clamp to the path; a step back or a scrub is a jump") {
    PathPlayer p(10, 24.0);
    p.rendered();
    p.togglePlay();
    p.step(1);
    CHECK_FALSE(p.playing());
    CHECK(p.frame() == 1);
    CHECK_FALSE(p.jumped());
    p.rendered();
    p.step(-1);
    CHECK(p.frame() == 0);
    CHECK(p.jumped());
    p.step(-5);  // clamped at the first frame
    CHECK(p.frame() == 0);
    p.step(25);  // clamped at the last
    CHECK(p.frame() == 9);
    p.scrub(-3);
    CHECK(p.frame() == 0);
    p.scrub(4);
    CHECK(p.frame() == 4);
    CHECK(p.time() == doctest::Approx(4.0 / 24.0));
    p.scrub(1000);
    CHECK(p.frame() == 9);
    p.rendered();
    p.home();
    CHECK(p.frame() == 0);
    CHECK_FALSE(p.playing());
    CHECK(p.jumped());
    PathPlayer one(1, 30.0);  // a one-frame path: every step stays on frame 0
    one.step(1);
    CHECK(one.frame() == 0);
    one.togglePlay();
    one.advance();
    CHECK(one.frame() == 0);
    CHECK_FALSE(one.playing());
    CHECK_THROWS(PathPlayer(0, 30.0));
    CHECK_THROWS(PathPlayer(5, 0.0));
}

TEST_CASE("view path: the frame-to-frame change is the RMS of the difference over finite pixels") {
    FloatImage a, b;
    a.width = b.width = 2;
    a.height = b.height = 1;
    a.channels = b.channels = 4;
    a.data = {0.1f, 0.2f, 0.3f, 1.0f, 0.5f, 0.5f, 0.5f, 1.0f};
    b.data = {0.4f, 0.2f, 0.3f, 0.0f, 0.5f, 0.1f, 0.5f, 1.0f};  // alpha ignored (3 channels)
    // Differences 0.3, 0, 0 and 0, -0.4, 0: sqrt((0.09 + 0.16) / 6).
    REQUIRE(rmsChange(a, b, 3));
    CHECK(*rmsChange(a, b, 3) == doctest::Approx(std::sqrt(0.25 / 6.0)).epsilon(1e-6));
    CHECK(*rmsChange(a, a, 3) == 0.0);
    b.data[5] = std::numeric_limits<float>::quiet_NaN();  // the second pixel drops out
    CHECK(*rmsChange(a, b, 3) == doctest::Approx(std::sqrt(0.09 / 3.0)).epsilon(1e-6));
    FloatImage c = a;
    c.width = 1;
    c.data.resize(4);
    CHECK_FALSE(rmsChange(a, c, 3));
}

TEST_CASE("view keys: Space, Left/Right, Home drive the path; X the history; N toggles lpv.snap") {
    Settings s;
    CHECK(handleKey(key::Space, 0, s).playPause);
    CHECK(handleKey(key::Right, 0, s).frameStep == 1);
    CHECK(handleKey(key::Left, 0, s).frameStep == -1);
    CHECK(handleKey(key::Right, key::ModShift, s).frameStep == 10);
    CHECK(handleKey(key::Left, key::ModShift, s).frameStep == -10);
    CHECK(handleKey(key::Home, 0, s).pathHome);
    KeyAction x = handleKey('X', 0, s);
    CHECK(x.toggleHistoryReset);
    CHECK_FALSE(x.reconfigure);  // the history mode is the host's, not a setting
    REQUIRE(s.lpv.snap);
    KeyAction n = handleKey('N', 0, s);
    CHECK(n.reconfigure);
    CHECK_FALSE(s.lpv.snap);
    CHECK(n.message == "lpv.snap=off");
    handleKey('N', 0, s);
    CHECK(s.lpv.snap);
}
