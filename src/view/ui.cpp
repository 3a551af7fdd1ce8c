#include "view/ui.h"

#include "compute/lib/view_shared.h"
#include "view/controls.h"

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace rtgi::view {

namespace {

// The family a key belongs to ("ao.radius" -> "ao"; camera/lights/post keys
// grouped), for the collapsing headers.
std::string family(const std::string& key) {
    std::string f = key.substr(0, key.find('.'));
    if (f == "camera" || f == "view") return "camera";
    if (f == "sun" || f == "sky" || f == "emissive" || f == "shadow") return "lights";
    if (f == "post" || f == "passes" || f == "floor") return "post";
    return f;
}

// One key's widget; returns the new value text when the user changed it.
bool keyWidget(const SettingKey& k, const KeyWidget& w, const std::string& current, std::string& out) {
    ImGui::PushID(k.key.c_str());
    bool changed = false;
    const char* label = k.key.c_str();
    switch (w.kind) {
        case KeyWidget::Kind::Toggle: {
            bool on = current == "on";
            if (ImGui::Checkbox(label, &on)) {
                out = on ? "on" : "off";
                changed = true;
            }
            break;
        }
        case KeyWidget::Kind::Choice: {
            if (ImGui::BeginCombo(label, current.c_str())) {
                for (auto& c : w.choices)
                    if (ImGui::Selectable(c.c_str(), c == current)) {
                        out = c;
                        changed = c != current;
                    }
                ImGui::EndCombo();
            }
            break;
        }
        case KeyWidget::Kind::Int: {
            int v = std::atoi(current.c_str());
            const int lo = int(w.lo), hi = int(w.hi);
            bool edited = w.logScale ? ImGui::DragInt(label, &v, std::max(1.0f, float(std::abs(v)) * 0.02f), lo, hi,
                                                      "%d", ImGuiSliderFlags_AlwaysClamp)
                                     : ImGui::SliderInt(label, &v, lo, hi, "%d", ImGuiSliderFlags_AlwaysClamp);
            if (edited && ImGui::IsItemDeactivatedAfterEdit()) edited = true;
            if (edited) {
                out = std::to_string(v);
                changed = out != current;
            }
            break;
        }
        case KeyWidget::Kind::Float: {
            float v = float(std::atof(current.c_str()));
            const float lo = float(w.lo), hi = float(w.hi);
            bool edited = w.logScale
                              ? ImGui::DragFloat(label, &v, std::max(1e-4f, std::abs(v) * 0.01f), lo, hi, "%.4g",
                                                 ImGuiSliderFlags_AlwaysClamp | ImGuiSliderFlags_Logarithmic)
                              : ImGui::SliderFloat(label, &v, lo, hi, "%.4g", ImGuiSliderFlags_AlwaysClamp);
            if (edited) {
                char buf[64];
                std::snprintf(buf, sizeof buf, "%.6g", double(v));
                out = buf;
                changed = out != current;
            }
            break;
        }
        case KeyWidget::Kind::Text: {
            char buf[256];
            std::snprintf(buf, sizeof buf, "%s", current.c_str());
            if (ImGui::InputText(label, buf, sizeof buf, ImGuiInputTextFlags_EnterReturnsTrue)) {
                out = buf;
                changed = out != current;
            }
            break;
        }
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s\n%s", k.doc.c_str(), k.values.c_str());
    ImGui::PopID();
    return changed;
}

}  // namespace

Ui::Ui(void* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini in the working directory
    ImGui::StyleColorsDark();
    ImGui::GetStyle().Alpha = 0.92f;
    ImGui_ImplGlfw_InitForOpenGL(static_cast<GLFWwindow*>(window), true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
}

Ui::~Ui() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

bool Ui::wantsKeyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }
bool Ui::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }

bool Ui::settingsPanel(Settings& settings, const Settings& defaults, ViewState& state) {
    bool changed = false;
    const auto current = describe(settings), def = describe(defaults);
    std::map<std::string, std::vector<const SettingKey*>> byFamily;
    std::vector<std::string> order;
    for (auto& k : settingKeys()) {
        std::string f = family(k.key);
        if (!byFamily.count(f)) order.push_back(f);
        byFamily[f].push_back(&k);
    }
    for (auto& f : order) {
        const bool open = f == "ao" || f == "lpv" || f == "post";
        if (!ImGui::CollapsingHeader(f.c_str(), open ? ImGuiTreeNodeFlags_DefaultOpen : 0)) continue;
        for (const SettingKey* k : byFamily[f]) {
            const std::string& cur = current.at(k->key);
            std::string v;
            // Reset to default: a small button, enabled when the value differs.
            const bool differs = cur != def.at(k->key);
            ImGui::PushID(("reset" + k->key).c_str());
            ImGui::BeginDisabled(!differs);
            const bool reset = ImGui::SmallButton("R");
            ImGui::EndDisabled();
            if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
                ImGui::SetTooltip("reset to %s", def.at(k->key).c_str());
            ImGui::PopID();
            ImGui::SameLine();
            if (reset) v = def.at(k->key);
            if (keyWidget(*k, widgetFor(*k), cur, v) || reset) {
                std::string err = applyPanelSetting(settings, k->key, v);  // the same path as --script
                state.message = err.empty() ? k->key + "=" + v : err;
                changed |= err.empty();
            }
        }
    }
    return changed;
}

bool Ui::build(Settings& settings, const Settings& defaults, ViewState& state, const std::vector<DisplayImage>& images,
               const TimingHistory& timings, const LiveReference& reference, const std::string& title) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    if (!state.showPanel) return false;
    bool changed = false;
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    const float w = std::min(340.0f, vp->WorkSize.x * 0.4f);
    ImGui::SetNextWindowPos(ImVec2(vp->WorkPos.x + vp->WorkSize.x - w, vp->WorkPos.y), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(w, vp->WorkSize.y), ImGuiCond_Always);
    ImGui::Begin("rtgi", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    ImGui::TextWrapped("%s", title.c_str());
    if (!state.message.empty()) ImGui::TextWrapped("%s", state.message.c_str());
    ImGui::PushItemWidth(-150.0f);

    if (ImGui::CollapsingHeader("image", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (ImGui::BeginCombo("shown", state.imageName.c_str())) {
            for (auto& im : images)
                if (ImGui::Selectable(im.name.c_str(), im.name == state.imageName)) state.imageName = im.name;
            ImGui::EndCombo();
        }
        ImGui::SliderFloat("exposure x", &state.present.exposure, 1.0f / 64.0f, 64.0f, "%.3g",
                           ImGuiSliderFlags_Logarithmic);
        const char* channels[] = {"rgb", "r", "g", "b", "a"};
        ImGui::Combo("channel", &state.present.channel, channels, 5);
    }

    if (ImGui::CollapsingHeader("reference", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::Checkbox("live reference", &state.liveReference);
        ImGui::SliderInt("samples / frame", &state.samplesPerFrame, 1, 64, "%d", ImGuiSliderFlags_Logarithmic);
        const char* layouts[] = {"off", "split", "reference (toggle)", "heat map", "side by side"};
        ImGui::Combo("layout", &state.compare, layouts, 5);
        if (state.compare == RTGI_VIEW_COMPARE_SPLIT) ImGui::SliderFloat("split", &state.present.split, 0.0f, 1.0f);
        if (state.compare == RTGI_VIEW_COMPARE_HEATMAP) {
            ImGui::Checkbox("auto scale (99th percentile)", &state.autoHeat);
            if (state.autoHeat) ImGui::Text("heat max %.4g", double(state.present.heatMax));
            else ImGui::SliderFloat("heat max", &state.present.heatMax, 1e-4f, 10.0f, "%.3g", ImGuiSliderFlags_Logarithmic);
        }
        const LiveErrors& e = reference.errors();
        if (state.liveReference) {
            ImGui::Text("%s reference: %d / %d samples%s", e.compared.c_str(), e.samples, e.targetSamples,
                        reference.converged() ? " (converged)" : "");
            if (e.valid) {
                if (e.compared == "ao")  // relative RMSE divides by the reference: meaningless for AO
                    ImGui::Text("RMSE %.4g   bias %.3g", e.metrics.rmse, e.metrics.bias);
                else
                    ImGui::Text("RMSE %.4g   relative RMSE %.4g", e.metrics.rmse, e.metrics.relRmse);
                ImGui::Text("SSIM %.4f   PSNR %.2f dB", e.metrics.ssim, e.metrics.psnr);
                ImGui::Text("reference noise (RMS SE) %.4g", e.referenceNoise);
                const RmseUncertainty& u = e.uncertainty;
                ImGui::Text("RMSE debiased %.4g +- %.2g (95 %%: %.4g .. %.4g)", u.rmseDebiased, 0.5 * (u.high - u.low),
                            u.low, u.high);
                if (e.referenceNoise > 0.5 * e.metrics.rmse)
                    ImGui::TextWrapped("the reference's noise is still comparable to the error: let it converge");
                for (const LiveErrors::Gain& g : e.gains) {
                    ImGui::Text("%s gain %+.3f (RMSE without it %.4g)", g.technique.c_str(), g.gain, g.rmseWithout);
                    if (g.gain < 0.0)
                        ImGui::TextWrapped("the %s makes this view worse than switching it off", g.technique.c_str());
                }
            }
        }
    }

    if (ImGui::CollapsingHeader("temporal", ImGuiTreeNodeFlags_DefaultOpen)) {
        TemporalState& t = state.temporal;
        if (t.path) {
            ImGui::Text("path %s: frame %d / %d, t = %.3f s", t.pathName.c_str(), t.frame, t.frames - 1, t.time);
            if (ImGui::Button(t.playing ? "pause" : "play")) t.playToggled = true;
            ImGui::SameLine();
            int f = t.frame;
            if (ImGui::SliderInt("frame", &f, 0, t.frames - 1, "%d", ImGuiSliderFlags_AlwaysClamp) && f != t.frame)
                t.scrubTo = f;
        } else {
            ImGui::TextWrapped("no --path: the camera is yours (rtgi-view --path NAME plays one)");
        }
        ImGui::Checkbox("reset history every frame (X)", &t.resetHistory);
        for (auto& c : t.disoccluded)
            ImGui::Text("%-16s %8.0f disoccluded (%.2f %%)", c.pass.c_str(), c.disoccluded,
                        c.pixels > 0 ? 100.0 * c.disoccluded / c.pixels : 0.0);
        if (t.disoccluded.empty()) ImGui::TextWrapped("no screen-space temporal filter in this frame");
        if (t.haveChange) ImGui::Text("frame-to-frame change (RMS, final) %.4g", t.change);
    }

    if (ImGui::CollapsingHeader("GPU timings", ImGuiTreeNodeFlags_DefaultOpen)) {
        // Execution order, frame total last; each row: median and the rolling graph with its median line.
        for (auto& name : timings.order()) {
            const auto& d = timings.samples(name);
            if (d.empty()) continue;
            std::vector<float> v(d.begin(), d.end());
            const float med = float(timings.median(name));
            const float top = std::max(*std::max_element(v.begin(), v.end()), 1e-6f);
            ImGui::Text("%-22s %8.3f ms", name.c_str(), double(med));
            ImGui::PushID(name.c_str());
            ImVec2 pos = ImGui::GetCursorScreenPos();
            const ImVec2 size(ImGui::GetContentRegionAvail().x, 22.0f);
            ImGui::PlotLines("##t", v.data(), int(v.size()), 0, nullptr, 0.0f, top * 1.1f, size);
            const float y = pos.y + size.y * (1.0f - med / (top * 1.1f));
            ImGui::GetWindowDrawList()->AddLine(ImVec2(pos.x, y), ImVec2(pos.x + size.x, y), IM_COL32(255, 200, 0, 200));
            ImGui::PopID();
        }
    }

    if (ImGui::CollapsingHeader("settings", ImGuiTreeNodeFlags_DefaultOpen)) changed = settingsPanel(settings, defaults, state);
    if (ImGui::CollapsingHeader("keys"))
        for (auto& line : keyHelp()) ImGui::TextUnformatted(line.c_str());
    ImGui::PopItemWidth();
    ImGui::End();
    return changed;
}

void Ui::render() {
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

}  // namespace rtgi::view
