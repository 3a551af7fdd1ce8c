#pragma once
// The window-free half of rtgi-view's ImGui panels (unit-tested in
// tests/unit/test_view_panel.cpp): the widget each configuration key gets,
// derived from the settings table; the one function that applies an edit
// (called by the widgets and by --script, so the test drives the panel's code
// path); the rolling per-pass timing history; the --script format.
#include "render/settings.h"

#include <deque>
#include <map>
#include <string>
#include <vector>

namespace rtgi::view {

// How a key is edited, from its SettingKey::values text: "on|off" -> Toggle,
// "a|b|c" -> Choice, "lo..hi" -> Int or Float with that range, anything with
// "auto", vectors or free text -> Text (typed in, validated by the table).
struct KeyWidget {
    enum class Kind { Toggle, Choice, Int, Float, Text } kind = Kind::Text;
    std::vector<std::string> choices;
    double lo = 0, hi = 0;
    bool logScale = false;  // range spans many decades: a logarithmic slider
};
KeyWidget widgetFor(const SettingKey& key);

// The edit every panel widget makes: key=value through the settings table.
// Returns "" on success, else the table's one-sentence error (settings unchanged).
std::string applyPanelSetting(Settings& settings, const std::string& key, const std::string& value);
// Keys whose value differs between two settings (what a reconfigure changes).
std::vector<std::string> changedKeys(const Settings& a, const Settings& b);

// The last `capacity` frames of per-pass GPU milliseconds, passes kept in
// execution order with the frame total last.
class TimingHistory {
public:
    explicit TimingHistory(std::size_t capacity = 240) : capacity_(capacity) {}
    // One frame: (pass, ms) in execution order; "frame" (the total) is moved last.
    void add(const std::vector<std::pair<std::string, double>>& frame);
    // Passes in display order.
    const std::vector<std::string>& order() const { return order_; }
    const std::deque<float>& samples(const std::string& pass) const;
    double median(const std::string& pass) const;
    void clear();

private:
    std::size_t capacity_;
    std::vector<std::string> order_;
    std::map<std::string, std::deque<float>> samples_;
};

// --script FILE: one action per line, "FRAME VERB ARGS..." ('#' comments):
//   set KEY VALUE | image NAME | exposure X | channel rgb|r|g|b|a |
//   reference on|off | compare off|split|side|toggle|heatmap | split X |
//   screenshot FILE (the view without the panel) | window FILE (with it) | panel on|off |
//   path play|pause|home|next|prev (--path playback, the keys' actions) | history live|reset (key X)
struct ScriptAction {
    int frame = 0;
    std::string verb;
    std::vector<std::string> args;
};
// Throws ConfigError naming the file and line on a malformed line.
std::vector<ScriptAction> parseScript(const std::string& text, const std::string& source);

}  // namespace rtgi::view
