#include "bench/run.h"

#include "gl/image_files.h"
#include "gl/image_io.h"
#include "bench/path_run.h"
#include "gl/input_files.h"
#include "bench/reference_compare.h"
#include "bench/results_csv.h"
#include "render/memory_budget.h"
#include "render/progress.h"
#include "render/renderer.h"
#include "render/visibility/visibility.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace rtgi {

namespace {

nlohmann::json stats(const gl::TimingStats& s) {
    return {{"median", s.median}, {"min", s.min}, {"max", s.max}, {"mean", s.mean}};
}

void writeTexture(const std::string& dir, const std::string& name, const gl::Texture& tex, float scale = 1.0f,
                  bool srgb = true) {
    if (!tex) return;
    FloatImage img = readTexture(tex);
    GLenum f = tex.format();
    if (f == GL_R32F || f == GL_R16F || f == GL_R8)  // single channel: show as grey, not red
        for (std::size_t i = 0; i < img.data.size(); i += 4) img.data[i + 1] = img.data[i + 2] = img.data[i];
    writePng(dir + "/" + name + ".png", img, scale, srgb);
}

}  // namespace

nlohmann::json runBenchmark(const gl::ContextInfo& info, const Scene& scene, const Settings& settings,
                            const RunOptions& opts) {
    gl::Profiler profiler(info.timerQuery);
    Renderer renderer(scene, settings, profiler);
    return runBenchmark(info, renderer, opts);
}

