// ref.bvh_upload -> ref.ao | ref.path: the ray-traced reference (SPEC 7.1).
#include "render/reference/reference_passes.h"

#include "render/gpu_scene.h"
#include "render/gpu_types.h"
#include "render/progress.h"
#include "render/reference/reference_cache.h"
#include "scene/bvh.h"
#include "scene/emitters.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

namespace rtgi {

gl::Defines ReferenceConstants::defines(bool haveEmitters) const {
    gl::Defines d;
    if (kind == ReferenceSettings::Kind::Full) d.push_back({"RTGI_REF_FULL", ""});
    if (diffuseOnly) d.push_back({"RTGI_REF_DIFFUSE_ONLY", ""});
    if (lightSampling && haveEmitters) d.push_back({"RTGI_REF_EMITTER_NEE", ""});
    if (kind == ReferenceSettings::Kind::Indirect && emissionIsDirect && haveEmitters)
        d.push_back({"RTGI_REF_EMISSION_IS_DIRECT", ""});
    if (kind != ReferenceSettings::Kind::Ao && caustics != ReferenceSettings::Caustics::On && !diffuseOnly) {
        d.push_back({caustics == ReferenceSettings::Caustics::Off ? "RTGI_REF_CAUSTICS_OFF" : "RTGI_REF_CAUSTICS_REGULARIZED", ""});
        d.push_back(gl::floatDefine("RTGI_REF_CAUSTIC_ROUGHNESS", causticRoughness));
    }
    return d;
}

// Paths (AO: rays) per pixel per dispatch times pixels: at most this many per dispatch.
constexpr double kMaxSamplesPerDispatch = 1920.0 * 1080.0 * 4.0;

ReferenceConstants referenceConstants(const Settings& s, const Aabb&) {
    ReferenceConstants c;
    c.kind = s.reference.kind;
    c.spp = s.reference.spp;
    // AO rays are cheap (one any-hit traversal); a path costs several.
    c.samplesPerDispatch = std::min(c.spp, c.kind == ReferenceSettings::Kind::Ao ? 16 : 4);
    c.seed = unsigned(s.reference.seed);
    c.bounces = s.reference.bounces;
    c.rayLength = s.ao.radius;
    c.diffuseOnly = !s.reference.specular;
    c.lightSampling = s.reference.lightSampling;
    c.emissionIsDirect = s.light.emissiveLights;
    c.caustics = s.reference.caustics;
    c.causticRoughness = s.reference.causticRoughness;
    c.converging = s.reference.converging();
    // Secondary-ray origins: offsetRayOrigin (bvh.glsl) from the point's own
    // floating-point magnitude; first rays from G-buffer points add 4 ulps of
    // the scene's reach from the camera (the shader reads the BVH root) and
    // the snapped-coverage term from the projection (gbufferRayOrigin).
    return c;
}

namespace {

// Built once per renderer configuration, shared by the tracing passes.
struct ReferenceState {
    gl::Buffer nodes, triangles;
    // Emissive triangles: (id, area CDF as float bits) pairs, count, total area.
    gl::Buffer emitters;
    int emitterCount = 0;
    float emitterArea = 0;
    std::size_t nodeCount = 0, triangleCount = 0;
    int depth = 0;
    double buildMs = 0;
    std::uint64_t geometryVersion = 0;  // GpuScene::geometryVersion the BVH was built from
};

class BvhUploadPass final : public Pass {
public:
    explicit BvhUploadPass(std::shared_ptr<ReferenceState> st) : st_(std::move(st)) {}
    std::string name() const override { return "ref.bvh_upload"; }
    void declare(PassDecl&, const Scene&, const Settings&) const override {}
    void execute(FrameContext& ctx) override {
        // Built once; rebuilt when a moving scene rewrote the vertices (issue 23).
        if (st_->nodes && st_->geometryVersion == ctx.gpuScene.geometryVersion()) return;
        st_->geometryVersion = ctx.gpuScene.geometryVersion();
        auto t0 = std::chrono::steady_clock::now();
        Bvh bvh = buildBvh(sceneTriangles(ctx.scene));
        st_->buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (bvh.triangles.empty()) {  // an empty scene: one leaf with an empty box, never hit
            bvh.nodes.assign(1, gpu::BvhNode{glm::vec3(1e30f), 0, glm::vec3(-1e30f), 0});
            bvh.triangles.assign(1, gpu::BvhTriangle{});
        }
        st_->nodeCount = bvh.nodes.size();
        st_->triangleCount = ctx.scene.triangleCount();
        st_->depth = bvh.depth;
        st_->nodes = gl::Buffer(ctx.ledger, "ref.bvh.nodes", std::int64_t(bvh.nodes.size() * sizeof(gpu::BvhNode)),
                                bvh.nodes.data(), 0);
        st_->triangles = gl::Buffer(ctx.ledger, "ref.bvh.triangles",
                                    std::int64_t(bvh.triangles.size() * sizeof(gpu::BvhTriangle)), bvh.triangles.data(), 0);
        // Light sampling table over the emissive area (the materials after
        // overrides, as the path tracer's material table holds them).
        std::vector<std::uint32_t> table;
        double cdf = 0;
        for (auto& e : emissiveTriangles(ctx.scene, resolveMaterials(ctx.scene, ctx.settings))) {
            cdf += e.area;
            float f = float(cdf);
            std::uint32_t bits;
            std::memcpy(&bits, &f, 4);
            table.push_back(e.triangle);
            table.push_back(bits);
        }
        st_->emitterCount = int(table.size() / 2);
        st_->emitterArea = float(cdf);
        if (table.empty()) table.assign(2, 0u);
        st_->emitters = gl::Buffer(ctx.ledger, "ref.emitters", std::int64_t(table.size() * 4), table.data(), 0);
    }
    std::vector<std::pair<std::string, double>> stats() override {
        return {{"nodes", double(st_->nodeCount)}, {"triangles", double(st_->triangleCount)},
                {"emissive_triangles", double(st_->emitterCount)}, {"emissive_area", double(st_->emitterArea)},
                {"depth", double(st_->depth)}, {"build_ms", st_->buildMs}};
    }

private:
    std::shared_ptr<ReferenceState> st_;
};

class TracePass final : public Pass, public ReferenceOutput {
public:
    TracePass(std::shared_ptr<ReferenceState> st, bool ao) : st_(std::move(st)), ao_(ao) {}
    std::string name() const override { return ao_ ? "ref.ao" : "ref.path"; }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if ((s.reference.kind == ReferenceSettings::Kind::Ao) != ao_)
            return d.skip(ao_ ? "reference is a path-traced image" : "reference=ao traces AO rays only");
        d.read(R::linearDepth).read(R::normal);
        if (!ao_) d.read(R::albedo).read(R::material).read(R::emissive);
        d.output("mean", &mean_).output("stderr", &se_);
        if (ao_) {
            d.debugImage("ref.ao", &mean_).debugImage("ref.ao.stderr", &se_, 10.0f);
        } else {
            d.debugImage("ref.path", &ldr_).debugImage("ref.path.stderr", &se_, 10.0f);
        }
    }

