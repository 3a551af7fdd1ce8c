#pragma once
// The command line shared by rtgi-bench and rtgi-view (SPEC section 12): one
// option table that says which binary accepts each option, one parser, the
// --help text generated from the table (each binary lists only what it
// accepts) and --version. Layering: app/ sits above render/ and scene/; bench/
// and view/ both use it and never each other.
#include "render/settings.h"
#include "scene/scene.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace rtgi {

enum class Host { Bench, View };
const char* hostName(Host h);  // "rtgi-bench" / "rtgi-view"

// What one run renders (rtgi-bench single runs and sweeps; rtgi-view's
// --frames automation uses scenes, resolution and frames).
struct RunOptions {
    std::vector<std::string> scenes{"builtin:atrium"};
    glm::ivec2 resolution{1280, 720};
    int frames = 100;
    int warmup = 20;
    std::string outDir = "out";
    bool writeImages = true;
    bool check = false;
    bool quiet = false;      // no progress output (sweeps print one line per configuration instead)
    bool reference = false;  // --reference: compare the output with the matching ray-traced reference
    // The kind a sweep asked for: its frames are timed without the reference
    // passes (reference=off), so the kind travels here (Off: what the run produces).
    ReferenceSettings::Kind referenceKind = ReferenceSettings::Kind::Off;
    // --path FILE|NAME (issue 23): frame i renders the scene state at t = i / fps
    // (warm-up frames at t = 0); --frames then counts path frames (default: the whole path).
    std::string path;
    // --reference-every K on a path: a reference for every K-th frame and the one
    // before it (flicker), and every frame around a step event (0: the default, docs/temporal.md).
    int referenceEvery = 0;
    // --path-frames: the LDR image of every path frame as <out>/frames/frame_NNNN.png,
    // and <out>/path.mp4 through ffmpeg when it is on PATH (docs/temporal.md).
    bool pathFrames = false;
    std::int64_t maxMemory = 0;  // --max-memory: GPU memory budget in bytes (0 = what the device reports)
    // Provenance recorded in results.json (SPEC 12: any figure can be reproduced).
    std::string commandLine;  // the exact argv, shell-quoted
};

struct CommandLine {
    RunOptions run;
    Settings settings;
    int device = -1;
    bool debug = false;
    bool help = false;
    bool version = false;
    bool listDevices = false;
    bool printFrame = false;  // --print-frame: print the pruned frame and exit
    bool validateOnly = false;  // --validate-only: load scenes and settings, no GL, exit 0
    bool framesGiven = false;
    bool warmupGiven = false, resolutionGiven = false;
    std::string sweep;    // --sweep FILE.json
    int shardIndex = 0, shardCount = 1;
    bool scenesGiven = false;
    // rtgi-view only.
    std::string screenshot;   // --screenshot FILE
    bool vsync = true;        // --no-vsync
    std::string script;       // --script FILE (panel actions replayed per frame; docs/viewer.md)
    bool liveReference = false;  // --reference in the viewer: start in live reference mode
    // --config files then --set, in order (settings = these applied on top of
    // the scene's suggested settings: see settingsFor).
    Assignments assignments;
};

// Parses argv for `host`; throws ConfigError naming the option on bad input,
// on unknown options and on options of the other binary.
CommandLine parseCommandLine(Host host, int argc, char** argv);
// Consistency of options that parse alone (empty --scene, --shard without
// --sweep); throws ConfigError. Called by parseCommandLine.
void checkCommandLine(const CommandLine& c);
// "8G", "512M", "1048576" -> bytes (binary multiples); throws ConfigError naming `opt`.
std::int64_t parseByteSize(const std::string& opt, const std::string& v);
// The settings of a run of `scene`: defaults, the scene's suggestions, then
// the command line's --config / --set.
Settings settingsFor(const Scene& scene, const CommandLine& cl);
// The option list of `host` (generated from the option table).
std::string optionsHelp(Host host);
std::string settingsHelp();
// "rtgi 0.9.0 (git v0.9.0-12-gabc1234-dirty)" — CMake project version and
// `git describe` at build time when the source is a git checkout.
std::string versionString();
// argv as one shell-quoted line (results.json "command_line").
std::string quoteCommandLine(int argc, char** argv);

// Loads and merges the --scene list. A glTF model merged with a built-in
// floor scene (builtin:plane) is moved so that it stands on the floor
// (minimum y = 0, centred in x/z), the floor is scaled to 10x the model's
// footprint, and the camera frames the model.
Scene loadScenes(const std::vector<std::string>& specs);
// loadScenes without the scene-wide warnings (several suns).
Scene mergeScenes(const std::vector<std::string>& specs);

}  // namespace rtgi
