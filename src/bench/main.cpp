// rtgi-bench: the headless benchmark and main job (EGL; never links GLFW).
#include "app/cli.h"
#include "app/progress_printer.h"
#include "bench/reference_compare.h"
#include "bench/results_csv.h"
#include "bench/run.h"
#include "bench/sweep.h"
#include "scene/path.h"
#include "gl/context.h"
#include "gl/input_files.h"
#include "gl/output_files.h"
#include "gl/program.h"
#include "render/lights.h"
#include "render/renderer.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

using namespace rtgi;

namespace {

// Exit codes (README "Exit codes"): 0 ok, 1 some sweep configurations failed,
// 2 configuration / command line / memory budget, 3 scene or image input,
// 4 GL, 5 --check found NaN/Inf, 6 a result file could not be written.
constexpr int kExitOutput = 6;

// --path --reference without --res (docs/temporal.md): the size and reference spacing.
constexpr int kPathReferenceSize[2] = {192, 108};
constexpr int kPathReferenceEvery = 8;
constexpr int kPathReferenceSpp = 64;

const char* kCompareUsage =
    "usage: rtgi-bench --compare IMAGE REFERENCE [--out DIR] [--quantity auto|ao|ldr|radiance]\n"
    "                  [--mask FILE | --background VALUE]\n"
    "  IMAGE, REFERENCE   PNG, PFM or EXR files of the same size\n"
    "  --quantity Q       auto (default): radiance for a PFM/EXR reference, else ldr;\n"
    "                     ao: channel 0 in [0,1] (no relative RMSE); ldr: rgb in [0,1];\n"
    "                     radiance: HDR rgb, PSNR/SSIM peak = the reference's largest luminance, relative RMSE\n"
    "  --mask FILE        compare only where FILE's channel 0 > 0.5 (e.g. a geometry mask)\n"
    "  --background V     compare only where the reference is not V (e.g. 0 for a black sky)\n"
    "  --out DIR          where compare.json and error.heatmap.png go (default out)\n";

// rtgi-bench --compare IMAGE REFERENCE [...], in any argument order: no GL context needed.
int compareCommand(int argc, char** argv) {
    CompareOptions opts;
    std::vector<std::string> files;
    try {
        for (int i = 1; i < argc; ++i) {
            std::string a = argv[i];
            auto value = [&]() -> std::string {
                if (i + 1 >= argc) throw ConfigError("--compare: " + a + ": missing value");
                return argv[++i];
            };
            if (a == "--compare") continue;
            if (a == "--help" || a == "-h") {
                std::printf("%s", kCompareUsage);
                return 0;
            } else if (a == "--out") {
                opts.outDir = value();
                if (opts.outDir.empty()) throw ConfigError("--out: the output directory is empty");
            } else if (a == "--quantity") opts.quantity = parseCompareQuantity(value());
            else if (a == "--mask") opts.maskFile = value();
            else if (a == "--background") {
                std::string v = value();
                char* end = nullptr;
                double x = std::strtod(v.c_str(), &end);
                if (v.empty() || *end || !std::isfinite(x)) throw ConfigError("--background '" + v + "': expected a number");
                opts.background = x;
            } else if (a.rfind("--", 0) == 0) {
                throw ConfigError("--compare: option '" + a + "' does not apply (--out, --quantity, --mask, --background)");
            } else files.push_back(a);
        }
        if (files.size() != 2) throw ConfigError("--compare: expected two image files (IMAGE REFERENCE)");
        if (!opts.maskFile.empty() && opts.background)
            throw ConfigError("--compare: --mask and --background exclude each other");
    } catch (const ConfigError& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n%s", e.what(), kCompareUsage);
        return 2;
    }
    try {
        prepareOutputDirectory(opts.outDir);
        nlohmann::json j = compareImageFiles(files[0], files[1], opts);
        std::cout << j.dump(2) << "\n";
        const auto& c = j["compared"];
        std::cout << "  compared " << c["quantity"].get<std::string>() << " (" << c["channels"].get<std::string>()
                  << ", from " << c["quantity_from"].get<std::string>() << ") over " << c["compared_pixels"] << " of "
                  << c["total_pixels"] << " pixels: " << c["pixels"].get<std::string>() << "\n";
        std::cout << "  wrote " << opts.outDir << "/compare.json, error.heatmap.png\n";
        return 0;
    } catch (const OutputError& e) {
        std::fprintf(stderr, "rtgi-bench: --compare: %s\n", escapeControl(e.what()).c_str());
        return kExitOutput;
    } catch (const ConfigError& e) {
        std::fprintf(stderr, "rtgi-bench: --compare: %s\n", escapeControl(e.what()).c_str());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rtgi-bench: --compare: %s\n", escapeControl(e.what()).c_str());
        return 3;
    }
}

}  // namespace

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]) == "--compare") return compareCommand(argc, argv);
    CommandLine cl;
    try {
        cl = parseCommandLine(Host::Bench, argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", escapeControl(e.what()).c_str());
        return 2;
    }
    if (cl.help) {
        std::printf("rtgi-bench: headless real-time GI benchmark (OpenGL 4.5+ compute through EGL)\n%s\n\n%s\n%s",
                    versionString().c_str(), optionsHelp(Host::Bench).c_str(), settingsHelp().c_str());
        return 0;
    }
    if (cl.version) {
        std::printf("rtgi-bench %s\n", versionString().c_str());
        return 0;
    }
    if (cl.listDevices) {
        auto devs = gl::HeadlessContext::listDevices();
        for (std::size_t i = 0; i < devs.size(); ++i) std::printf("%zu: %s\n", i, devs[i].c_str());
        return 0;
    }
    try {
        if (!cl.sweep.empty()) return runSweepCommand(cl);
        if (!cl.validateOnly && !cl.printFrame) {  // an unwritable --out fails before any work
            prepareOutputDirectory(cl.run.outDir);
            checkOutputTarget(cl.run.outDir + "/results.json");
            checkOutputTarget(cl.run.outDir + "/results.csv");
        }
        Scene scene = loadScenes(cl.run.scenes);
        for (auto& w : scene.warnings) std::fprintf(stderr, "rtgi-bench: warning: %s\n", escapeControl(w).c_str());
        checkRadiometricRange(scene, settingsFor(scene, cl));  // also for --validate-only and --print-frame
        if (!cl.run.path.empty()) {  // issue 23: checked before any GL work (docs/temporal.md)
            const Path path = loadPath(cl.run.path, scene);
            if (!cl.framesGiven) cl.run.frames = path.frameCount();
            if (cl.run.reference && !cl.resolutionGiven) {
                // A reference per frame: small defaults keep a path on a CPU (llvmpipe) to minutes
                // (docs/temporal.md); --res (and --set reference.spp) choose the real size.
                cl.run.resolution = {kPathReferenceSize[0], kPathReferenceSize[1]};
                if (cl.run.referenceEvery == 0) cl.run.referenceEvery = kPathReferenceEvery;
                cl.assignments.insert(cl.assignments.begin(), {"reference.spp", std::to_string(kPathReferenceSpp)});
                std::fprintf(stderr,
                             "rtgi-bench: --path with --reference and no --res: %dx%d, a reference (%d spp unless "
                             "reference.spp is set) every %d frames with the frame before it and the frames around "
                             "step events; --res, --reference-every and --set reference.spp change this\n",
                             cl.run.resolution.x, cl.run.resolution.y, kPathReferenceSpp, cl.run.referenceEvery);
            }
        }
        if (cl.printFrame) {  // the declared frame; no GL context needed
            std::cout << FramePlan::build(frameScript(), frameFamilies(), scene, settingsFor(scene, cl)).table();
            return 0;
        }
        if (cl.validateOnly) {
            // The scene's suggested settings must be valid too, and the frame must build from them.
            (void)FramePlan::build(frameScript(), frameFamilies(), scene, settingsFor(scene, cl));
            (void)resolveCamera(scene, settingsFor(scene, cl));  // an unknown view: the run's sentence (issue 28)
            std::printf("rtgi-bench: %s: valid (%zu triangles)\n", scene.name.c_str(), scene.triangleCount());
            return 0;
        }
        auto ctx = gl::HeadlessContext::create({cl.device, cl.debug});
        ProgressPrinter progressPrinter("rtgi-bench");  // warm-up, measured frames, reference samples on stderr
        nlohmann::json r = runBenchmark(ctx->info(), scene, settingsFor(scene, cl), cl.run);
        writeFileAtomic(cl.run.outDir + "/results.json", r.dump(2) + "\n");
        std::string csv = resultsCsvHeader() + "\n";
        for (auto& row : resultsCsvRows(r)) csv += row + "\n";
        writeFileAtomic(cl.run.outDir + "/results.csv", csv);
        std::cout << formatTimingTable(r);
        if (r.contains("temporal")) {
            const auto& t = r["temporal"];
            auto mean = [](const nlohmann::json& s) { return s.is_null() ? std::string("-") : s["mean"].dump(); };
            std::cout << "  temporal error (" << t["compared"].get<std::string>() << ", " << t["reference_frames"]
                      << " reference frames): rmse mean " << mean(t["rmse"]) << ", flicker mean " << mean(t["flicker"])
                      << ", disoccluded rmse mean " << mean(t["rmse_disoccluded"]) << ", lag events " << t["lag"].size()
                      << "\n";
        }
        if (r.contains("path"))
            std::cout << "  path " << r["path"]["name"].get<std::string>() << ": " << r["path"]["frames"]
                      << " frames at " << r["path"]["fps"] << " fps; wrote " << cl.run.outDir << "/temporal.csv\n";
        if (r.contains("error")) {
            const auto& e = r["error"];
            std::cout << "  error vs reference (" << e["compared"].get<std::string>() << ", "
                      << (e["reference"]["from_cache"].get<bool>() ? "from cache" : "rendered") << "): rmse "
                      << e["rmse"] << ", mae " << e["mae"] << ", psnr " << e["psnr"] << ", ssim " << e["ssim"] << ", skill "
                      << e["skill"] << "\n";
            if (e.contains("matching_bounce")) {
                const auto& mb = e["matching_bounce"];
                std::cout << "  vs matching-bounce reference (" << mb["bounces"] << " bounce(s), Lambert): rmse "
                          << mb["rmse"] << ", rmse of black " << mb["rmse_zero"] << ", skill " << mb["skill"]
                          << "; interior rel_rmse " << mb["interior"]["rel_rmse"] << ", skill "
                          << mb["interior"]["skill"] << "\n";
            }
            if (e.contains("stage")) {
                const auto& st = e["stage"];
                std::cout << "  stages (probe volume, " << st["probe_directions"] << " directions/cell): lookup rmse "
                          << st["lookup"]["rmse"] << " (skill " << st["lookup"]["skill"] << "), propagation rmse "
                          << st["propagation"]["rmse"] << " (adds " << st["propagation"]["rmse_delta"] << ")\n";
            }
        }
        std::cout << "  wrote " << cl.run.outDir << "/results.json, results.csv"
                  << (cl.run.writeImages ? ", final.png, final.pfm, final.exr and debug images" : "") << "\n";
        if (cl.run.check && r["check"]["non_finite"].get<std::uint64_t>() > 0) {
            std::fprintf(stderr, "rtgi-bench: --check found non-finite values (see results.json \"check\")\n");
            return 5;
        }
        return 0;
    } catch (const OutputError& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", escapeControl(e.what()).c_str());
        return kExitOutput;
    } catch (const SceneError& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", escapeControl(e.what()).c_str());
        return 3;
    } catch (const ConfigError& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", escapeControl(e.what()).c_str());
        return 2;
    } catch (const gl::ShaderError& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", escapeControl(e.what()).c_str());
        return 4;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rtgi-bench: %s\n", escapeControl(e.what()).c_str());
        return 4;
    }
}