    void execute(FrameContext& ctx) override {
        const View& v = ctx.view;
        if (progressive_ > 0) {
            executeProgressive(ctx);
            return;
        }
        if (mean_ && v.size == doneSize_ && v.view == doneView_ && v.proj == doneProj_ &&
            doneState_ == ctx.gpuScene.stateVersion())
            return;  // still valid: the same view of the same scene state
        ReferenceConstants c = referenceConstants(ctx.settings, ctx.scene.bounds());
        if (measure_ && c.converging) {
            executeConverging(ctx, c);
            return;
        }
        key_ = referenceCacheKey(ctx.scene, ctx.settings, c, v);
        const glm::ivec2 s = v.size;
        beginView(ctx);
        if (auto cached = loadCachedReference(ctx.settings.reference.cacheDir, key_);
            cached && cached->mean.width == s.x && cached->mean.height == s.y) {
            upload(mean_, cached->mean);
            upload(se_, cached->standardError);
            fromCache_ = true;
            seconds_ = cached->info.value("seconds", 0.0);
            rays_ = cached->info.value("rays", 0.0);
            spp_ = c.spp;
            if (!ao_) resolve(ctx, /*tonemapOnly=*/true);
            summarize(ctx);
            return;
        }
        fromCache_ = false;
        trace(ctx, c);
        CachedReference out{readTexture(mean_), readTexture(se_),
                            {{"settings", referenceSettingsJson(c)}, {"scene", ctx.scene.name},
                             {"resolution", std::to_string(s.x) + "x" + std::to_string(s.y)},
                             {"seconds", seconds_}, {"rays", rays_}}};
        storeCachedReference(ctx.settings.reference.cacheDir, key_, out);
        summarize(ctx);
    }

