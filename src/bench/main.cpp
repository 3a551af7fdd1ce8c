// rtgi-bench: the headless benchmark and main job (EGL; never links GLFW).
#include "bench/cli.h"
#include "bench/run.h"
#include "bench/sweep.h"
#include "gl/context.h"
#include "gl/output_files.h"
#include "gl/program.h"
#include "render/reference/reference_runner.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

using namespace rtgi;

namespace {

// Exit codes (README "Exit codes"): 0 ok, 1 some sweep configurations failed,
// 2 configuration / command line / memory budget, 3 scene or image input,
// 4 GL, 5 --check found NaN/Inf, 6 a result file could not be written.
constexpr int kExitOutput = 6;

// rtgi-bench --compare IMAGE REFERENCE [--out DIR], in any argument order:
// no GL context needed.
int compareCommand(int argc, char** argv) {
    std::string outDir = "out";
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--compare") continue;
        if (a == "--out") {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "rtgi-bench: --out: missing value\n");
                return 2;
            }
            outDir = argv[++i];
        } else if (a.rfind("--", 0) == 0) {
            std::fprintf(stderr, "rtgi-bench: --compare: option '%s' does not apply (only --out DIR)\n", a.c_str());
            return 2;
        } else {
            files.push_back(a);
        }
    }
    if (files.size() != 2) {
        std::fprintf(stderr, "rtgi-bench: --compare IMAGE REFERENCE [--out DIR]: expected two image files\n");
        return 2;
    }
    try {
        prepareOutputDirectory(outDir);
        nlohmann::json j = compareImageFiles(files[0], files[1], outDir);
        std::cout << j.dump(2) << "\n  wrote " << outDir << "/compare.json, error.heatmap.png\n";
        return 0;
    } catch (const OutputError& e) {
        std::fprintf(stderr, "rtgi-bench: --compare: %s\n", e.what());
        return kExitOutput;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rtgi-bench: --compare: %s\n", e.what());
        return 3;
    }
}

}  // namespace

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]) == "--compare") return compareCommand(argc, argv);
    CommandLine cl;
    try {
        cl = parseCommandLine(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", e.what());
        return 2;
    }
    if (cl.help) {
        std::printf("rtgi-bench: headless real-time GI benchmark (OpenGL 4.5+ compute through EGL)\n\n%s\n%s",
                    commonHelp().c_str(), settingsHelp().c_str());
        return 0;
    }
    if (cl.listDevices) {
        auto devs = gl::HeadlessContext::listDevices();
        for (std::size_t i = 0; i < devs.size(); ++i) std::printf("%zu: %s\n", i, devs[i].c_str());
        return 0;
    }
    try {
        if (!cl.sweep.empty()) return runSweepCommand(cl);
        if (!cl.validateOnly) {  // an unwritable --out fails before any work
            prepareOutputDirectory(cl.run.outDir);
            checkOutputTarget(cl.run.outDir + "/results.json");
            checkOutputTarget(cl.run.outDir + "/results.csv");
        }
        Scene scene = loadScenes(cl.run.scenes);
        for (auto& w : scene.warnings) std::fprintf(stderr, "rtgi-bench: warning: %s\n", w.c_str());
        if (cl.validateOnly) {
            (void)settingsFor(scene, cl);  // the scene's suggested settings must be valid too
            std::printf("rtgi-bench: %s: valid (%zu triangles)\n", scene.name.c_str(), scene.triangleCount());
            return 0;
        }
        auto ctx = gl::HeadlessContext::create({cl.device, cl.debug});
        nlohmann::json r = runBenchmark(ctx->info(), scene, settingsFor(scene, cl), cl.run);
        writeFileAtomic(cl.run.outDir + "/results.json", r.dump(2) + "\n");
        std::string csv = resultsCsvHeader() + "\n";
        for (auto& row : resultsCsvRows(r)) csv += row + "\n";
        writeFileAtomic(cl.run.outDir + "/results.csv", csv);
        std::cout << formatTimingTable(r);
        if (r.contains("error")) {
            const auto& e = r["error"];
            std::cout << "  error vs reference (" << e["compared"].get<std::string>() << ", "
                      << (e["reference"]["from_cache"].get<bool>() ? "from cache" : "rendered") << "): rmse "
                      << e["rmse"] << ", mae " << e["mae"] << ", psnr " << e["psnr"] << ", ssim " << e["ssim"] << "\n";
        }
        std::cout << "  wrote " << cl.run.outDir << "/results.json, results.csv"
                  << (cl.run.writeImages ? ", final.png, final.pfm and debug images" : "") << "\n";
        if (cl.run.check && r["check"]["non_finite"].get<std::uint64_t>() > 0) {
            std::fprintf(stderr, "rtgi-bench: --check found non-finite values (see results.json \"check\")\n");
            return 5;
        }
        return 0;
    } catch (const OutputError& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", e.what());
        return kExitOutput;
    } catch (const SceneError& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", e.what());
        return 3;
    } catch (const ConfigError& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", e.what());
        return 2;
    } catch (const gl::ShaderError& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", e.what());
        return 4;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", e.what());
        return 4;
    }
}
