#pragma once
// rtgi-view's Dear ImGui panels (docs/viewer.md): settings generated from the
// settings table, per-pass GPU timings with rolling graphs, image selection
// with exposure and channel, and the live reference comparison. Compiled into
// rtgi-view only (rtgi-bench links neither GLFW nor ImGui).
#include "view/display.h"
#include "view/live_reference.h"
#include "view/panel_model.h"

#include <string>
#include <vector>

namespace rtgi::view {

// The temporal section (issue 23): --path playback and the live temporal numbers.
struct TemporalState {
    bool path = false;            // a --path is loaded
    std::string pathName;
    int frame = 0, frames = 1;
    double time = 0, fps = 30;
    bool playing = false;
    int scrubTo = -1;             // set by the panel's slider (the host scrubs and clears it)
    bool playToggled = false;     // the panel's play / pause button
    bool resetHistory = false;    // X: a reset (cut) every frame instead of live reprojection
    struct FilterCount {
        std::string pass;
        double disoccluded = 0, pixels = 0;  // the filter's count and its image's pixels (0: unknown)
    };
    std::vector<FilterCount> disoccluded;  // per screen-space temporal filter of the frame
    bool haveChange = false;
    double change = 0;            // RMS change of the final image since the last frame
};

// What the panels edit besides the settings.
struct ViewState {
    std::string imageName = "final";
    PresentOptions present;
    bool liveReference = false;
    int compare = 1;  // RTGI_VIEW_COMPARE_* while the live reference is on
    bool autoHeat = true;     // heat map scale = the live 99th percentile of the error
    int samplesPerFrame = 4;  // of the live reference (more: faster convergence, slower frames)
    bool showPanel = true;
    std::string message;
    TemporalState temporal;
};

class Ui {
public:
    // `window`: the GLFWwindow (WindowHost::nativeHandle()).
    explicit Ui(void* window);
    ~Ui();
    Ui(const Ui&) = delete;
    Ui& operator=(const Ui&) = delete;

    bool wantsKeyboard() const;
    bool wantsMouse() const;
    // Builds this frame's panels; returns true when `settings` changed (the
    // caller reconfigures). `defaults`: what the reset buttons restore.
    bool build(Settings& settings, const Settings& defaults, ViewState& state, const std::vector<DisplayImage>& images,
               const TimingHistory& timings, const LiveReference& reference, const std::string& title);
    void render();

private:
    bool settingsPanel(Settings& settings, const Settings& defaults, ViewState& state);
};

}  // namespace rtgi::view