    std::vector<std::pair<std::string, double>> stats() override {
        return {{"spp", double(spp_)},         {"seconds", seconds_},
                {"rays", rays_},               {"rays_per_s", seconds_ > 0 ? rays_ / seconds_ : 0.0},
                {"from_cache", fromCache_ ? 1.0 : 0.0}, {"mean_stderr", meanStdErr_}};
    }

    void setProgressive(int samplesPerFrame) override { progressive_ = std::max(samplesPerFrame, 0); }
    void setConvergence(Measure measure) override { measure_ = std::move(measure); }
    nlohmann::json convergenceInfo() const override { return convergence_; }
    int samplesDone() const override { return progressive_ > 0 ? samplesDone_ : spp_; }

    const gl::Texture& mean() const override { return mean_; }
    const gl::Texture& standardError() const override { return se_; }
    bool fromCache() const override { return fromCache_; }
    std::string cacheKey() const override { return key_; }

private:
    // Traces in batches until planConvergence stops (docs/reference.md,
    // "Converging to a noise target"). The cache entry holds mean, standard
    // error and spp, from which the running moments are rebuilt
    // (M2 = SE²·n·(n − 1)), so a later run with a tighter target continues
    // the same sample sequence instead of starting over.
    void executeConverging(FrameContext& ctx, const ReferenceConstants& c) {
        const glm::ivec2 s = ctx.view.size;
        key_ = referenceCacheKey(ctx.scene, ctx.settings, c, ctx.view);
        beginView(ctx);
        const ReferenceSettings& rs = ctx.settings.reference;
        ConvergenceTarget target;
        target.relative = rs.targetNoise;
        target.absolute = rs.targetStderr;
        target.timeBudget = rs.timeBudget;
        target.maxSpp = rs.maxSpp;
        target.firstSpp = std::min(16, rs.maxSpp);
        int n = 0;
        double seconds = 0, rays = 0;
        fromCache_ = false;
        int cachedSpp = 0;
        if (auto cached = loadCachedReference(rs.cacheDir, key_);
            cached && cached->mean.width == s.x && cached->mean.height == s.y && cached->info.value("spp", 0) > 0) {
            n = cachedSpp = cached->info.value("spp", 0);
            seconds = cached->info.value("seconds", 0.0);
            rays = cached->info.value("rays", 0.0);
            upload(mean_, cached->mean);
            upload(se_, cached->standardError);
            resumeMoments(ctx, *cached, n);
            fromCache_ = true;
        }
        convergence_ = nlohmann::json();
        nlohmann::json checks = nlohmann::json::array();
        ConvergenceStep step;
        int batch = n == 0 ? target.firstSpp : 0;
        for (;;) {
            if (batch > 0) {
                trace(ctx, c, n, batch, n == 0);
                n += batch;
                seconds += seconds_;
                rays += rays_;
            } else if (!ao_) {
                resolve(ctx, /*tonemapOnly=*/true);  // a cached mean: make its LDR image
            }
            // Producer: resolve dispatch / cache upload (read back by measure_).
            glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
            ConvergenceCheck check = measure_(readTexture(mean_), readTexture(se_));
            check.spp = n;
            check.seconds = seconds;
            step = planConvergence(target, check);
            const double goal = targetNoiseFor(target, check.error);
            checks.push_back({{"spp", n}, {"seconds", seconds}, {"noise", check.noise}, {"error", check.error},
                              {"target", goal}});
            std::fprintf(stderr, "rtgi: %s: %d samples, noise %.4g (target %.4g at error %.4g), %.1f s\n",
                         name().c_str(), n, check.noise, goal, check.error, seconds);
            if (step.stop != StopReason::None) {
                convergence_ = {{"spp", n}, {"seconds", seconds}, {"noise", check.noise}, {"error", check.error},
                                {"target_noise", goal}, {"reached", step.stop == StopReason::Target},
                                {"stop", toString(step.stop)}, {"resumed_from_spp", cachedSpp},
                                {"relative_target", target.relative}, {"absolute_target", target.absolute},
                                {"time_budget", target.timeBudget}, {"max_spp", target.maxSpp}, {"checks", checks}};
                break;
            }
            batch = step.nextBatch;
            fromCache_ = false;  // more samples were needed than the cache held
        }
        spp_ = n;
        seconds_ = seconds;
        rays_ = rays;
        if (!fromCache_) {
            CachedReference out{readTexture(mean_), readTexture(se_),
                                {{"settings", referenceSettingsJson(c)}, {"scene", ctx.scene.name},
                                 {"resolution", std::to_string(s.x) + "x" + std::to_string(s.y)},
                                 {"seconds", seconds}, {"rays", rays}, {"spp", n}}};
            storeCachedReference(rs.cacheDir, key_, out);
        }
        summarize(ctx);
    }