nlohmann::json runBenchmark(const gl::ContextInfo& info, Renderer& renderer, const RunOptions& opts) {
    // Before the first frame allocates anything (render/memory_budget.h).
    for (auto& w : renderer.warnings()) std::fprintf(stderr, "rtgi-bench: warning: %s\n", escapeControl(w).c_str());
    checkMemoryBudget(renderer, opts.resolution, opts.maxMemory);
    gl::Profiler& profiler = renderer.profiler();
    profiler.reset();
    const Scene& scene = renderer.scene();
    const Settings& settings = renderer.settings();
    renderer.setCheck(opts.check);
    Camera cam = resolveCamera(scene, settings);
    nlohmann::json pathResult;
    if (!opts.path.empty()) {  // a moving scene (issue 23): bench/path_run.h
        const Path path = loadPath(opts.path, scene);
        pathResult = runPathFrames(renderer, path, opts, cam);
    }
    View prev;
    int total = opts.path.empty() ? opts.warmup + opts.frames : 0;
    for (int f = 0; f < total; ++f) {
        const bool warm = f < opts.warmup;
        if (warm) progress::report("warm-up frames", f, opts.warmup);
        else progress::report("measured frames", f - opts.warmup, opts.frames);
        profiler.setMeasuring(!warm);
        View v = makeView(cam, opts.resolution, f == 0 ? nullptr : &prev, unsigned(f));
        renderer.render(v);
        prev = v;
        if (progress::wantsSteps()) glFinish();  // a terminal shows each frame: count finished ones
        if (f + 1 == opts.warmup) progress::report("warm-up frames", opts.warmup, opts.warmup);
    }
    profiler.flush();
    if (opts.path.empty()) progress::report("measured frames", opts.frames, opts.frames);

    nlohmann::json r;
    r["version"] = versionString();
    if (!opts.commandLine.empty()) r["command_line"] = opts.commandLine;
    r["device"] = info.renderer;
    r["driver"] = info.version;
    r["vendor"] = info.vendor;
    r["gl_version"] = std::to_string(info.major) + "." + std::to_string(info.minor);
    r["egl_device"] = info.device;
    r["timer"] = profiler.timer();
    r["scene"] = scene.name;
    if (!scene.suggestedSettings.empty()) {
        nlohmann::json ss = nlohmann::json::object();
        for (auto& [k, v] : scene.suggestedSettings) ss[k] = typedValue(v);
        r["scene_settings"] = ss;  // the scene's suggestions; "config" holds what took effect
    }
    r["triangles"] = scene.triangleCount();
    r["resolution"] = std::to_string(opts.resolution.x) + "x" + std::to_string(opts.resolution.y);
    r["frames"] = opts.frames;
    r["warmup"] = opts.warmup;
    nlohmann::json cfg = nlohmann::json::object();
    for (auto& [k, v] : describe(settings)) cfg[k] = typedValue(v);  // numbers as numbers
    r["config"] = cfg;
    if (const auto& e = renderer.enclosure()) {  // what lpv.coarse_iterations=auto was resolved from (docs/lpv.md, "Closed scenes")
        r["enclosure"] = {{"escaped", e->escaped},
                          {"rays", e->rays},
                          {"lit", e->lit},
                          {"closed", e->rays > 0 && e->escaped < double(settings.lpv.closedEscape)}};
    }
    // Which rasterizer produced the G-buffer, shadow map and RSM (docs/visibility.md);
    // "compute-32" / "compute-64": the two-pass 32-bit or the 64-bit atomic path.
    const std::string computeKind =
        visibilityOptions(settings).atomic64 && visibilityAtomic64Supported() ? "compute-64" : "compute-32";
    r["raster_path"] = useComputeRaster(settings) ? computeKind : std::string("hardware");
    // raster.path=auto keeps the light views (shadow maps, sun RSM) on the hardware rasterizer.
    r["raster_path_lights"] = useComputeRasterLightViews(settings) ? computeKind : std::string("hardware");
    r["camera"] = {{"position", {cam.position.x, cam.position.y, cam.position.z}},
                   {"target", {cam.target.x, cam.target.y, cam.target.z}},
                   {"fov", glm::degrees(cam.fovY)}, {"near", cam.near}, {"far", cam.far}};
    if (!pathResult.is_null()) {
        if (pathResult.contains("temporal")) {  // the temporal error at the top level, beside "error" of a still run
            r["temporal"] = pathResult["temporal"];
            pathResult.erase("temporal");
        }
        r["path"] = pathResult;
    }
    nlohmann::json passes = nlohmann::json::array();
    double totalMs = 0;
    for (auto& t : profiler.results()) {
        if (t.name == "frame") {
            totalMs = t.ms.median;
            continue;
        }
        passes.push_back({{"name", t.name}, {"gpu_ms", stats(t.ms)}, {"dispatches", t.dispatchesPerFrame}});
    }
    r["passes"] = passes;
    nlohmann::json skipped = nlohmann::json::array();
    for (auto& s : renderer.skipped()) skipped.push_back({{"name", s.name}, {"reason", s.reason}});
    r["skipped"] = skipped;
    r["total_ms"] = totalMs;
    nlohmann::json mem = {{"total", renderer.ledger().total()}};
    nlohmann::json per = nlohmann::json::object();
    for (auto& [k, v] : renderer.ledger().entries()) per[k] = v;
    mem["resources"] = per;
    r["memory_bytes"] = mem;
    nlohmann::json st = nlohmann::json::object();
    for (auto& p : renderer.passes())
        for (auto& [k, v] : p->stats()) st[p->name() + "." + k] = v;
    if (!st.empty()) r["stats"] = st;
    std::vector<std::string> warnings = scene.warnings;
    warnings.insert(warnings.end(), renderer.warnings().begin(), renderer.warnings().end());
    if (!warnings.empty()) r["warnings"] = warnings;
    if (opts.check) {
        nlohmann::json fc = nlohmann::json::array();
        std::uint64_t bad = 0;
        for (auto& c : renderer.finiteCounts()) {
            fc.push_back({{"pass", c.pass}, {"output", c.resource}, {"nan", c.nan}, {"inf", c.inf},
                          {"negative", c.negative}, {"fp16_saturated", c.fp16Saturated}});
            bad += c.nan + c.inf;
        }
        r["check"] = {{"outputs", fc}, {"non_finite", bad}};
    }

    if (opts.writeImages) {
        std::filesystem::create_directories(opts.outDir);
        FrameResources& res = renderer.resources();
        writeTexture(opts.outDir, "final", res.ldr, 1.0f, false);
        if (res.hdr) {
            FloatImage hdr = readTexture(res.hdr);
            writePfm(opts.outDir + "/final.pfm", hdr);
            // Half floats: the display image at a quarter of the float size
            // (11-bit mantissa is below the RGBA16F target's own precision).
            writeExr(opts.outDir + "/final.exr", hdr, 3, ExrPixel::Half);
        }
        writeTexture(opts.outDir, "gbuffer.albedo", res.gbuffer.albedo, 1.0f, true);
        {
            FloatImage n = readTexture(res.gbuffer.normal);
            for (std::size_t i = 0; i < n.data.size(); i += 4)
                for (int c = 0; c < 3; ++c) n.data[i + std::size_t(c)] = n.data[i + std::size_t(c)] * 0.5f + 0.5f;
            writePng(opts.outDir + "/gbuffer.normal.png", n);
            FloatImage d = readTexture(res.gbuffer.linearDepth);
            float far = 0;
            for (std::size_t i = 0; i < d.data.size(); i += 4) far = std::max(far, d.data[i]);
            for (std::size_t i = 0; i < d.data.size(); i += 4)
                d.data[i + 1] = d.data[i + 2] = d.data[i] = far > 0 ? d.data[i] / far : 0;
            writePng(opts.outDir + "/gbuffer.depth.png", d);
        }
        writeTexture(opts.outDir, "direct", res.direct, settings.post.exposure, true);
        writeTexture(opts.outDir, "indirect", res.indirectDiffuse, settings.post.exposure, true);
        if (res.indirectDiffuse) writePfm(opts.outDir + "/indirect.pfm", readTexture(res.indirectDiffuse));
        writeTexture(opts.outDir, "specular", res.specular, settings.post.exposure, true);
        writeTexture(opts.outDir, "ao", res.ao, 1.0f, false);
        for (auto& p : renderer.passes())
            for (auto& d : renderer.debugImages(*p))
                if (d.tex && *d.tex) writeTexture(opts.outDir, d.name, *d.tex, d.scale, false);
        r["images"] = opts.outDir;
    }
    if (opts.reference && opts.path.empty()) {  // a path's error is per frame: r["path"]["temporal"]
        r["error"] = compareWithReference(renderer, cam, opts.resolution, opts.outDir, opts.writeImages,
                                          opts.referenceKind, opts.warmup + opts.frames);
        // The frames above were timed without the reference passes; the
        // configuration this result describes is compared with this kind.
        r["config"]["reference"] = r["error"]["kind"];
    }
    return r;
}

