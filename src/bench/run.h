#pragma once
// One benchmark run: scene(s) + settings -> frames rendered headless, timings,
// memory, images and results (shared by rtgi-bench, sweeps and the tests).
#include "gl/context.h"
#include "render/settings.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace rtgi {

struct RunOptions {
    std::vector<std::string> scenes{"builtin:atrium"};
    glm::ivec2 resolution{1280, 720};
    int frames = 100;
    int warmup = 20;
    std::string outDir = "out";
    bool writeImages = true;
    bool check = false;
    bool quiet = false;
    bool reference = false;  // --reference: compare the output with the matching ray-traced reference
    std::int64_t maxMemory = 0;  // --max-memory: GPU memory budget in bytes (0 = what the device reports)
};

// Loads and merges the --scene list. A glTF model merged with a built-in
// floor scene (builtin:plane) is moved so that it stands on the floor
// (minimum y = 0, centred in x/z), the floor is scaled to 10x the model's
// footprint, and the camera frames the model.
Scene loadScenes(const std::vector<std::string>& specs);

// Renders and measures; returns the results.json object of SPEC section 12.
nlohmann::json runBenchmark(const gl::ContextInfo& info, const Scene& scene, const Settings& settings,
                            const RunOptions& opts);

// The same with an existing renderer (its profiler is reset first): a sweep
// keeps one renderer per scene and only reconfigures it between runs.
class Renderer;
nlohmann::json runBenchmark(const gl::ContextInfo& info, Renderer& renderer, const RunOptions& opts);

// Flattens a results object into CSV header + row (one row per pass).
std::string resultsCsvHeader();
std::vector<std::string> resultsCsvRows(const nlohmann::json& results);
// RFC 4180 quoting of one CSV field.
std::string csvQuote(const std::string& s);

// The per-pass table printed on stdout.
std::string formatTimingTable(const nlohmann::json& results);

}  // namespace rtgi
