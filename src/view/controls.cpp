#include "view/controls.h"

#include <glm/gtc/constants.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>

namespace rtgi::view {

namespace {

// Next (or previous) of a settings key's allowed values, through the key
// table so the viewer never keeps its own list of variants.
std::string cycle(Settings& s, const std::string& key, const std::vector<std::string>& values, int dir) {
    std::string cur = describe(s).at(key);
    auto it = std::find(values.begin(), values.end(), cur);
    int n = int(values.size());
    int i = it == values.end() ? 0 : (int(it - values.begin()) + dir + n) % n;
    applySetting(s, key, values[std::size_t(i)]);
    return key + "=" + values[std::size_t(i)];
}

std::vector<std::string> allowedValues(const std::string& key) {
    for (auto& k : settingKeys())
        if (k.key == key) {
            std::vector<std::string> v;
            std::string cur;
            for (char c : k.values + "|") {
                if (c == '|') {
                    v.push_back(cur);
                    cur.clear();
                } else {
                    cur += c;
                }
            }
            return v;
        }
    return {};
}

}  // namespace

const std::vector<int>& aoSampleSteps() {
    static const std::vector<int> steps{4, 8, 16, 24, 32, 48, 64};
    return steps;
}

KeyAction handleKey(int k, int mods, Settings& s) {
    KeyAction a;
    int dir = (mods & key::ModShift) ? -1 : 1;
    auto change = [&](std::string msg) {
        a.reconfigure = true;
        a.message = std::move(msg);
    };
    switch (k) {
        case key::Escape: a.quit = true; break;
        case 'H':
        case key::F1: a.toggleHelp = true; break;
        case key::Tab: a.imageStep = dir; break;
        case key::PageDown: a.imageStep = 1; break;
        case key::PageUp: a.imageStep = -1; break;
        case '1': a.finalImage = true; break;
        case 'V': a.viewStep = dir; break;
        case 'C': a.resetCamera = true; break;
        case 'P':
        case key::F12: a.screenshot = true; break;
        case 'J': a.dumpConfig = true; break;
        case 'Y': a.toggleVsync = true; break;
        case key::Space: a.playPause = true; break;
        case key::Right: a.frameStep = (mods & key::ModShift) ? 10 : 1; break;
        case key::Left: a.frameStep = (mods & key::ModShift) ? -10 : -1; break;
        case key::Home: a.pathHome = true; break;
        case 'X': a.toggleHistoryReset = true; break;
        case 'N': change(cycle(s, "lpv.snap", allowedValues("lpv.snap"), dir)); break;
        case 'L': change(cycle(s, "lpv", allowedValues("lpv"), dir)); break;
        case 'O': change(cycle(s, "ao", allowedValues("ao"), dir)); break;
        case 'R': change(cycle(s, "ssr", allowedValues("ssr"), dir)); break;
        case 'B': change(cycle(s, "ao.directional", allowedValues("ao.directional"), dir)); break;
        case 'T': change(cycle(s, "lpv.path", allowedValues("lpv.path"), dir)); break;
        case 'G': change(cycle(s, "ao.resolution", allowedValues("ao.resolution"), dir)); break;
        case 'M': change(cycle(s, "reference", allowedValues("reference"), dir)); break;
        case key::LeftBracket:
        case key::RightBracket: {
            int it = std::clamp(s.lpv.iterations + (k == key::RightBracket ? 1 : -1), 1, 64);
            applySetting(s, "lpv.iterations", std::to_string(it));
            change("lpv.iterations=" + std::to_string(it));
            break;
        }
        case key::Comma:
        case key::Period: {
            const auto& steps = aoSampleSteps();
            // The next step above / below the current count (which may lie between steps).
            int cur = s.ao.samples, next = cur;
            if (k == key::Period) {
                auto it = std::upper_bound(steps.begin(), steps.end(), cur);
                next = it == steps.end() ? steps.back() : *it;
            } else {
                auto it = std::lower_bound(steps.begin(), steps.end(), cur);
                next = it == steps.begin() ? steps.front() : *(it - 1);
            }
            applySetting(s, "ao.samples", std::to_string(next));
            change("ao.samples=" + std::to_string(next));
            break;
        }
        default: break;
    }
    return a;
}

std::vector<std::string> keyHelp() {
    return {
        "W A S D / Q E   move / down up (Shift: x5)",
        "right mouse     look around",
        "Tab, Shift+Tab  next / previous image",
        "PgDn, PgUp      next / previous image",
        "1               final image",
        "L               LPV auto/on/off",
        "T               LPV compute/raster",
        "[ ]             LPV iterations -/+",
        "O, Shift+O      next / previous AO variant",
        ", .             AO samples -/+",
        "B               AO directional off/bent/s3ho",
        "G               AO full/half resolution",
        "R, Shift+R      next / previous SSR tracer",
        "M               reference off/ao/indirect/full",
        "N               LPV cascade snapping on/off (lpv.snap)",
        "Space           --path: play / pause",
        "Left, Right     --path: step a frame (Shift: 10)",
        "Home            --path: frame 0",
        "X               temporal history: live reprojection / reset every frame",
        "V, Shift+V      next / previous named view",
        "C               scene camera",
        "P or F12        screenshot (PNG)",
        "J               dump camera+config JSON",
        "Y               vsync on/off",
        "H or F1         hide / show the panel",
        "Esc             quit",
    };
}

std::string dumpConfig(const Settings& settings, const Camera& c) {
    nlohmann::json j = nlohmann::json::object();
    for (auto& [k, v] : describe(settings)) j[k] = v;
    j["view"] = "";
    j["camera.position"] = {c.position.x, c.position.y, c.position.z};
    j["camera.target"] = {c.target.x, c.target.y, c.target.z};
    j["camera.fov"] = glm::degrees(c.fovY);
    j["camera.near"] = c.near;
    j["camera.far"] = c.far;
    return j.dump(2) + "\n";
}

}  // namespace rtgi::view
