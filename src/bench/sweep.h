#pragma once
// Sweeps (--sweep FILE.json): many configurations in one process.
#include "app/cli.h"
#include "bench/sweep_spec.h"
#include "gl/context.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>

namespace rtgi {

class Renderer;
namespace gl {
class Profiler;
}

int runSweepCommand(const CommandLine& cl);

// Reads and parses a sweep file (bounded, no FIFOs); throws ConfigError
// naming the file.
SweepSpec readSweepFile(const std::string& path);

// Runs sweep configurations one after another in the current GL context
// (rtgi-bench --sweep and the Python module's rtgi.sweep): consecutive
// configurations of the same scene reuse one renderer (the expansion keeps
// scenes outermost), so the GPU scene and compiled programs are reused.
class SweepRunner {
public:
    // `base`: the options every configuration starts from (check, images,
    // memory budget); resolution, frames and warm-up come from the config.
    SweepRunner(const gl::ContextInfo& info, const RunOptions& base);
    ~SweepRunner();
    // One results.jsonl line: the run's results.json with "sweep" (the
    // configuration, sweep name, `shard`) and "wall_s", or "failed" with
    // the error's sentence (the runner goes on with the next one).
    nlohmann::json run(const SweepSpec& spec, const SweepConfig& c, const std::string& shard,
                       const std::string& imageDir);

private:
    gl::ContextInfo info_;
    RunOptions base_;
    bool haveReference_;
    std::unique_ptr<gl::Profiler> profiler_;
    std::unique_ptr<Scene> scene_;
    std::unique_ptr<Renderer> renderer_;
    std::string loadedScene_;
};

}  // namespace rtgi
