#include "bench/sweep_spec.h"

#include "bench/results_csv.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <sstream>

namespace rtgi {

namespace {

using Assignments = std::vector<std::pair<std::string, std::string>>;

// Pseudo-keys an axis may set besides the settings table.
constexpr const char* kResolutionKey = "resolution";

std::string fail(const std::string& source, const std::string& what) { return source + ": " + what; }

[[noreturn]] void wrongType(const std::string& source, const std::string& key, const char* expected,
                            const nlohmann::json& v) {
    throw ConfigError(fail(source, "'" + key + "': expected " + expected + ", found " + jsonTypeWord(v)));
}
// Typed members with the file and key named on a wrong type (no raw
// nlohmann type_error text reaches the user).
double numberOf(const nlohmann::json& o, const std::string& k, const std::string& source, const std::string& path) {
    const auto& v = o.at(k);
    if (!v.is_number()) wrongType(source, path, "a number", v);
    double x = v.get<double>();
    if (!std::isfinite(x)) wrongType(source, path, "a finite number", v);
    return x;
}
std::string stringOr(const nlohmann::json& o, const std::string& k, const std::string& def, const std::string& source,
                     const std::string& path) {
    if (!o.contains(k)) return def;
    if (!o[k].is_string()) wrongType(source, path, "a string", o[k]);
    return o[k].get<std::string>();
}
bool boolOr(const nlohmann::json& o, const std::string& k, bool def, const std::string& source) {
    if (!o.contains(k)) return def;
    if (!o[k].is_boolean()) wrongType(source, k, "true or false", o[k]);
    return o[k].get<bool>();
}
int intOr(const nlohmann::json& o, const std::string& k, int def, const std::string& source) {
    if (!o.contains(k)) return def;
    const auto& v = o[k];
    if (!v.is_number_integer() || v.get<double>() < -1e9 || v.get<double>() > 1e9)
        wrongType(source, k, "an integer", v);
    return v.get<int>();
}

// Values a {"from", "to", "times"|"step"} range would generate, computed
// before generating them (sweep size is checked before expansion).
constexpr std::size_t kMaxAxisValues = 10000;
constexpr std::size_t kMaxConfigurations = 1000000;

// JSON value -> the string form --set takes. Numbers print with 9 significant
// digits, so 0.5 and 0.50 give the same configuration id.
std::string valueString(const nlohmann::json& v, const std::string& source, const std::string& key) {
    if (v.is_string()) return v.get<std::string>();
    if (v.is_boolean()) return v.get<bool>() ? "on" : "off";
    if (v.is_number_integer()) return std::to_string(v.get<long long>());
    if (v.is_number()) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.9g", v.get<double>());
        return buf;
    }
    if (v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number()) {
        std::string s;
        for (auto& c : v) s += (s.empty() ? "" : ",") + valueString(c, source, key);
        return s;
    }
    throw ConfigError(fail(source, "value of '" + key + "' must be a string, number, boolean or [x,y,z]"));
}

// Values of one key: a list, or {"from": a, "to": b, "times": f} (geometric)
// or {"from": a, "to": b, "step": d} (arithmetic), both inclusive of `to`.
std::vector<std::string> axisValues(const nlohmann::json& v, const std::string& source, const std::string& key) {
    std::vector<std::string> out;
    if (v.is_array()) {
        if (v.size() > kMaxAxisValues)
            throw ConfigError(fail(source, "axis '" + key + "' lists " + std::to_string(v.size()) + " values, more than " +
                                               std::to_string(kMaxAxisValues)));
        for (auto& x : v) out.push_back(valueString(x, source, key));
    } else if (v.is_object() && v.contains("from") && v.contains("to") && (v.contains("times") || v.contains("step"))) {
        double from = numberOf(v, "from", source, key + ".from"), to = numberOf(v, "to", source, key + ".to");
        bool geometric = v.contains("times");
        double f = geometric ? numberOf(v, "times", source, key + ".times") : numberOf(v, "step", source, key + ".step");
        if (geometric ? !(f > 1.0 && from > 0.0) : !(f > 0.0))
            throw ConfigError(fail(source, "axis '" + key + "': 'times' must exceed 1 with 'from' > 0, 'step' must be > 0"));
        double count = to < from ? 0.0
                       : geometric ? std::floor(std::log(to / from) / std::log(f) + 1e-9) + 1.0
                                   : std::floor((to - from) / f + 1e-9) + 1.0;
        if (count > double(kMaxAxisValues))
            throw ConfigError(fail(source, "axis '" + key + "': the range has about " + std::to_string(std::llround(count)) +
                                               " values, more than " + std::to_string(kMaxAxisValues)));
        bool integers = v["from"].is_number_integer() && v["to"].is_number_integer();
        // Relative slack so that 0.1 + 0.1 + 0.1 still reaches a `to` of 0.3.
        for (double x = from; x <= to * (1 + 1e-9) && out.size() < kMaxAxisValues; x = geometric ? x * f : x + f)
            out.push_back(valueString(integers ? nlohmann::json(std::llround(x)) : nlohmann::json(x), source, key));
    } else {
        out.push_back(valueString(v, source, key));
    }
    if (out.empty()) throw ConfigError(fail(source, "axis '" + key + "' has no values"));
    return out;
}

// One axis -> its list of assignment sets.
std::vector<Assignments> expandAxis(const nlohmann::json& axis, const std::string& source) {
    std::vector<Assignments> out;
    if (axis.is_array()) {  // explicit list of cases
        for (auto& c : axis) {
            if (!c.is_object()) throw ConfigError(fail(source, "an explicit axis must be a list of objects"));
            Assignments a;
            for (auto& [k, v] : c.items()) a.emplace_back(k, valueString(v, source, k));
            out.push_back(a);
        }
    } else if (axis.is_object() && !axis.empty()) {  // one key, or several zipped
        std::vector<std::pair<std::string, std::vector<std::string>>> cols;
        for (auto& [k, v] : axis.items()) cols.emplace_back(k, axisValues(v, source, k));
        for (auto& c : cols)
            if (c.second.size() != cols.front().second.size())
                throw ConfigError(fail(source, "zipped axis keys '" + cols.front().first + "' and '" + c.first +
                                                   "' have different numbers of values"));
        for (std::size_t i = 0; i < cols.front().second.size(); ++i) {
            Assignments a;
            for (auto& c : cols) a.emplace_back(c.first, c.second[i]);
            out.push_back(a);
        }
    } else {
        throw ConfigError(fail(source, "each axis must be an object {key: [values]} or a list of objects"));
    }
    if (out.empty()) throw ConfigError(fail(source, "an axis has no entries"));
    return out;
}

glm::ivec2 parseResolution(const std::string& s, const std::string& source) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' || w < 1 || h < 1 || w > 16384 ||
        h > 16384)
        throw ConfigError(fail(source, "resolution '" + s + "': expected WxH with 1..16384, e.g. 1920x1080"));
    return {w, h};
}

