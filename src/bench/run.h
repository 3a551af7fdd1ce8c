#pragma once
// One benchmark run: scene(s) + settings -> frames rendered headless, timings,
// memory, images and results (shared by rtgi-bench, sweeps and the tests).
#include "app/cli.h"
#include "gl/context.h"
#include "render/settings.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace rtgi {

// Renders and measures; returns the results.json object of SPEC section 12.
nlohmann::json runBenchmark(const gl::ContextInfo& info, const Scene& scene, const Settings& settings,
                            const RunOptions& opts);

// The same with an existing renderer (its profiler is reset first): a sweep
// keeps one renderer per scene and only reconfigures it between runs.
class Renderer;
nlohmann::json runBenchmark(const gl::ContextInfo& info, Renderer& renderer, const RunOptions& opts);

// The per-pass table printed on stdout.
std::string formatTimingTable(const nlohmann::json& results);

}  // namespace rtgi
