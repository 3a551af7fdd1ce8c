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