std::string defaultLabel(const std::vector<std::string>& scenes) {
    // The last scene is the interesting one (a model on builtin:plane).
    std::string s = scenes.back();
    if (s.rfind("builtin:", 0) == 0) return s.substr(8);
    auto slash = s.find_last_of('/');
    if (slash != std::string::npos) s = s.substr(slash + 1);
    auto dot = s.find_last_of('.');
    return dot == std::string::npos ? s : s.substr(0, dot);
}

struct SceneEntry {
    std::vector<std::string> scenes;
    std::string label;
    std::vector<std::string> views;  // "" = the scene's own camera
    Assignments set;                 // per-scene settings (e.g. an AO radius fitted to the scene's scale)
};

std::vector<SceneEntry> parseScenes(const nlohmann::json& j, const std::string& source) {
    if (!j.is_array() || j.empty()) throw ConfigError(fail(source, "'scenes' must be a non-empty list"));
    auto sceneList = [&](const nlohmann::json& v) {
        std::vector<std::string> s;
        if (v.is_string()) s.push_back(v.get<std::string>());
        else if (v.is_array())
            for (auto& x : v) {
                if (!x.is_string()) throw ConfigError(fail(source, "a scene list must hold strings"));
                s.push_back(x.get<std::string>());
            }
        if (s.empty()) throw ConfigError(fail(source, "a scene entry is empty"));
        return s;
    };
    std::vector<SceneEntry> out;
    for (std::size_t i = 0; i < j.size(); ++i) {
        const auto& e = j[i];
        if (!e.is_object() && !e.is_string() && !e.is_array())
            wrongType(source, "scenes[" + std::to_string(i) + "]",
                      "a scene (builtin:NAME or a glTF path), a list of scenes or an object with \"scene\"", e);
        SceneEntry se;
        if (e.is_object()) {
            if (!e.contains("scene")) throw ConfigError(fail(source, "a scene object needs \"scene\""));
            se.scenes = sceneList(e["scene"]);
            se.label = stringOr(e, "label", defaultLabel(se.scenes), source, "scenes[].label");
            if (e.contains("views")) {
                if (!e["views"].is_array()) wrongType(source, "scenes[].views", "a list of view names", e["views"]);
                for (auto& v : e["views"]) {
                    if (!v.is_string()) wrongType(source, "scenes[].views[]", "a string", v);
                    se.views.push_back(v.get<std::string>());
                }
            }
            if (e.contains("set")) {
                if (!e["set"].is_object()) throw ConfigError(fail(source, "a scene's \"set\" must be an object"));
                for (auto& [k, v] : e["set"].items()) se.set.emplace_back(k, valueString(v, source, k));
            }
        } else {
            se.scenes = sceneList(e);
            se.label = defaultLabel(se.scenes);
        }
        if (se.views.empty()) se.views.push_back("");
        out.push_back(se);
    }
    return out;
}

}  // namespace

