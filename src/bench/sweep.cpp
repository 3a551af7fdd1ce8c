#include "bench/sweep.h"

#include "bench/run.h"
#include "bench/sweep_spec.h"
#include "gl/input_files.h"
#include "gl/output_files.h"
#include "gl/program.h"
#include "render/renderer.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace rtgi {

namespace {

// "$SCENES/x.gltf" -> the SCENES environment variable (the directory of the
// shared scenes); the id keeps the unexpanded form, so shards on machines
// with different paths agree.
std::string expandScenePath(const std::string& spec) {
    const std::string var = "$SCENES";
    if (spec.rfind(var, 0) != 0) return spec;
    const char* dir = std::getenv("SCENES");
    if (!dir || !*dir)
        throw SceneError("scene '" + spec + "' needs the SCENES environment variable (the directory of the shared scenes)");
    return std::string(dir) + spec.substr(var.size());
}

std::string formatDuration(double s) {
    char buf[32];
    if (s < 60) std::snprintf(buf, sizeof buf, "%.0fs", s);
    else if (s < 3600) std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
    else std::snprintf(buf, sizeof buf, "%dh%02dm", int(s) / 3600, (int(s) % 3600) / 60);
    return buf;
}

// Rewrites results.csv from results.jsonl (the record that resume trusts), so
// the CSV never holds rows of a configuration interrupted between the writes.
// The sweep's own record (results.jsonl in --out), through the one reader:
// absent is empty; a FIFO or device put in its place is an output error.
std::string readRecords(const std::string& jsonlPath) {
    if (inputFileProblem(jsonlPath, InputKind::Records) == "does not exist") return {};
    try {
        return readInputFile(jsonlPath, InputKind::Records);
    } catch (const InputError& e) {
        throw OutputError(e.what());
    }
}

void rewriteCsv(const std::string& jsonlPath, const std::string& csvPath) {
    std::string csv = sweepCsvHeader() + "\n";
    std::istringstream in(readRecords(jsonlPath));
    std::string line;
    while (std::getline(in, line)) {
        auto j = nlohmann::json::parse(line, nullptr, false);
        if (j.is_discarded() || !j.is_object() || !j.contains("sweep")) continue;
        for (auto& row : sweepCsvRows(j)) csv += row + "\n";
    }
    writeFileAtomic(csvPath, csv);  // gl/output_files.h: complete or the previous file
}

// Whether this build's frame script has the ray-traced reference passes.
bool buildHasReference() {
    for (auto& p : frameScript())
        if (p->name().rfind("ref.", 0) == 0) return true;
    return false;
}

}  // namespace

SweepSpec readSweepFile(const std::string& path) {
    std::string text;
    try {
        text = readInputFile(path, InputKind::Config);  // gl/input_files.h: no FIFOs, bounded
    } catch (const InputError& e) {
        throw ConfigError(std::string("--sweep ") + e.what());
    }
    return parseSweep(text, escapeControl(path));
}

SweepRunner::SweepRunner(const gl::ContextInfo& info, const RunOptions& base)
    : info_(info), base_(base), haveReference_(buildHasReference()) {}

SweepRunner::~SweepRunner() = default;

nlohmann::json SweepRunner::run(const SweepSpec& spec, const SweepConfig& c, const std::string& shard,
                                const std::string& imageDir) {
    using Clock = std::chrono::steady_clock;
    auto t0 = Clock::now();
    nlohmann::json line;
    std::string retry;
    try {
        std::string sceneKey;
        for (auto& s : c.scenes) sceneKey += s + "\n";
        if (sceneKey != loadedScene_ || !scene_) {
            std::vector<std::string> paths;
            for (auto& s : c.scenes) paths.push_back(expandScenePath(s));
            renderer_.reset();
            loadedScene_.clear();
            scene_ = std::make_unique<Scene>(loadScenes(paths));
            for (auto& w : scene_->warnings) std::fprintf(stderr, "rtgi-bench: warning: %s\n", escapeControl(w).c_str());
        }
        Settings settings = effectiveSettings(scene_->suggestedSettings, c.assignments, scene_->name);
        // A configuration with a reference is timed without it (the
        // reference passes would run inside the measured frames) and then
        // compared with it, as `--reference` does; the kind follows from
        // what the configuration produces (AO, indirect light, image).
        const ReferenceSettings::Kind requested = settings.reference.kind;
        bool compare = requested != ReferenceSettings::Kind::Off;
        settings.reference.kind = ReferenceSettings::Kind::Off;
        if (compare && !haveReference_) {
            // Time the techniques now; the errors come when the reference
            // lands (resume re-runs lines marked "retry").
            compare = false;
            retry = "this build has no reference passes: no error values";
        }
        if (sceneKey != loadedScene_ || !renderer_) {
            if (!profiler_) profiler_ = std::make_unique<gl::Profiler>(info_.timerQuery);
            renderer_ = std::make_unique<Renderer>(*scene_, settings, *profiler_);
            loadedScene_ = sceneKey;
        } else {
            renderer_->configure(settings);
        }
        RunOptions opts = base_;
        opts.resolution = c.resolution;
        opts.frames = c.frames;
        opts.warmup = c.warmup;
        opts.writeImages = spec.images && base_.writeImages;  // the file asks for images, --no-images wins
        opts.outDir = imageDir;
        opts.check = spec.check || base_.check;
        opts.quiet = true;
        opts.reference = compare;
        opts.referenceKind = requested;  // e.g. full-frame asks for "full", not the AO the frame also makes
        line = runBenchmark(info_, *renderer_, opts);
    } catch (const std::exception& e) {
        // A configuration the build cannot run (a technique not landed, a
        // scene missing on this machine) is recorded and the sweep goes on;
        // resume retries it.
        line = nlohmann::json::object();
        line["failed"] = e.what();
        renderer_.reset();  // its state after a throw inside configure() is not trusted
        loadedScene_.clear();
    }
    line["sweep"] = c.describe();
    line["sweep"]["name"] = spec.name;
    line["sweep"]["shard"] = shard;
    line["wall_s"] = std::chrono::duration<double>(Clock::now() - t0).count();
    if (!retry.empty()) line["retry"] = retry;
    return line;
}