std::string formatTimingTable(const nlohmann::json& r) {
    std::ostringstream o;
    o << "rtgi-bench: " << r["scene"].get<std::string>() << " at " << r["resolution"].get<std::string>() << ", "
      << r["frames"] << " frames after " << r["warmup"] << " warm-up, timer=" << r["timer"].get<std::string>();
    if (r["timer"] == "cpu") o << " (no GPU timer queries: glFinish + CPU clock per pass)";
    o << "\n  device: " << r["device"].get<std::string>() << " | " << r["driver"].get<std::string>() << "\n";
    o << std::left << std::setw(26) << "  pass" << std::right << std::setw(11) << "median ms" << std::setw(10)
      << "min" << std::setw(10) << "max" << std::setw(10) << "mean" << std::setw(12) << "dispatches" << "\n";
    o << std::fixed;
    for (auto& p : r["passes"]) {
        o << "  " << std::left << std::setw(24) << p["name"].get<std::string>() << std::right << std::setprecision(4)
          << std::setw(11) << p["gpu_ms"]["median"].get<double>() << std::setw(10) << p["gpu_ms"]["min"].get<double>()
          << std::setw(10) << p["gpu_ms"]["max"].get<double>() << std::setw(10) << p["gpu_ms"]["mean"].get<double>()
          << std::setprecision(1) << std::setw(12) << p["dispatches"].get<double>() << "\n";
    }
    o << "  " << std::left << std::setw(24) << "frame (total)" << std::right << std::setprecision(4) << std::setw(11)
      << r["total_ms"].get<double>() << "\n";
    for (auto& s : r["skipped"]) o << "  skipped " << s["name"].get<std::string>() << ": " << s["reason"].get<std::string>() << "\n";
    o << "  GPU memory: " << std::setprecision(2) << r["memory_bytes"]["total"].get<double>() / (1024.0 * 1024.0)
      << " MiB\n";
    return o.str();
}

}  // namespace rtgi