std::string stableHash(const std::string& text) {
    std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a 64 offset basis
    for (unsigned char c : text) {
        h ^= c;
        h *= 0x100000001b3ull;  // FNV 64 prime
    }
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

std::string SweepConfig::canonical() const {
    std::string s = "scene=";
    for (std::size_t i = 0; i < scenes.size(); ++i) s += (i ? "+" : "") + scenes[i];
    s += "|res=" + std::to_string(resolution.x) + "x" + std::to_string(resolution.y);
    s += "|frames=" + std::to_string(frames) + "|warmup=" + std::to_string(warmup);
    for (auto& [k, v] : assignments) s += "|" + k + "=" + v;
    return s;
}

std::string SweepConfig::label() const {
    std::string s = sceneLabel;
    for (auto& [k, v] : assignments)
        if (k == "view") s += " view=" + v;
    s += " " + std::to_string(resolution.x) + "x" + std::to_string(resolution.y);
    for (auto& [k, v] : axisValues)
        if (k != "view" && k != kResolutionKey) s += " " + k + "=" + v;
    return s;
}

Settings SweepConfig::settings() const {
    Settings s;
    for (auto& [k, v] : assignments) applySetting(s, k, v);
    return s;
}

nlohmann::json SweepConfig::describe() const {
    nlohmann::json axes = nlohmann::json::object();
    for (auto& [k, v] : axisValues) axes[k] = v;
    nlohmann::json set = nlohmann::json::object();
    std::string view;
    for (auto& [k, v] : assignments) {
        set[k] = v;
        if (k == "view") view = v;
    }
    return {{"id", id},       {"label", label()}, {"scene_label", sceneLabel}, {"scenes", scenes},
            {"view", view},   {"axes", axes},     {"set", set}, {"held_out", heldOut}};
}

namespace {
SweepSpec parseSweepImpl(const std::string& text, const std::string& source);
}  // namespace

SweepSpec parseSweep(const std::string& text, const std::string& source) {
    try {
        return parseSweepImpl(text, source);
    } catch (const nlohmann::json::exception& e) {
        // A type the explicit checks above do not cover: still name the file.
        throw ConfigError(source + ": " + jsonErrorText(e));
    }
}

namespace {
SweepSpec parseSweepImpl(const std::string& text, const std::string& source) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        throw ConfigError(source + ": not valid JSON (" + jsonErrorText(e) + ")");
    }
    if (!j.is_object()) throw ConfigError(fail(source, "a sweep must be a JSON object"));
    static const std::set<std::string> known = {"name",   "description", "scenes", "resolutions", "frames",   "warmup",
                                                "images", "check",       "base",   "axes",        "reference", "held_out"};
    for (auto& [k, v] : j.items())
        if (!known.count(k)) throw ConfigError(fail(source, "unknown sweep field '" + k + "'"));
    SweepSpec spec;
    spec.name = stringOr(j, "name", source, source, "name");
    spec.description = stringOr(j, "description", "", source, "description");
    spec.images = boolOr(j, "images", false, source);
    spec.check = boolOr(j, "check", false, source);
    int frames = intOr(j, "frames", 100, source), warmup = intOr(j, "warmup", 20, source);
    if (frames < 1 || warmup < 0) throw ConfigError(fail(source, "'frames' must be >= 1 and 'warmup' >= 0"));
    if (!j.contains("scenes")) throw ConfigError(fail(source, "missing 'scenes'"));
    std::vector<SceneEntry> scenes = parseScenes(j["scenes"], source);

    // Base assignments (nested objects flatten to dotted keys, as --config).
    Assignments base;
    if (j.contains("base")) {
        std::function<void(const nlohmann::json&, const std::string&)> walk = [&](const nlohmann::json& o,
                                                                                 const std::string& prefix) {
            for (auto& [k, v] : o.items()) {
                std::string key = prefix.empty() ? k : prefix + "." + k;
                if (v.is_object()) walk(v, key);
                else base.emplace_back(key, valueString(v, source, key));
            }
        };
        if (!j["base"].is_object()) throw ConfigError(fail(source, "'base' must be an object"));
        walk(j["base"], "");
    }
    // "reference": the kind of ground truth the error is measured against
    // (the settings key `reference`; an axis may override it).
    if (j.contains("reference")) base.emplace_back("reference", valueString(j["reference"], source, "reference"));

    // Axes: resolutions first (outermost after scenes and views), then the
    // listed axes in order; their cartesian product.
    std::vector<std::vector<Assignments>> axes;
    if (j.contains("resolutions") && !j["resolutions"].is_array())
        wrongType(source, "resolutions", "a list of \"WxH\" strings (e.g. [\"1920x1080\"])", j["resolutions"]);
    if (j.contains("resolutions")) axes.push_back(expandAxis({{kResolutionKey, j["resolutions"]}}, source));
    if (j.contains("axes")) {
        if (!j["axes"].is_array()) throw ConfigError(fail(source, "'axes' must be a list"));
        for (auto& a : j["axes"]) axes.push_back(expandAxis(a, source));
    }
    // The size of the product before building it (two 10^4-value axes would
    // otherwise allocate 10^8 assignment lists before the limit is seen).
    {
        double size = double(scenes.size());
        std::size_t views = 0;
        for (auto& sc : scenes) views = std::max(views, sc.views.size());
        size *= double(views);
        for (auto& axis : axes) size *= double(axis.size());
        if (size > double(kMaxConfigurations))
            throw ConfigError(fail(source, "the sweep expands to about " + std::to_string(std::llround(size)) +
                                               " configurations, more than 10^6 (split it into several files)"));
    }
    std::vector<Assignments> product{{}};
    for (auto& axis : axes) {
        std::vector<Assignments> next;
        for (auto& prefix : product)
            for (auto& entry : axis) {
                Assignments a = prefix;
                a.insert(a.end(), entry.begin(), entry.end());
                next.push_back(a);
            }
        product = std::move(next);
        if (product.size() > kMaxConfigurations) throw ConfigError(fail(source, "more than 10^6 configurations"));
    }

    std::set<std::string> seen;
    for (auto& sc : scenes)
        for (auto& view : sc.views)
            for (auto& axisSet : product) {
                SweepConfig c;
                c.scenes = sc.scenes;
                c.sceneLabel = sc.label;
                c.frames = frames;
                c.warmup = warmup;
                std::map<std::string, std::string> assigned;  // last assignment wins
                for (auto& [k, v] : base) assigned[k] = v;
                if (!view.empty()) assigned["view"] = view;
                for (auto& [k, v] : sc.set) assigned[k] = v;
                std::map<std::string, std::string> axisAssigned;
                for (auto& [k, v] : axisSet) assigned[k] = axisAssigned[k] = v;
                if (!view.empty()) axisAssigned["view"] = view;
                if (auto r = assigned.find(kResolutionKey); r != assigned.end()) {
                    c.resolution = parseResolution(r->second, source);
                    assigned.erase(r);
                }
                c.assignments.assign(assigned.begin(), assigned.end());
                c.axisValues.assign(axisAssigned.begin(), axisAssigned.end());
                try {
                    (void)c.settings();  // every key and value must be valid before anything runs
                } catch (const ConfigError& e) {
                    throw ConfigError(fail(source, c.label() + ": " + e.what()));
                }
                c.id = stableHash(c.canonical());
                if (!seen.insert(c.id).second) {
                    ++spec.duplicates;
                    continue;
                }
                spec.configs.push_back(std::move(c));
            }
    // "held_out": ["LABEL/VIEW", ...]: views kept out of tuning (the test set
    // of a train/test split); each must name a scene label and view above.
    if (j.contains("held_out")) {
        if (!j["held_out"].is_array()) throw ConfigError(fail(source, "'held_out' must be a list of \"LABEL/VIEW\" strings"));
        for (auto& h : j["held_out"]) {
            if (!h.is_string()) throw ConfigError(fail(source, "'held_out' entries must be \"LABEL/VIEW\" strings"));
            const std::string name = h.get<std::string>();
            bool found = false;
            for (auto& c : spec.configs) {
                std::string view;
                for (auto& [k, v] : c.assignments)
                    if (k == "view") view = v;
                if (c.sceneLabel + "/" + view == name) found = c.heldOut = true;
            }
            if (!found) throw ConfigError(fail(source, "'held_out' names '" + name + "', which is no scene label/view of this sweep"));
        }
    }
    return spec;
}
}  // namespace

