#include "app/cli.h"

#include "app/version.h"
#include "gl/input_files.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace rtgi {

namespace {

constexpr unsigned kBench = 1u << int(Host::Bench), kView = 1u << int(Host::View), kBoth = kBench | kView;

// The option table: every option of both binaries, which of them accepts it,
// and its help line. An option appears twice when its meaning differs.
struct OptionSpec {
    const char* name;
    const char* arg;  // nullptr: a flag
    unsigned hosts;
    const char* help;
};

const OptionSpec kOptions[] = {
    {"--scene", "builtin:NAME|PATH.gltf|PATH.glb", kBoth,
     "scene (repeatable: merged; a model on builtin:plane stands on it)\n"
     "built-ins: cornell atrium restaurant plane corner box-on-plane sphere-on-plane"},
    {"--res", "WxH", kBench, "resolution (default 1280x720)"},
    {"--res", "WxH", kView, "window size (default 1280x720)"},
    {"--frames", "N", kBench, "measured frames (default 100)"},
    {"--frames", "N", kView, "render N frames and exit (automation; the screenshot is taken after the last)"},
    {"--warmup", "N", kBench, "warm-up frames before measuring (default 20)"},
    {"--path", "FILE|NAME", kBench,
     "play a camera/scene path (benchmarks/paths/<scene>.json or a file): frame i at\n"
     "t = i/fps; --frames counts path frames (default: all); with --reference a\n"
     "temporal error (per-frame CSV, flicker, lag; docs/temporal.md)"},
    {"--reference-every", "K", kBench,
     "on a path with --reference: reference every K-th frame (+ the frame before it\n"
     "and the frames around step events); default 1, and 8 at the small default size of a\n"
     "path reference without --res (192x108, reference.spp=64; docs/temporal.md)"},
    {"--path", "FILE|NAME", kView,
     "play a camera/scene path (as rtgi-bench --path): Space play/pause, Left/Right\n"
     "step a frame, Home frame 0, X reset the temporal history every frame (docs/viewer.md)"},
    {"--path-frames", nullptr, kBench,
     "with --path: write every path frame as <out>/frames/frame_NNNN.png and, when\n"
     "ffmpeg is on PATH, <out>/path.mp4 (H.264, the path's fps)"},
    {"--device", "N", kBench, "EGL device index (default: NVIDIA if present, else Mesa)"},
    {"--out", "DIR", kBench, "output directory for images and results (default out)"},
    {"--set", "key=value", kBoth, "configuration (repeatable; see the keys below)"},
    {"--config", "FILE.json", kBoth, "configuration file (keys as below, nested objects allowed)"},
    {"--sweep", "FILE.json", kBench, "run every configuration of a sweep"},
    {"--shard", "i/n", kBench, "run only the i-th of n parts of a sweep"},
    {"--max-memory", "SIZE", kBench,
     "GPU memory budget, e.g. 8G (default: what the driver reports as available,\n"
     "else 4 GiB; see docs/STABILITY.md \"Bad input\")"},
    {"--check", nullptr, kBench, "count NaN/Inf/negative/fp16-saturated values in every pass output"},
    {"--no-images", nullptr, kBench, "do not write images"},
    {"--reference", nullptr, kBench,
     "compare the output with the matching ray-traced reference (ao -> AO rays,\n"
     "indirect light -> path-traced indirect, else the full image; cached on disk)"},
    {"--reference", nullptr, kView, "start with the live reference comparison on (the panel toggles it; docs/viewer.md)"},
    {"--compare", "IMAGE REF", kBench,
     "error metrics and heat map of an image file against a reference (PNG/PFM/EXR);\n"
     "with --quantity ao|ldr|radiance, --mask FILE or --background V (rtgi-bench --compare --help)"},
    {"--validate-only", nullptr, kBench,
     "load and validate the scene(s) and the configuration, render nothing (exit 0\n"
     "when both are valid; no GL context is created)"},
    {"--screenshot", "FILE", kView, "write the displayed image (PNG) after the last frame"},
    {"--no-vsync", nullptr, kView, "start with vsync off (Y toggles)"},
    {"--script", "FILE", kView, "replay panel actions (one per line: FRAME set KEY VALUE | FRAME split X | ...)"},
    {"--debug", nullptr, kBoth, "KHR_debug output"},
    {"--list-devices", nullptr, kBench, "list EGL devices and exit"},
    {"--print-frame", nullptr, kBench,
     "print the frame for the scene + settings (passes, what each reads and writes,\n"
     "skipped passes with why) and exit without rendering"},
    {"--version", nullptr, kBoth, "print the version and exit"},
    {"--help", nullptr, kBoth, "this text"},
};

const OptionSpec* findOption(const std::string& name, Host host) {
    for (auto& o : kOptions)
        if (name == o.name && (o.hosts & (1u << int(host)))) return &o;
    return nullptr;
}

bool knownElsewhere(const std::string& name) {
    for (auto& o : kOptions)
        if (name == o.name) return true;
    return false;
}

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
    if (c.run.referenceEvery > 0 && c.run.path.empty())
        throw ConfigError("--reference-every applies only to --path (no path given)");
    if (c.run.pathFrames && c.run.path.empty()) throw ConfigError("--path-frames applies only to --path (no path given)");
    if (!c.sweep.empty() && !c.run.path.empty())
        throw ConfigError("--path does not apply to --sweep (a sweep runs still frames; run one rtgi-bench --path per configuration)");
    if (!c.sweep.empty() && c.scenesGiven)
        throw ConfigError("--scene does not apply to --sweep; the sweep file lists its scenes");
}