    // Running moments from a finished reference: mean and n, M2 = SE²·n·(n−1).
    void resumeMoments(FrameContext& ctx, const CachedReference& r, int n) {
        const glm::ivec2 s = ctx.view.size;
        ensureAccumulation(ctx, s);
        FloatImage meanN = r.mean, m2 = r.standardError;
        meanN.channels = m2.channels = 4;
        const std::size_t pixels = std::size_t(s.x) * std::size_t(s.y);
        meanN.data.assign(pixels * 4, 0.0f);
        m2.data.assign(pixels * 4, 0.0f);
        const double k = double(n) * double(std::max(n - 1, 0));
        for (std::size_t i = 0; i < pixels; ++i) {
            for (std::size_t ch = 0; ch < 3; ++ch) {
                const std::size_t src = i * std::size_t(r.mean.channels) + std::min<std::size_t>(ch, std::size_t(r.mean.channels) - 1);
                const std::size_t se = i * std::size_t(r.standardError.channels) +
                                       std::min<std::size_t>(ch, std::size_t(r.standardError.channels) - 1);
                meanN.data[i * 4 + ch] = r.mean.data[src];
                const double e = r.standardError.data[se];
                m2.data[i * 4 + ch] = float(e * e * k);
            }
            meanN.data[i * 4 + 3] = float(n);
        }
        upload(accum_, meanN);
        upload(accumSq_, m2);
    }

    static void upload(const gl::Texture& t, const FloatImage& img) {
        glTextureSubImage2D(t.id(), 0, 0, 0, img.width, img.height, img.channels == 4 ? GL_RGBA : GL_RGB, GL_FLOAT,
                            img.data.data());
    }

