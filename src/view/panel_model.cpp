#include "view/panel_model.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

namespace rtgi::view {

namespace {

bool parseNumber(const std::string& s, double& out) {
    char* end = nullptr;
    out = std::strtod(s.c_str(), &end);
    return !s.empty() && *end == '\0' && std::isfinite(out);
}

bool isIntegerText(const std::string& s) {
    return !s.empty() && s.find_first_of(".eE") == std::string::npos;
}

}  // namespace

KeyWidget widgetFor(const SettingKey& key) {
    KeyWidget w;
    const std::string& v = key.values;
    if (v == "on|off") {
        w.kind = KeyWidget::Kind::Toggle;
        return w;
    }
    auto dots = v.find("..");
    if (dots != std::string::npos && v.find('|') == std::string::npos) {
        double lo = 0, hi = 0;
        std::string a = v.substr(0, dots), b = v.substr(dots + 2);
        if (parseNumber(a, lo) && parseNumber(b, hi) && lo < hi) {
            w.kind = isIntegerText(a) && isIntegerText(b) ? KeyWidget::Kind::Int : KeyWidget::Kind::Float;
            w.lo = lo;
            w.hi = hi;
            // Ranges like 0..1e6 or 1e-12..1e12: a linear slider cannot hit small values.
            w.logScale = hi > 1000.0 * std::max(std::abs(lo), 1.0) || (lo > 0 && hi / lo > 1e4);
            return w;
        }
    }
    // A closed list: "a|b|c", with "word1..word6" expanded (ao.radius_mode).
    if (v.find('|') != std::string::npos) {
        std::vector<std::string> choices;
        bool closed = true;
        std::stringstream ss(v);
        std::string c;
        while (std::getline(ss, c, '|')) {
            if (c.empty() || c == "path" || c == "name" || c.find_first_of(" ,\"(") != std::string::npos) closed = false;
            auto d = c.find("..");
            if (d == std::string::npos) {
                choices.push_back(c);
                continue;
            }
            // "dynamic1..dynamic6": same prefix, integer suffixes.
            std::string a = c.substr(0, d), b = c.substr(d + 2);
            auto digits = [](const std::string& t) { return t.find_last_not_of("0123456789") + 1; };
            std::size_t pa = digits(a), pb = digits(b);
            if (pa == 0 || pb == 0 || pa == a.size() || pb == b.size() || a.substr(0, pa) != b.substr(0, pb)) {
                closed = false;  // a numeric range next to words ("auto|0.5..175"): typed in
                continue;
            }
            for (int i = std::atoi(a.c_str() + pa); i <= std::atoi(b.c_str() + pb); ++i)
                choices.push_back(a.substr(0, pa) + std::to_string(i));
        }
        if (closed) {
            w.kind = KeyWidget::Kind::Choice;
            w.choices = choices;
            return w;
        }
    }
    w.kind = KeyWidget::Kind::Text;
    return w;
}

std::string applyPanelSetting(Settings& settings, const std::string& key, const std::string& value) {
    Settings trial = settings;
    try {
        applySetting(trial, key, value);
    } catch (const ConfigError& e) {
        return e.what();
    }
    settings = trial;
    return "";
}

std::vector<std::string> changedKeys(const Settings& a, const Settings& b) {
    std::vector<std::string> out;
    auto da = describe(a), db = describe(b);
    for (auto& [k, v] : da)
        if (db[k] != v) out.push_back(k);
    return out;
}

void TimingHistory::add(const std::vector<std::pair<std::string, double>>& frame) {
    std::vector<std::string> order;
    double total = -1;
    for (auto& [name, ms] : frame) {
        if (name == "frame") {
            total = ms;
            continue;
        }
        order.push_back(name);
        auto& d = samples_[name];
        d.push_back(float(ms));
        while (d.size() > capacity_) d.pop_front();
    }
    if (total >= 0) {
        order.push_back("frame");
        auto& d = samples_["frame"];
        d.push_back(float(total));
        while (d.size() > capacity_) d.pop_front();
    }
    // Passes that left the frame (a reconfigure) drop out of the display.
    if (order != order_) {
        std::set<std::string> keep(order.begin(), order.end());
        for (auto it = samples_.begin(); it != samples_.end();)
            it = keep.count(it->first) ? std::next(it) : samples_.erase(it);
        order_ = order;
    }
}

const std::deque<float>& TimingHistory::samples(const std::string& pass) const {
    static const std::deque<float> none;
    auto it = samples_.find(pass);
    return it == samples_.end() ? none : it->second;
}

double TimingHistory::median(const std::string& pass) const {
    std::vector<float> v(samples(pass).begin(), samples(pass).end());
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? double(v[n / 2]) : 0.5 * (double(v[n / 2 - 1]) + double(v[n / 2]));
}

void TimingHistory::clear() {
    order_.clear();
    samples_.clear();
}

std::vector<ScriptAction> parseScript(const std::string& text, const std::string& source) {
    static const std::map<std::string, std::size_t> arity = {
        {"set", 2},     {"image", 1},  {"exposure", 1},   {"channel", 1}, {"reference", 1},
        {"compare", 1}, {"split", 1},  {"screenshot", 1}, {"window", 1},  {"panel", 1},
        {"path", 1},    {"history", 1}};
    std::vector<ScriptAction> out;
    std::stringstream in(text);
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        if (auto h = line.find('#'); h != std::string::npos) line.resize(h);
        std::stringstream ls(line);
        std::string frame;
        if (!(ls >> frame)) continue;
        auto fail = [&](const std::string& why) {
            throw ConfigError(source + ":" + std::to_string(lineNo) + ": " + why);
        };
        ScriptAction a;
        char* end = nullptr;
        long f = std::strtol(frame.c_str(), &end, 10);
        if (*end || f < 0 || f > 1000000) fail("'" + frame + "' is not a frame number");
        a.frame = int(f);
        if (!(ls >> a.verb)) fail("missing action after the frame number");
        auto it = arity.find(a.verb);
        if (it == arity.end())
            fail("unknown action '" + a.verb + "' (set image exposure channel reference compare split screenshot window panel path history)");
        std::string arg;
        while (ls >> arg) a.args.push_back(arg);
        if (a.args.size() != it->second)
            fail("'" + a.verb + "' takes " + std::to_string(it->second) + " argument(s), got " + std::to_string(a.args.size()));
        out.push_back(a);
    }
    std::stable_sort(out.begin(), out.end(), [](const ScriptAction& x, const ScriptAction& y) { return x.frame < y.frame; });
    return out;
}

}  // namespace rtgi::view