const char* hostName(Host h) { return h == Host::Bench ? "rtgi-bench" : "rtgi-view"; }

CommandLine parseCommandLine(Host host, int argc, char** argv) {
    CommandLine c;
    c.run.commandLine = quoteCommandLine(argc, argv);
    std::vector<std::string> sets;
    std::vector<std::string> configs;
    const Host other = host == Host::Bench ? Host::View : Host::Bench;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "-h") a = "--help";
        const OptionSpec* spec = findOption(a, host);
        if (!spec) {
            if (knownElsewhere(a))
                throw ConfigError("option '" + a + "' is for " + hostName(other) + " only; " + hostName(host) +
                                  " --help lists what " + hostName(host) + " accepts");
            throw ConfigError("unknown option '" + a + "' (see " + std::string(hostName(host)) + " --help)");
        }
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw ConfigError(a + ": missing value (" + spec->arg + ")");
            return argv[++i];
        };
        if (a == "--help") c.help = true;
        else if (a == "--version") c.version = true;
        else if (a == "--scene") {
            if (!c.scenesGiven) c.run.scenes.clear();
            c.scenesGiven = true;
            c.run.scenes.push_back(value());
        } else if (a == "--res") {
            std::string v = value();
            auto x = v.find('x');
            if (x == std::string::npos) throw ConfigError("--res '" + v + "': expected WxH, e.g. 1920x1080");
            c.run.resolution = {toInt("--res", v.substr(0, x), 1, 16384), toInt("--res", v.substr(x + 1), 1, 16384)};
            c.resolutionGiven = true;
        } else if (a == "--frames") {
            c.run.frames = toInt(a, value(), 1, 1000000);
            c.framesGiven = true;
        } else if (a == "--warmup") {
            c.run.warmup = toInt(a, value(), 0, 1000000);
            c.warmupGiven = true;
        } else if (a == "--path") {
            c.run.path = value();
            if (c.run.path.empty()) throw ConfigError("--path: the path file or name is empty");
        } else if (a == "--reference-every") c.run.referenceEvery = toInt(a, value(), 1, 1000000);
        else if (a == "--device") c.device = toInt(a, value(), 0, 64);
        else if (a == "--out") {
            c.run.outDir = value();
            if (c.run.outDir.empty()) throw ConfigError("--out: the output directory is empty");
        } else if (a == "--max-memory") c.run.maxMemory = parseByteSize(a, value());
        else if (a == "--validate-only") c.validateOnly = true;
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
        else if (a == "--path-frames") c.run.pathFrames = true;
        else if (a == "--reference") (host == Host::Bench ? c.run.reference : c.liveReference) = true;
        else if (a == "--list-devices") c.listDevices = true;
        else if (a == "--print-frame") c.printFrame = true;
        else if (a == "--screenshot") c.screenshot = value();
        else if (a == "--no-vsync") c.vsync = false;
        else if (a == "--script") c.script = value();
        else if (a == "--compare")
            throw ConfigError("--compare must be the first option: rtgi-bench --compare IMAGE REF [--out DIR] ...");
        else throw ConfigError("option '" + a + "' is in the table but not handled (a bug)");
    }
    checkCommandLine(c);
    // --config files first, then --set in order: the command line wins.
    for (auto& f : configs) {
        std::string text;
        try {
            text = readInputFile(f, InputKind::Config);  // gl/input_files.h: no FIFOs, bounded
        } catch (const InputError& e) {
            throw ConfigError(std::string("--config ") + e.what());
        }
        for (auto& kv : flattenJsonConfig(text, escapeControl(f))) {
            try {
                applySetting(c.settings, kv.first, kv.second);
            } catch (const ConfigError& e) {
                throw ConfigError(escapeControl(f) + ": " + e.what());
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

std::string optionsHelp(Host host) {
    std::string s = "Options:\n";
    for (auto& o : kOptions) {
        if (!(o.hosts & (1u << int(host)))) continue;
        std::string head = std::string("  ") + o.name + (o.arg ? std::string(" ") + o.arg : "");
        std::string help = o.help;
        std::size_t start = 0;
        bool first = true;
        while (start <= help.size()) {
            std::size_t nl = help.find('\n', start);
            std::string part = help.substr(start, nl == std::string::npos ? std::string::npos : nl - start);
            std::string line = first ? head : "";
            if (line.size() >= 27) {  // long option: help on the next line
                s += line + "\n";
                line.clear();
            }
            line.resize(27, ' ');
            s += line + part + "\n";
            first = false;
            if (nl == std::string::npos) break;
            start = nl + 1;
        }
    }
    return s;
}

std::string settingsHelp() {
    std::string s = "Configuration keys (--set key=value):\n";
    for (auto& k : settingKeys()) {
        std::string line = "  " + k.key;
        if (line.size() < 26) line.resize(26, ' ');
        s += line + " " + k.values + "  " + k.doc + " (default: " + settingDefault(k) + ")\n";
    }
    return s;
}

std::string versionString() {
    std::string v = std::string("rtgi ") + kProjectVersion;
    if (*kGitDescribe) v += std::string(" (git ") + kGitDescribe + ")";
    return v;
}

std::string quoteCommandLine(int argc, char** argv) {
    std::string out;
    for (int i = 0; i < argc; ++i) {
        std::string a = argv[i];
        bool plain = !a.empty() && std::all_of(a.begin(), a.end(), [](unsigned char ch) {
            return std::isalnum(ch) || std::string("-_./:=,+@%").find(char(ch)) != std::string::npos;
        });
        if (!out.empty()) out += ' ';
        if (plain) {
            out += a;
        } else {  // POSIX single quotes; a ' inside becomes '\''
            out += '\'';
            for (char ch : a) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
            out += '\'';
        }
    }
    return out;
}

namespace {
// The frame has one sun (one shadow map, one RSM, one LPV injection:
// docs/lights.md): Scene::sun() is the first directional light; the others
// are left out with a warning (stderr and results.json "warnings").
void warnExtraSuns(Scene& s) {
    std::size_t suns = 0;
    for (auto& l : s.lights) suns += l.type == LightType::Directional ? 1 : 0;
    if (suns < 2) return;
    const std::string first = s.sun()->name.empty() ? std::string("the first") : "'" + s.sun()->name + "'";
    s.warnings.push_back(s.name + ": " + std::to_string(suns) + " directional lights; only " + first +
                         " is used (the frame has one sun), the other " + std::to_string(suns - 1) + " are ignored");
}
}  // namespace

Scene loadScenes(const std::vector<std::string>& specs) {
    Scene s = mergeScenes(specs);
    warnExtraSuns(s);
    return s;
}

Scene mergeScenes(const std::vector<std::string>& specs) {
    if (specs.empty()) throw SceneError("--scene: no scene given");
    std::vector<Scene> floors, models;
    for (auto& s : specs) {
        Scene sc = loadSceneSpec(s);
        bool isFloor = s == "builtin:plane";
        (isFloor && specs.size() > 1 ? floors : models).push_back(std::move(sc));
    }
    Scene merged;
    for (auto& m : models) merged.merge(m);
    if (floors.empty()) return merged;

    Aabb mb = merged.bounds();
    glm::vec3 shift(-mb.center().x, -mb.lo.y, -mb.center().z);
    for (auto& v : merged.vertices) v.position += shift;
    for (auto& l : merged.lights) l.position += shift;
    for (auto& c : merged.cameras) {
        c.position += shift;
        c.target += shift;
    }
    float footprint = std::max(mb.extent().x, mb.extent().z);
    Scene out;
    for (auto& f : floors) {
        Aabb fb = f.bounds();
        float fext = std::max(fb.extent().x, fb.extent().z);
        float scale = fext > 0 ? 10.0f * footprint / fext : 1.0f;
        for (auto& v : f.vertices) v.position = glm::vec3(v.position.x * scale, v.position.y, v.position.z * scale);
        f.cameras.clear();  // the floor's camera does not frame the model
        out.merge(f);
    }
    Scene framed = merged;
    out.merge(merged);
    if (merged.cameras.empty()) {
        out.cameras.insert(out.cameras.begin(), defaultCamera(framed));
    }
    std::string name;
    for (auto& s : specs) name += (name.empty() ? "" : "+") + s;
    out.name = name;
    return out;
}

}  // namespace rtgi