    // The live comparison: samples [samplesDone_, samplesDone_ + progressive_)
    // on top of the accumulation, then resolve. The sample sequence is the
    // one the all-at-once trace uses (a pure function of pixel, sample index
    // and seed), so a converged progressive reference equals the normal one
    // up to float summation order.
    void executeProgressive(FrameContext& ctx) {
        const View& v = ctx.view;
        ReferenceConstants c = referenceConstants(ctx.settings, ctx.scene.bounds());
        const bool restart = !mean_ || v.size != doneSize_ || v.view != doneView_ || v.proj != doneProj_ ||
                             doneState_ != ctx.gpuScene.stateVersion();
        if (restart) {
            beginView(ctx);
            samplesDone_ = 0;
            fromCache_ = false;
            seconds_ = rays_ = 0;
        }
        if (samplesDone_ >= c.spp) return;  // converged to reference.spp
        const int n = std::min(progressive_, c.spp - samplesDone_);
        const double before = seconds_, raysBefore = rays_;
        trace(ctx, c, samplesDone_, n, restart);
        seconds_ += before;
        rays_ += raysBefore;
        samplesDone_ += n;
        spp_ = samplesDone_;
    }

    // The pass's textures for a view of size s (privateTextures lists them):
    // mean, standard error, the running sums of x and x² (RGBA32F), the LDR image (ref.path only).
    enum { kMean, kStdErr, kAccum, kAccumSq, kLdr };
    std::vector<gl::NamedTextureDesc> textures(glm::ivec2 s) const {
        std::vector<gl::NamedTextureDesc> t;
        for (const char* n : {".mean", ".stderr", ".accum", ".accum_sq"})
            t.push_back({name() + n, {GL_TEXTURE_2D, GL_RGBA32F, s.x, s.y}});
        if (!ao_) t.push_back({name() + ".ldr", {GL_TEXTURE_2D, GL_RGBA8, s.x, s.y}});
        return t;
    }
    void ensureAccumulation(FrameContext& ctx, glm::ivec2 s) {
        const auto t = textures(s);
        accum_.ensure(ctx.ledger, t[kAccum].label, t[kAccum].desc);
        accumSq_.ensure(ctx.ledger, t[kAccumSq].label, t[kAccumSq].desc);
    }

public:
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings&, glm::ivec2 view) const override { return textures(view); }

private:
    // Outputs for the frame's view and size, and that view remembered.
    void beginView(FrameContext& ctx) {
        const View& v = ctx.view;
        const glm::ivec2 s = v.size;
        const auto t = textures(s);
        mean_.ensure(ctx.ledger, t[kMean].label, t[kMean].desc);
        se_.ensure(ctx.ledger, t[kStdErr].label, t[kStdErr].desc);
        if (!ao_) ldr_.ensure(ctx.ledger, t[kLdr].label, t[kLdr].desc);
        doneSize_ = v.size;
        doneView_ = v.view;
        doneProj_ = v.proj;
        doneState_ = ctx.gpuScene.stateVersion();
    }

    void trace(FrameContext& ctx, const ReferenceConstants& c) { trace(ctx, c, 0, c.spp, true); }