int runSweepCommand(const CommandLine& cl) {
    // A sweep file is self-contained: its id scheme only sees what the file
    // says, so command-line settings would silently change resumed results.
    if (!cl.assignments.empty() || describe(cl.settings) != describe(Settings{}))
        throw ConfigError("--sweep: --set/--config do not apply to sweeps; put the keys in the sweep file's \"base\"");
    SweepSpec spec = readSweepFile(cl.sweep);
    std::vector<SweepConfig> mine = shardOf(spec.configs, cl.shardIndex, cl.shardCount);

    const std::string dir = cl.run.outDir;
    prepareOutputDirectory(dir);
    const std::string jsonlPath = dir + "/results.jsonl", csvPath = dir + "/results.csv";
    std::set<std::string> done;
    {
        std::istringstream in(readRecords(jsonlPath));
        int unreadable = 0;
        done = completedIds(in, &unreadable);
        if (unreadable > 0)
            std::fprintf(stderr, "rtgi-bench: %s: ignored %d unreadable line(s) (an interrupted write?)\n",
                         jsonlPath.c_str(), unreadable);
    }
    std::vector<SweepConfig> todo = pending(mine, done);
    std::fprintf(stderr, "rtgi-bench: sweep '%s': %zu configurations%s, shard %d/%d holds %zu, %zu done, %zu to run\n",
                 escapeControl(spec.name).c_str(), spec.configs.size(),
                 spec.duplicates ? (" (" + std::to_string(spec.duplicates) + " duplicates dropped)").c_str() : "",
                 cl.shardIndex, cl.shardCount, mine.size(), mine.size() - todo.size(), todo.size());
    rewriteCsv(jsonlPath, csvPath);
    if (todo.empty()) return 0;

    auto ctx = gl::HeadlessContext::create({cl.device, cl.debug});
    checkOutputTarget(jsonlPath);  // appended to: no links, no directories in the way
    checkOutputTarget(csvPath);
    std::ofstream jsonl(jsonlPath, std::ios::app);
    std::ofstream csv(csvPath, std::ios::app);
    if (!jsonl || !csv) throw OutputError(dir + ": results.jsonl or results.csv cannot be opened for appending");

    SweepRunner runner(ctx->info(), cl.run);
    const std::string shard = std::to_string(cl.shardIndex) + "/" + std::to_string(cl.shardCount);
    using Clock = std::chrono::steady_clock;
    auto start = Clock::now();
    int failures = 0;
    for (std::size_t k = 0; k < todo.size(); ++k) {
        const SweepConfig& c = todo[k];
        nlohmann::json line = runner.run(spec, c, shard, dir + "/images/" + c.id);
        if (line.contains("failed")) {
            ++failures;
            std::fprintf(stderr, "rtgi-bench: %s: %s\n", escapeControl(c.label()).c_str(),
                         escapeControl(line["failed"].get<std::string>()).c_str());
        }
        const double wall = line["wall_s"].get<double>();
        jsonl << line.dump() << "\n";
        jsonl.flush();
        for (auto& row : sweepCsvRows(line)) csv << row << "\n";
        csv.flush();
        if (!jsonl || !csv) throw OutputError(jsonlPath + ": appending a result failed (disk full?)");

        double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
        double eta = elapsed / double(k + 1) * double(todo.size() - k - 1);
        std::fprintf(stderr, "[%zu/%zu] %s  %s  %.3f ms/frame  (%.1fs, elapsed %s, ETA %s)\n", k + 1, todo.size(),
                     c.id.c_str(), c.label().c_str(), line.contains("total_ms") ? line["total_ms"].get<double>() : 0.0,
                     wall, formatDuration(elapsed).c_str(), formatDuration(eta).c_str());
    }
    std::fprintf(stderr, "rtgi-bench: sweep '%s': wrote %s and %s\n", escapeControl(spec.name).c_str(), jsonlPath.c_str(),
                 csvPath.c_str());
    if (failures > 0) {
        std::fprintf(stderr, "rtgi-bench: %d of %zu configurations failed (lines with \"failed\" in %s)\n", failures,
                     todo.size(), jsonlPath.c_str());
        return 1;
    }
    return 0;
}

}  // namespace rtgi
