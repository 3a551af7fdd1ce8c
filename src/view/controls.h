#pragma once
// Key handling of rtgi-view, without a window: a key press changes the
// settings (each change asks for Renderer::configure) or asks the host for an
// action. Key codes are GLFW's (letters and digits are their ASCII upper-case
// codes; window_host.cpp static_asserts the named ones). Unit-tested in
// tests/unit/test_view_controls.cpp.
#include "render/settings.h"
#include "scene/scene.h"

#include <string>
#include <vector>

namespace rtgi::view {

namespace key {
constexpr int Space = 32, Comma = 44, Period = 46, LeftBracket = 91, RightBracket = 93;
constexpr int Escape = 256, Tab = 258, Right = 262, Left = 263, PageUp = 266, PageDown = 267, Home = 268, F1 = 290,
              F12 = 301;
constexpr int ModShift = 0x0001;  // GLFW_MOD_SHIFT
}  // namespace key

struct KeyAction {
    bool reconfigure = false;  // settings changed: Renderer::configure, camera cut
    int imageStep = 0;         // +-1: next / previous displayed image
    bool finalImage = false;   // show the final image
    int viewStep = 0;          // +-1: next / previous named view
    bool resetCamera = false;  // back to the scene's camera
    bool screenshot = false, dumpConfig = false, toggleHelp = false, toggleVsync = false, quit = false;
    // --path playback (view/path_player.h): Space, Left / Right, Home.
    bool playPause = false, pathHome = false;
    int frameStep = 0;
    bool toggleHistoryReset = false;  // X: live reprojection <-> a reset history every frame
    std::string message;       // one line for the overlay ("ao=hbao")
};

// Applies a key press (with GLFW modifier bits) to `settings`.
KeyAction handleKey(int keyCode, int mods, Settings& settings);

// The key help shown with H (one line per binding).
std::vector<std::string> keyHelp();

// Sample counts the AO sample keys step through (seed 003 used 8/16/24).
const std::vector<int>& aoSampleSteps();

// The configuration that `rtgi-bench --config FILE` replays: every key with
// its effective value, the camera keys set to `camera` and `view` cleared.
std::string dumpConfig(const Settings& settings, const Camera& camera);

}  // namespace rtgi::view
