#include "bench/path_run.h"

#include "bench/temporal.h"
#include "gl/image_io.h"
#include "gl/output_files.h"
#include "render/progress.h"
#include "render/reference/metrics.h"
#include "render/reference/reference_kind.h"
#include "render/reference/reference_passes.h"
#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>

namespace rtgi {

std::vector<bool> referenceFrames(int frames, int every, const std::vector<int>& eventFrames) {
    std::vector<bool> r(std::size_t(std::max(frames, 0)), false);
    every = std::max(every, 1);
    for (int i = 0; i < frames; i += every) {
        r[std::size_t(i)] = true;
        if (i > 0) r[std::size_t(i - 1)] = true;  // the pair for flicker
    }
    if (frames > 0) r[std::size_t(frames - 1)] = true;
    for (int e : eventFrames)
        for (int i = std::max(e - 1, 0); i <= std::min(e + kEventWindow, frames - 1); ++i) r[std::size_t(i)] = true;
    return r;
}

namespace {

struct FrameRecord {
    double time = 0, updateMs = 0;
    std::int64_t uploadedBytes = 0;
    bool geometry = false, lights = false, transforms = false;
    std::optional<double> bvhMs;  // the reference's BVH rebuild (CPU) when this frame's reference rebuilt it
    bool referenced = false, fromCache = false;
    std::optional<double> rmse, rmseDebiased, flicker, rmseVisible, rmseDisoccluded, disoccludedFraction;
    std::map<std::string, double> filterDisoccluded;  // temporal pass -> pixels whose history it rejected
};

nlohmann::json summaryJson(const std::vector<std::optional<double>>& v) {
    Summary s = summarize(v);
    if (s.count == 0) return nullptr;
    return {{"mean", s.mean}, {"p95", s.p95}, {"max", s.max}, {"frames", s.count}};
}

std::string csvNumber(const std::optional<double>& v) {
    if (!v) return "";
    std::ostringstream o;
    o.precision(9);
    o << *v;
    return o.str();
}

// The directory of PATH holding an executable `name`, or "" (no shell involved).
std::string findOnPath(const std::string& name) {
    const char* env = std::getenv("PATH");
    std::string paths = env ? env : "";
    std::size_t start = 0;
    while (start <= paths.size()) {
        std::size_t end = paths.find(':', start);
        if (end == std::string::npos) end = paths.size();
        std::string dir = paths.substr(start, end - start);
        std::error_code ec;
        auto st = std::filesystem::status(std::filesystem::path(dir.empty() ? "." : dir) / name, ec);
        if (!ec && std::filesystem::is_regular_file(st) &&
            (st.permissions() & std::filesystem::perms::others_exec) != std::filesystem::perms::none)
            return (std::filesystem::path(dir.empty() ? "." : dir) / name).string();
        start = end + 1;
    }
    return "";
}

std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// --path-frames: path.mp4 from the PNG sequence through Debian's ffmpeg (H.264;
// odd sizes padded by one pixel). Returns the results.json entry.
nlohmann::json encodeVideo(const std::string& outDir, double fps) {
    const std::string ffmpeg = findOnPath("ffmpeg");
    if (ffmpeg.empty()) {
        std::fprintf(stderr, "rtgi-bench: --path-frames: ffmpeg is not on PATH, so no path.mp4 (the PNG sequence is "
                             "in %s/frames; apt-get install ffmpeg for the video)\n", outDir.c_str());
        return {{"frames", "frames/frame_%04d.png"}, {"mp4", nullptr}, {"why", "ffmpeg is not on PATH"}};
    }
    char rate[32];
    std::snprintf(rate, sizeof rate, "%.6g", fps);
    const std::string cmd = shellQuote(ffmpeg) + " -y -loglevel error -framerate " + rate + " -i " +
                            shellQuote(outDir + "/frames/frame_%04d.png") +
                            " -vf pad=ceil(iw/2)*2:ceil(ih/2)*2 -c:v libx264 -pix_fmt yuv420p " +
                            shellQuote(outDir + "/path.mp4");
    const int rc = std::system(cmd.c_str());
    if (rc != 0) {
        std::fprintf(stderr, "rtgi-bench: --path-frames: ffmpeg failed (exit status %d), so no path.mp4: %s\n", rc,
                     cmd.c_str());
        return {{"frames", "frames/frame_%04d.png"}, {"mp4", nullptr}, {"why", "ffmpeg failed"}};
    }
    return {{"frames", "frames/frame_%04d.png"}, {"mp4", "path.mp4"}};
}

}  // namespace

nlohmann::json runPathFrames(Renderer& renderer, const Path& path, const RunOptions& opts, Camera& lastCamera) {
    using K = ReferenceSettings::Kind;
    gl::Profiler& profiler = renderer.profiler();
    const Scene rest = renderer.scene();
    const Settings settings = renderer.settings();
    const glm::ivec2 size = opts.resolution;
    const int frames = opts.frames;

    std::vector<int> eventFrames;
    for (double e : path.events) {
        int f = int(std::ceil(e * path.fps - 1e-9));
        if (f >= 1 && f < frames) eventFrames.push_back(f);
    }
    const int every = opts.referenceEvery > 0 ? opts.referenceEvery : 1;
    const std::vector<bool> refs =
        opts.reference ? referenceFrames(frames, every, eventFrames) : std::vector<bool>(std::size_t(frames), false);

    std::unique_ptr<Renderer> ref;
    gl::Profiler refProfiler(false);
    K kind = K::Off;
    int channels = 3;
    double refSeconds = 0;
    int refFromCache = 0, refCount = 0;
    nlohmann::json refInfo;

    Scene state = rest;
    View prev;
    std::vector<FrameRecord> rec(static_cast<std::size_t>(frames));
    FloatImage prevTest, prevRef, prevDepth;
    int prevIndex = -1;
    const int total = opts.warmup + frames;
    for (int f = 0; f < total; ++f) {
        const bool warm = f < opts.warmup;
        const int i = f - opts.warmup;
        const double t = warm ? 0.0 : path.timeOfFrame(i);
        if (warm) progress::report("warm-up frames (path at t = 0)", f, opts.warmup);
        else progress::report("path frames", i, frames);
        // The scene state at t, from the rest scene (nothing carries over between frames).
        state.vertices = rest.vertices;
        state.lights = rest.lights;
        state.cameras = rest.cameras;
        evaluateScene(state, rest, &path, t);
        renderer.updateScene(state);
        const Camera cam = pathCamera(&path, t, resolveCamera(state, settings));
        profiler.setMeasuring(!warm);
        View v = makeView(cam, size, f == 0 ? nullptr : &prev, unsigned(f));
        renderer.render(v);
        prev = v;
        lastCamera = cam;
        if (progress::wantsSteps()) glFinish();
        if (warm) continue;
        FrameRecord& r = rec[std::size_t(i)];
        if (opts.pathFrames) {
            char name[32];
            std::snprintf(name, sizeof name, "/frame_%04d.png", i);
            std::filesystem::create_directories(opts.outDir + "/frames");
            writePng(opts.outDir + "/frames" + name, readTexture(renderer.resources().ldr));
        }
        // History rejected by the reprojecting filters (docs/temporal.md, "Disocclusion"): a counter
        // read back, so only on referenced frames (which read images back anyway), never a stall
        // on the others.
        for (const char* pass : {"ao.temporal", "ssr.temporal"}) {
            if (!refs[std::size_t(i)]) break;
            Pass* p = renderer.findPass(pass);
            bool skipped = !p;
            for (auto& sk : renderer.skipped()) skipped = skipped || sk.name == pass;
            if (skipped) continue;
            for (auto& [k, val] : p->stats())
                if (k == "disoccluded_pixels") r.filterDisoccluded[pass] = val;
        }
        r.time = t;
        r.updateMs = renderer.lastSceneUpdate().ms;
        r.geometry = renderer.lastSceneUpdate().geometry;
        r.transforms = renderer.lastSceneUpdate().transforms;
        r.uploadedBytes = renderer.lastSceneUpdate().uploadedBytes;
        r.lights = renderer.lastSceneUpdate().lights;
        if (!refs[std::size_t(i)]) continue;

        // The reference of this frame's scene state and camera (cached by both: render/reference/reference_cache.h).
        if (!ref) {
            kind = opts.referenceKind != K::Off ? opts.referenceKind : referenceKindFor(settings, renderer.resources());
            channels = kind == K::Ao ? 1 : 3;
            Settings rs = referenceRunSettings(settings, kind);
            if (rs.reference.converging())
                throw ConfigError("--path --reference: a converging reference (reference.target_noise / "
                                  "target_stderr) is not supported per frame; set reference.spp instead");
            ref = std::make_unique<Renderer>(rest, rs, refProfiler);
        }
        const gl::Texture& tested = comparedTexture(kind, renderer.resources());
        if (!tested) throw ConfigError("--reference: this path run produced no image of the compared kind");
        ref->updateScene(state);
        const bool rebuilt = refCount == 0 || ref->lastSceneUpdate().geometry;  // ref.bvh_upload rebuilds on its next use
        ref->render(makeView(cam, size, nullptr, 0));
        if (rebuilt)
            if (Pass* bvhPass = ref->findPass("ref.bvh_upload"))
                for (auto& [k, val] : bvhPass->stats())
                    if (k == "build_ms") r.bvhMs = val;
        auto* out = dynamic_cast<ReferenceOutput*>(ref->findPass(kind == K::Ao ? "ref.ao" : "ref.path"));
        if (!out) throw ConfigError("--reference: the reference pass did not run");
        for (auto& [k, val] : ref->findPass(kind == K::Ao ? "ref.ao" : "ref.path")->stats()) {
            if (k == "seconds") refSeconds += val;
            refInfo[k] = val;  // the last frame's
        }
        ++refCount;
        if (out->fromCache()) ++refFromCache;
        r.referenced = true;
        r.fromCache = out->fromCache();
        FloatImage I = readTexture(tested), R = readTexture(out->mean()), se = readTexture(out->standardError());
        FloatImage depth = readTexture(renderer.resources().gbuffer.linearDepth);
        std::vector<std::uint8_t> mask(std::size_t(size.x) * std::size_t(size.y));
        for (std::size_t p = 0; p < mask.size(); ++p) mask[p] = depth.data[p * std::size_t(depth.channels)] > 0 ? 1 : 0;
        RmseUncertainty u = rmseUncertainty(I, R, se, channels, mask);
        r.rmse = u.rmse;
        r.rmseDebiased = u.rmseDebiased;
        if (prevIndex == i - 1 && i > 0) {
            FrameGeometry g;
            g.depth = depth;
            g.view = glm::dmat4(v.view);
            g.prevView = glm::dmat4(v.prevView);
            g.prevProj = glm::dmat4(v.prevProj);
            g.tanHalfFovY = std::tan(0.5 * double(v.fovY));
            g.aspect = double(size.x) / double(size.y);
            std::vector<std::int32_t> prevPixel = reprojectPixels(g, prevDepth);
            r.flicker = flickerRms(I, R, prevTest, prevRef, prevPixel, channels);
            std::vector<std::uint8_t> visible(mask.size()), dis(mask.size());
            std::size_t geometry = 0, disoccluded = 0;
            for (std::size_t p = 0; p < mask.size(); ++p) {
                visible[p] = prevPixel[p] >= 0;
                dis[p] = prevPixel[p] == -1;
                geometry += prevPixel[p] != -2;
                disoccluded += dis[p];
            }
            r.rmseVisible = maskedRmse(I, R, visible, channels);
            r.rmseDisoccluded = maskedRmse(I, R, dis, channels);
            r.disoccludedFraction = geometry ? double(disoccluded) / double(geometry) : 0.0;
        }
        prevTest = std::move(I);
        prevRef = std::move(R);
        prevDepth = std::move(depth);
        prevIndex = i;
    }
    profiler.flush();
    progress::report("path frames", frames, frames);
    // Back to the rest state: a sweep reuses the renderer.
    renderer.updateScene(rest);

    // Per-frame CSV: timings per pass, the scene update and the errors.
    const auto& timings = profiler.frameTimings();
    std::vector<std::string> passNames;
    for (auto& pt : profiler.results())
        if (pt.name != "frame") passNames.push_back(pt.name);
    std::ostringstream csv;
    csv << "frame,time,frame_ms,scene_update_ms,scene_upload_bytes,geometry_moved,geometry_by_transforms,lights_changed";
    for (auto& n : passNames) csv << ",ms." << n;
    csv << ",referenced,reference_from_cache,bvh_build_ms,rmse,rmse_debiased,flicker,disoccluded_fraction,rmse_visible,rmse_disoccluded";
    const char* filters[] = {"ao.temporal", "ssr.temporal"};
    for (const char* f : filters) csv << ",disoccluded." << f;
    csv << "\n";
    std::vector<double> updateMs, uploaded, bvhMs;
    for (int i = 0; i < frames; ++i) {
        const FrameRecord& r = rec[std::size_t(i)];
        const std::map<std::string, double>* tm = std::size_t(i) < timings.size() ? &timings[std::size_t(i)] : nullptr;
        auto ms = [&](const std::string& n) -> std::optional<double> {
            if (!tm) return std::nullopt;
            auto it = tm->find(n);
            return it == tm->end() ? std::optional<double>(0.0) : std::optional<double>(it->second);
        };
        csv << i << "," << csvNumber(r.time) << "," << csvNumber(ms("frame")) << "," << csvNumber(r.updateMs) << ","
            << r.uploadedBytes << "," << int(r.geometry) << "," << int(r.transforms) << "," << int(r.lights);
        for (auto& n : passNames) csv << "," << csvNumber(ms(n));
        csv << "," << int(r.referenced) << "," << int(r.fromCache) << "," << csvNumber(r.bvhMs) << "," << csvNumber(r.rmse) << ","
            << csvNumber(r.rmseDebiased) << "," << csvNumber(r.flicker) << "," << csvNumber(r.disoccludedFraction) << ","
            << csvNumber(r.rmseVisible) << "," << csvNumber(r.rmseDisoccluded);
        for (const char* f : filters) {
            auto it = r.filterDisoccluded.find(f);
            csv << "," << (it == r.filterDisoccluded.end() ? std::string() : csvNumber(it->second));
        }
        csv << "\n";
        updateMs.push_back(r.updateMs);
        uploaded.push_back(double(r.uploadedBytes));
        if (r.bvhMs) bvhMs.push_back(*r.bvhMs);
    }
    std::filesystem::create_directories(opts.outDir);
    writeFileAtomic(opts.outDir + "/temporal.csv", csv.str());

    nlohmann::json j;
    j["name"] = path.name;
    j["source"] = path.source;
    if (!path.description.empty()) j["description"] = path.description;
    j["fps"] = path.fps;
    j["duration"] = path.duration;
    j["path_frames"] = path.frameCount();
    j["frames"] = frames;
    j["time"] = "frame i renders the scene state at t = i / fps; warm-up frames at t = 0";
    gl::TimingStats us = gl::computeStats(updateMs);
    int moved = 0, lit = 0;
    for (auto& r : rec) {
        moved += r.geometry;
        lit += r.lights;
    }
    j["scene_update_ms"] = {{"median", us.median}, {"max", us.max}, {"mean", us.mean},
                            {"what", "CPU: Renderer::updateScene (the states compared, the GPU scene's update by "
                                     "per-object transforms or a vertex re-upload, the light update; submission only: "
                                     "the transform dispatch is the next frame's scene.transform)"}};
    gl::TimingStats ub = gl::computeStats(uploaded);
    j["scene_upload_bytes"] = {{"median", ub.median}, {"max", ub.max}, {"mean", ub.mean},
                               {"what", "bytes the GPU scene uploaded per frame (vertices, object transforms, lights)"}};
    int byTransforms = 0;
    for (auto& r : rec) byTransforms += r.transforms;
    j["frames_geometry_by_transforms"] = byTransforms;
    if (!bvhMs.empty()) {
        gl::TimingStats bs = gl::computeStats(bvhMs);
        j["bvh_build_ms"] = {{"median", bs.median}, {"max", bs.max}, {"mean", bs.mean}, {"frames", bs.samples},
                             {"what", "CPU: the reference's BVH build (binned SAH) on referenced frames that rebuilt "
                                      "it (the first one, then those whose geometry moved)"}};
    }
    j["frames_geometry_moved"] = moved;
    j["frames_lights_changed"] = lit;
    j["csv"] = "temporal.csv";
    if (opts.pathFrames) j["video"] = encodeVideo(opts.outDir, path.fps);
    if (!opts.reference) return j;

    std::vector<std::optional<double>> rmse, deb, flick, vis, dis, frac;
    for (auto& r : rec) {
        rmse.push_back(r.rmse);
        deb.push_back(r.rmseDebiased);
        flick.push_back(r.flicker);
        vis.push_back(r.rmseVisible);
        dis.push_back(r.rmseDisoccluded);
        frac.push_back(r.disoccludedFraction);
    }
    nlohmann::json tj;
    tj["compared"] = kind == K::Ao ? "ao" : kind == K::Indirect ? "indirectDiffuse" : "hdr";
    tj["kind"] = kind == K::Ao ? "ao" : kind == K::Indirect ? "indirect" : "full";
    tj["reference_every"] = every;
    tj["reference_frames"] = refCount;
    tj["references_from_cache"] = refFromCache;
    tj["reference_seconds"] = refSeconds;
    tj["reference"] = refInfo;
    tj["rmse"] = summaryJson(rmse);
    tj["rmse_debiased"] = summaryJson(deb);
    tj["flicker"] = summaryJson(flick);
    tj["rmse_visible"] = summaryJson(vis);
    tj["rmse_disoccluded"] = summaryJson(dis);
    tj["disoccluded_fraction"] = summaryJson(frac);
    tj["reprojection"] = "camera matrices, nearest pixel, relative depth tolerance " +
                         std::to_string(kReprojectionDepthTolerance);
    nlohmann::json lags = nlohmann::json::array();
    for (int e : eventFrames) {
        Lag l = lagAfter(rmse, e);
        lags.push_back({{"event_frame", e}, {"event_time", path.timeOfFrame(e)}, {"level_before", l.levelBefore},
                        {"peak", l.peak}, {"frames", l.frames ? nlohmann::json(*l.frames) : nlohmann::json(nullptr)},
                        {"tolerance", 0.1}});
    }
    tj["lag"] = lags;
    tj["formulas"] = "docs/temporal.md";
    j["temporal"] = tj;
    return j;
}

}  // namespace rtgi