std::vector<SweepConfig> shardOf(const std::vector<SweepConfig>& all, int index, int count) {
    if (count < 1 || index < 0 || index >= count)
        throw ConfigError("--shard " + std::to_string(index) + "/" + std::to_string(count) + ": expected 0 <= i < n");
    std::vector<SweepConfig> out;
    for (std::size_t k = std::size_t(index); k < all.size(); k += std::size_t(count)) out.push_back(all[k]);
    return out;
}

std::set<std::string> completedIds(std::istream& in, int* unreadable) {
    std::set<std::string> ids;
    int bad = 0;
    std::string line;
    while (std::getline(in, line)) {
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        auto j = nlohmann::json::parse(line, nullptr, false);
        if (j.is_discarded() || !j.is_object() || !j.contains("sweep") || !j["sweep"].contains("id")) {
            ++bad;
            continue;
        }
        if (!j.contains("failed") && !j.contains("retry")) ids.insert(j["sweep"]["id"].get<std::string>());
    }
    if (unreadable) *unreadable = bad;
    return ids;
}

std::vector<SweepConfig> pending(const std::vector<SweepConfig>& configs, const std::set<std::string>& done) {
    std::vector<SweepConfig> out;
    for (auto& c : configs)
        if (!done.count(c.id)) out.push_back(c);
    return out;
}

std::string sweepCsvHeader() { return resultsCsvHeader(); }

std::vector<std::string> sweepCsvRows(const nlohmann::json& line) { return resultsCsvRows(line); }

}  // namespace rtgi