    // Samples [begin, begin + count) into the accumulation (cleared first when
    // `clear`), then resolve.
    void trace(FrameContext& ctx, const ReferenceConstants& c, int begin, int count, bool clear) {
        const glm::ivec2 s = ctx.view.size;
        ensureAccumulation(ctx, s);
        if (clear) {
            accum_.clear();
            accumSq_.clear();
        }
        // One counter per dispatch, indexed by the dispatch's first sample.
        rayCounter_.ensure(ctx.ledger, "ref.ray_counters", std::int64_t(begin + count) * 4);
        rayCounter_.clearZero();
        const gl::Program& prog =
            ao_ ? ctx.programs.compute("ref/ao.comp") : ctx.programs.compute("ref/path.comp", c.defines(st_->emitterCount > 0));
        const GBuffer& g = ctx.res.gbuffer;
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_BVH_NODES, st_->nodes.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_BVH_TRIS, st_->triangles.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_REF_VERTICES, ctx.gpuScene.vertices().id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_REF_INDICES, ctx.gpuScene.indices().id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_REF_COUNTER, rayCounter_.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_REF_EMITTERS, st_->emitters.id());
        ctx.gpuScene.bindTables();
        if (ao_) {
            glBindTextureUnit(RTGI_REF_AO_TEX_LINEAR_DEPTH, g.linearDepth.id());
            glBindTextureUnit(RTGI_REF_AO_TEX_NORMAL, g.normal.id());
        } else {
            glBindTextureUnit(RTGI_REF_PATH_TEX_LINEAR_DEPTH, g.linearDepth.id());
            glBindTextureUnit(RTGI_REF_PATH_TEX_NORMAL, g.normal.id());
            glBindTextureUnit(RTGI_REF_TEX_ALBEDO, g.albedo.id());
            glBindTextureUnit(RTGI_REF_TEX_MATERIAL, g.material.id());
            glBindTextureUnit(RTGI_REF_TEX_EMISSIVE, g.emissive.id());
        }
        glBindImageTexture(RTGI_REF_IMG_ACCUM, accum_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
        glBindImageTexture(RTGI_REF_IMG_ACCUM_SQ, accumSq_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
        if (ao_) prog.set(RTGI_REF_LOC_RAY, c.rayLength);
        else if (c.lightSampling && st_->emitterCount > 0)
            prog.set(RTGI_REF_LOC_EMITTERS, glm::vec2(float(st_->emitterCount), st_->emitterArea));
        // Producer: gbuffer raster pass (framebuffer writes read through samplers).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glFinish();  // the clock below times the tracing alone
        auto t0 = std::chrono::steady_clock::now();
        rays_ = 0;
        const int end = begin + count;
        // Paths per dispatch bounded by pixels, not only by samples, so that
        // one dispatch stays well under a second (8.3 M = 4 paths per pixel at
        // 1080p; ~0.2 s on the atrium on an H100).
        const double pixels = double(s.x) * double(s.y);
        const int perDispatch =
            std::clamp(int(kMaxSamplesPerDispatch * (ao_ ? 4.0 : 1.0) / pixels), 1, c.samplesPerDispatch);
        const int total = c.converging ? end : c.spp;
        progress::report(ao_ ? "reference AO rays" : "reference paths", begin, total);
        for (int first = begin; first < end; first += perDispatch) {
            int n = std::min(perDispatch, end - first);
            // uvec4 uSamples (Program has no uvec4 setter).
            glProgramUniform4ui(prog.id(), RTGI_REF_LOC_SAMPLES, GLuint(first), GLuint(n), c.seed, GLuint(c.bounces));
            // Producer: the previous dispatch of this loop (accumulation images).
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
            gl::dispatch(prog, s.x, s.y);
            // One submission per dispatch: queued back to back, 64 dispatches of
            // ~0.2 s (the 2160p atrium) ran as one ~11 s submission and the
            // NVIDIA driver dropped it (ray counters garbage, zero variance);
            // 4 of them (0.9 s) ran. Waiting here also lets a terminal show
            // finished samples.
            glFinish();
            progress::report(ao_ ? "reference AO rays" : "reference paths", first + n, total);
        }
        glFinish();
        seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        // Producer: the dispatches above (ray counter atomics); read once, after timing.
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<std::uint32_t> counts(static_cast<std::size_t>(end));
        rayCounter_.download(counts.data(), std::int64_t(counts.size() * 4));
        // A trace the driver dropped (a reset, a watchdog) leaves the counters
        // undefined: more rays than any path can trace is an error, not a result.
        const double maxPerDispatch = pixels * double(perDispatch) * double(ao_ ? 1 : c.bounces + 1) * 16.0;
        for (int first = begin; first < end; first += perDispatch) {
            const double n = double(counts[std::size_t(first)]);
            if (n > maxPerDispatch)
                throw std::runtime_error(name() + ": the GPU reported " + std::to_string(std::uint64_t(n)) +
                                         " rays for one dispatch of at most " +
                                         std::to_string(std::uint64_t(maxPerDispatch)) +
                                         ": the trace was lost (driver reset?); lower the resolution or reference.spp");
            rays_ += n;
        }
        spp_ = end;
        resolve(ctx, false);
    }

    // Accumulation -> mean + standard error (+ tonemapped radiance); with
    // tonemapOnly the mean came from the cache and only the LDR is made.
    void resolve(FrameContext& ctx, bool tonemapOnly) {
        const glm::ivec2 s = ctx.view.size;
        gl::Defines d;
        if (!ao_) d.push_back({"RTGI_REF_RADIANCE", ""});
        if (tonemapOnly) d.push_back({"RTGI_REF_TONEMAP_ONLY", ""});
        const gl::Program& prog = ctx.programs.compute("ref/resolve.comp", d);
        // Producer: the last tracing dispatch (accumulation images) or the cache upload.
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
        if (tonemapOnly) {
            glBindImageTexture(RTGI_REF_IMG_MEAN, mean_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        } else {
            glBindImageTexture(RTGI_REF_IMG_ACCUM, accum_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
            glBindImageTexture(RTGI_REF_IMG_ACCUM_SQ, accumSq_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
            glBindImageTexture(RTGI_REF_IMG_MEAN, mean_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
            glBindImageTexture(RTGI_REF_IMG_STD_ERR, se_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        }
        if (!ao_) glBindImageTexture(RTGI_REF_IMG_LDR, ldr_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
        gl::dispatch(prog, s.x, s.y);
    }

    // mean_stderr: the RMS of the per-pixel standard error over the geometry
    // pixels (sky excluded) and the compared channels (AO: one), i.e. the
    // reference's own noise on the scale of the RMSE it is compared with
    // (docs/reference.md). The plain mean over all pixels understated it
    // (0.0217 vs 0.0323 on the atrium at 64 rays).
    void summarize(FrameContext& ctx) {
        // Producer: resolve dispatch / cache upload (read back below).
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
        FloatImage e = readTexture(se_), depth = readTexture(ctx.res.gbuffer.linearDepth);
        const int channels = ao_ ? 1 : 3;
        double sum = 0;
        std::size_t count = 0;
        for (std::size_t i = 0; i * 4 < e.data.size(); ++i) {
            if (!(depth.data[i * 4] > 0.0f)) continue;
            for (int c = 0; c < channels; ++c) sum += double(e.data[i * 4 + std::size_t(c)]) * e.data[i * 4 + std::size_t(c)];
            count += std::size_t(channels);
        }
        meanStdErr_ = count > 0 ? std::sqrt(sum / double(count)) : 0.0;
    }

    std::shared_ptr<ReferenceState> st_;
    bool ao_;
    gl::Texture accum_, accumSq_, mean_, se_, ldr_;
    gl::Buffer rayCounter_;
    glm::ivec2 doneSize_{0};
    glm::mat4 doneView_{0.0f}, doneProj_{0.0f};
    std::uint64_t doneState_ = 0;  // GpuScene::stateVersion of the scene it depicts (issue 23)
    std::string key_;
    bool fromCache_ = false;
    int spp_ = 0;
    int progressive_ = 0, samplesDone_ = 0;
    double seconds_ = 0, rays_ = 0, meanStdErr_ = 0;
    Measure measure_;
    nlohmann::json convergence_;
};

}  // namespace

Need referenceFamily(const Scene&, const Settings& s) {
    if (s.reference.kind == ReferenceSettings::Kind::Off) return Need::no("reference=off");
    return Need::yes();
}

void appendReferencePasses(std::vector<std::unique_ptr<Pass>>& frame) {
    auto st = std::make_shared<ReferenceState>();
    frame.push_back(std::make_unique<BvhUploadPass>(st));     // CPU binned-SAH BVH -> SSBOs (once)
    frame.push_back(std::make_unique<TracePass>(st, true));   // ref.ao: AO rays from the G-buffer surface
    frame.push_back(std::make_unique<TracePass>(st, false));  // ref.path: indirect or full path tracing
}

}  // namespace rtgi
