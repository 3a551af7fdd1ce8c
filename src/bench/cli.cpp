#include "bench/cli.h"

#include <fstream>
#include <sstream>

namespace rtgi {

namespace {
int toInt(const std::string& opt, const std::string& v, int lo, int hi) {
    char* end = nullptr;
    long x = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end || x < lo || x > hi)
        throw ConfigError(opt + " '" + v + "': expected an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
    return int(x);
}
}  // namespace

std::int64_t parseByteSize(const std::string& opt, const std::string& v) {
    // "4G", "512M", "1.5GiB", "1000000" (bytes); binary multiples.
    char* end = nullptr;
    double x = std::strtod(v.c_str(), &end);
    std::string unit = end ? std::string(end) : std::string();
    double mul = 1.0;
    if (unit.empty() || unit == "B") mul = 1.0;
    else if (unit == "K" || unit == "KiB") mul = 1024.0;
    else if (unit == "M" || unit == "MiB") mul = 1024.0 * 1024.0;
    else if (unit == "G" || unit == "GiB") mul = 1024.0 * 1024.0 * 1024.0;
    else if (unit == "T" || unit == "TiB") mul = 1024.0 * 1024.0 * 1024.0 * 1024.0;
    else x = -1.0;
    double bytes = x * mul;
    if (v.empty() || end == v.c_str() || !(bytes >= 1.0) || !(bytes <= 9.0e18))
        throw ConfigError(opt + " '" + v + "': expected a size such as 8G, 512M or 1048576 (bytes), at least 1 byte");
    return std::int64_t(bytes);
}

void checkCommandLine(const CommandLine& c) {
    for (auto& s : c.run.scenes)
        if (s.empty()) throw ConfigError("--scene: the scene path is empty");
    if (c.sweep.empty() && (c.shardIndex != 0 || c.shardCount != 1))
        throw ConfigError("--shard applies only to --sweep (no sweep file given)");
    if (!c.sweep.empty() && c.scenesGiven)
        throw ConfigError("--scene does not apply to --sweep; the sweep file lists its scenes");
}

CommandLine parseCommandLine(int argc, char** argv, const std::vector<std::pair<std::string, bool>>& hostOptions) {
    CommandLine c;
    std::vector<std::string> sets;
    std::vector<std::string> configs;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw ConfigError(a + ": missing value");
            return argv[++i];
        };
        if (a == "--help" || a == "-h") c.help = true;
        else if (a == "--scene") {
            if (!c.scenesGiven) c.run.scenes.clear();
            c.scenesGiven = true;
            c.run.scenes.push_back(value());
        } else if (a == "--res") {
            std::string v = value();
            auto x = v.find('x');
            if (x == std::string::npos) throw ConfigError("--res '" + v + "': expected WxH, e.g. 1920x1080");
            c.run.resolution = {toInt("--res", v.substr(0, x), 1, 16384), toInt("--res", v.substr(x + 1), 1, 16384)};
        } else if (a == "--frames") c.run.frames = toInt(a, value(), 1, 1000000);
        else if (a == "--warmup") c.run.warmup = toInt(a, value(), 0, 1000000);
        else if (a == "--device") c.device = toInt(a, value(), 0, 64);
        else if (a == "--out") {
            c.run.outDir = value();
            if (c.run.outDir.empty()) throw ConfigError("--out: the output directory is empty");
        } else if (a == "--max-memory") c.run.maxMemory = parseByteSize(a, value());
        else if (a == "--set") sets.push_back(value());
        else if (a == "--config") configs.push_back(value());
        else if (a == "--sweep") c.sweep = value();
        else if (a == "--shard") {
            std::string v = value();
            auto s = v.find('/');
            if (s == std::string::npos) throw ConfigError("--shard '" + v + "': expected i/n, e.g. 0/4");
            c.shardIndex = toInt("--shard", v.substr(0, s), 0, 1 << 20);
            c.shardCount = toInt("--shard", v.substr(s + 1), 1, 1 << 20);
            if (c.shardIndex >= c.shardCount) throw ConfigError("--shard '" + v + "': i must be below n");
        } else if (a == "--check") c.run.check = true;
        else if (a == "--debug") c.debug = true;
        else if (a == "--no-images") c.run.writeImages = false;
        else if (a == "--reference") c.run.reference = true;
        else if (a == "--list-devices") c.listDevices = true;
        else if (a == "--validate-only") c.validateOnly = true;
        else {
            bool handled = false;
            for (auto& [name, takesValue] : hostOptions)
                if (a == name) {
                    c.extra.push_back(a);
                    if (takesValue) c.extra.push_back(value());
                    handled = true;
                }
            if (!handled) throw ConfigError("unknown option '" + a + "' (see --help)");
        }
    }
    checkCommandLine(c);
    // --config files first, then --set in order: the command line wins.
    for (auto& f : configs) {
        std::ifstream in(f);
        if (!in) throw ConfigError("--config " + f + ": cannot open the file");
        std::stringstream ss;
        ss << in.rdbuf();
        for (auto& kv : flattenJsonConfig(ss.str(), f)) {
            try {
                applySetting(c.settings, kv.first, kv.second);
            } catch (const ConfigError& e) {
                throw ConfigError(f + ": " + e.what());
            }
            c.assignments.push_back(kv);
        }
    }
    for (auto& s : sets) {
        applyAssignment(c.settings, s);
        auto eq = s.find('=');
        c.assignments.emplace_back(s.substr(0, eq), s.substr(eq + 1));
    }
    return c;
}

Settings settingsFor(const Scene& scene, const CommandLine& cl) {
    return effectiveSettings(scene.suggestedSettings, cl.assignments, scene.name);
}

std::string commonHelp() {
    return R"(Options:
  --scene builtin:NAME|PATH.gltf|PATH.glb   scene (repeatable: merged; a model on builtin:plane stands on it)
                           built-ins: cornell atrium restaurant plane corner box-on-plane sphere-on-plane
  --res WxH                resolution (default 1280x720)
  --frames N               measured frames (default 100)
  --warmup N               warm-up frames before measuring (default 20)
  --device N               EGL device index (default: NVIDIA if present, else Mesa)
  --out DIR                output directory for images and results (default out)
  --set key=value          configuration (repeatable; see the keys below)
  --config FILE.json       configuration file (keys as below, nested objects allowed)
  --sweep FILE.json        run every configuration of a sweep
  --shard i/n              run only the i-th of n parts of a sweep
  --max-memory SIZE        GPU memory budget, e.g. 8G (default: what the driver reports as available,
                           else 4 GiB; see docs/STABILITY.md "Bad input")
  --check                  count NaN/Inf/negative/fp16-saturated values in every pass output
  --no-images              do not write images
  --reference              compare the output with the matching ray-traced reference (ao -> AO rays,
                           indirect light -> path-traced indirect, else the full image; cached on disk)
  --compare IMAGE REF      error metrics and heat map of an image file against a reference (PNG/PFM)
  --validate-only          load and validate the scene(s) and the configuration, render nothing (exit 0
                           when both are valid; no GL context is created)
  --debug                  KHR_debug output
  --list-devices           list EGL devices and exit
  --help                   this text
)";
}

std::string settingsHelp() {
    std::string s = "Configuration keys (--set key=value):\n";
    for (auto& k : settingKeys()) {
        std::string line = "  " + k.key;
        if (line.size() < 26) line.resize(26, ' ');
        s += line + " " + k.values + "  " + k.doc + "\n";
    }
    return s;
}

}  // namespace rtgi
