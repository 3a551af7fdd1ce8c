// Screen-space reflections (seed 000 4.4, 5.4; SPEC 5):
//   ssr.hiz -> ssr.trace -> ssr.resolve -> ssr.blur -> ssr.temporal -> ssr.shade
//   (+ ssr.diffuse_history with ssr.diffuse_history=on).
// The passes share one SsrState (private targets at trace resolution and the
// constant block); all of it is created inside execute(), so nothing is
// allocated when SSR is off.
#include "render/ssr/ssr_passes.h"

#include "gl/program.h"
#include "render/gpu_scene.h"
#include "render/ssr/ssr_constants.h"

#include <cstdio>

namespace rtgi {
namespace {

struct SsrState {
    gl::Texture hiz;                           // R32F min-depth pyramid (full resolution, all levels)
    gl::Texture hit, confidence, hitDistance;  // trace outputs
    gl::Texture resolved, blurTemp, blurred;   // premultiplied (L·c, c)
    gl::Texture temporal[2], temporalDepth[2]; // ping-pong temporal history + its linear depth
    gl::Texture directDiffuse;                 // diffuse-only direct light (ssr.diffuse_history)
    gl::Buffer ubo;
    int current = 0;                   // temporal[current] is this frame's output
    bool resolvedHadHistory = false;   // this frame's resolve fetched a valid history
    bool temporalValid = false;        // temporal[1 - current] holds a resolved frame
    bool diffuseHistoryValid = false;  // res.diffuseHistory holds the previous frame

    SsrSettings::Tracer tracer(const FrameContext& ctx) const { return effectiveSsrTracer(ctx.scene, ctx.settings); }
    glm::ivec2 traceSize(const FrameContext& ctx) const {
        return ssrTraceSize(ctx.view.size, ctx.settings.ssr.halfResolution);
    }
    // Uploads the constant block for this frame and binds it.
    void bindUniforms(FrameContext& ctx) {
        if (!ubo) ubo = gl::Buffer(ctx.ledger, "ssr.uniforms", sizeof(gpu::SsrUniforms));
        gpu::SsrUniforms u = makeSsrUniforms(ctx.settings.ssr, tracer(ctx), ctx.view.size, temporalValid);
        ubo.upload(&u, sizeof(u));
        glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_SSR, ubo.id());
    }
};

Need ssrNeed(const Scene& scene, const Settings& s) {
    if (s.ssr.tracer == SsrSettings::Tracer::Off) return Need::no("ssr=off");
    if (effectiveSsrTracer(scene, s) == SsrSettings::Tracer::Off) {
        char why[160];
        std::snprintf(why, sizeof why, "no material is glossy enough (roughness <= ssr.roughness_cutoff = %g)",
                      double(s.ssr.roughnessCutoff));
        return Need::no(why);
    }
    return Need::yes();
}

class SsrPass : public Pass {
public:
    explicit SsrPass(std::shared_ptr<SsrState> st) : st_(std::move(st)) {}
    Need needed(const Scene& scene, const Settings& s) const override { return ssrNeed(scene, s); }

protected:
    std::shared_ptr<SsrState> st_;
};

// ---- ssr.hiz ---------------------------------------------------------------
class HizPass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    std::string name() const override { return "ssr.hiz"; }
    Need needed(const Scene& scene, const Settings& s) const override {
        Need n = ssrNeed(scene, s);
        if (n.needed && effectiveSsrTracer(scene, s) != SsrSettings::Tracer::Hiz)
            return Need::no("only the hiz tracer reads the depth pyramid");
        return n;
    }
    std::vector<std::string> reads() const override { return {"gbuffer.linearDepth"}; }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 s = ctx.view.size;
        const int levels = hizLevelCount(s);
        st_->hiz.ensure(ctx.ledger, "ssr.hiz", {GL_TEXTURE_2D, GL_R32F, s.x, s.y, 1, levels});
        const gl::Program& copy = ctx.programs.compute("ssr/hiz.comp", {{"RTGI_HIZ_COPY", ""}});
        const gl::Program& reduce = ctx.programs.compute("ssr/hiz.comp");
        // Producer: gbuffer (framebuffer writes of linearDepth).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(0, ctx.res.gbuffer.linearDepth.id());
        glBindImageTexture(0, st_->hiz.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        gl::dispatch(copy, s.x, s.y);
        for (int l = 1; l < levels; ++l) {
            glm::ivec2 ls = hizLevelSize(s, l);
            // Producer: the previous dispatch of this loop (level l-1 image stores).
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            glBindImageTexture(1, st_->hiz.id(), l - 1, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
            glBindImageTexture(0, st_->hiz.id(), l, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
            gl::dispatch(reduce, ls.x, ls.y);
        }
    }
    std::vector<DebugImage> debugImages() const override { return {{"ssr.hiz.level0", &st_->hiz, 0.05f}}; }
    std::vector<Output> checkedOutputs(const FrameResources&) const override { return {{"ssr.hiz", &st_->hiz}}; }
};

// ---- ssr.trace -------------------------------------------------------------
class TracePass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    std::string name() const override { return "ssr.trace"; }
    std::vector<std::string> reads() const override {
        return {"gbuffer.linearDepth", "gbuffer.normal", "gbuffer.material"};
    }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 t = st_->traceSize(ctx);
        st_->hit.ensure(ctx.ledger, "ssr.hit", {GL_TEXTURE_2D, GL_RG16F, t.x, t.y});
        st_->confidence.ensure(ctx.ledger, "ssr.confidence", {GL_TEXTURE_2D, GL_R16F, t.x, t.y});
        st_->hitDistance.ensure(ctx.ledger, "ssr.hit_distance", {GL_TEXTURE_2D, GL_R16F, t.x, t.y});
        SsrSettings::Tracer tracer = st_->tracer(ctx);
        const gl::Program& prog =
            ctx.programs.compute("ssr/trace.comp", {{"RTGI_SSR_TRACER", std::to_string(ssrTracerId(tracer))}});
        st_->bindUniforms(ctx);
        const GBuffer& g = ctx.res.gbuffer;
        // Producers: gbuffer (framebuffer writes), ssr.hiz (image stores).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(0, g.linearDepth.id());
        glBindTextureUnit(1, g.normal.id());
        glBindTextureUnit(2, g.material.id());
        glBindTextureUnit(3, tracer == SsrSettings::Tracer::Hiz ? st_->hiz.id() : g.linearDepth.id());
        glBindImageTexture(0, st_->hit.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG16F);
        glBindImageTexture(1, st_->confidence.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
        glBindImageTexture(2, st_->hitDistance.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
        gl::dispatch(prog, t.x, t.y);
    }
    std::vector<DebugImage> debugImages() const override {
        return {{"ssr.trace.hit_mask", &st_->confidence, 1.0f},
                {"ssr.trace.hit_offset", &st_->hit, 1.0f},
                {"ssr.trace.hit_distance", &st_->hitDistance, 0.1f}};
    }
    std::vector<Output> checkedOutputs(const FrameResources&) const override {
        return {{"ssr.hit", &st_->hit, true}, {"ssr.confidence", &st_->confidence},
                {"ssr.hit_distance", &st_->hitDistance}};
    }
};

// ---- ssr.resolve -----------------------------------------------------------
class ResolvePass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    std::string name() const override { return "ssr.resolve"; }
    // With ssr.diffuse_history the previous frame's res.diffuseHistory is read
    // instead (written by ssr.diffuse_history at the end of the chain).
    std::vector<std::string> reads() const override { return {"gbuffer.velocity", "history"}; }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 t = st_->traceSize(ctx);
        const bool diffuse = ctx.settings.ssr.diffuseHistory;
        st_->resolved.ensure(ctx.ledger, "ssr.resolved", {GL_TEXTURE_2D, GL_RGBA16F, t.x, t.y});
        if (ctx.view.cut) st_->diffuseHistoryValid = false;
        const gl::Texture& history = diffuse ? ctx.res.diffuseHistory : ctx.res.history;
        bool have = bool(history) && (diffuse ? st_->diffuseHistoryValid : ctx.res.historyValid);
        st_->resolvedHadHistory = have;
        const gl::Program& prog = ctx.programs.compute("ssr/resolve.comp");
        st_->bindUniforms(ctx);
        // Producers: ssr.trace (image stores); post.history / ssr.diffuse_history of the previous frame.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(0, st_->hit.id());
        glBindTextureUnit(1, st_->confidence.id());
        glBindTextureUnit(2, ctx.res.gbuffer.velocity.id());
        glBindTextureUnit(3, have ? history.id() : st_->hit.id());  // unread without history
        prog.set(0, have ? 1 : 0);
        glBindImageTexture(0, st_->resolved.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        gl::dispatch(prog, t.x, t.y);
    }
    std::vector<DebugImage> debugImages() const override {
        return {{"ssr.resolve.reflection", &st_->resolved, 1.0f}};
    }
    std::vector<Output> checkedOutputs(const FrameResources&) const override {
        return {{"ssr.resolved", &st_->resolved}};
    }
};

// ---- ssr.blur --------------------------------------------------------------
class BlurPass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    std::string name() const override { return "ssr.blur"; }
    std::vector<std::string> reads() const override { return {"gbuffer.linearDepth", "gbuffer.normal"}; }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 t = st_->traceSize(ctx);
        st_->blurTemp.ensure(ctx.ledger, "ssr.blur_temp", {GL_TEXTURE_2D, GL_RGBA16F, t.x, t.y});
        st_->blurred.ensure(ctx.ledger, "ssr.blurred", {GL_TEXTURE_2D, GL_RGBA16F, t.x, t.y});
        const gl::Program& h = ctx.programs.compute("ssr/blur.comp");
        const gl::Program& v = ctx.programs.compute("ssr/blur.comp", {{"RTGI_BLUR_VERTICAL", ""}});
        st_->bindUniforms(ctx);
        glBindTextureUnit(1, ctx.res.gbuffer.linearDepth.id());
        glBindTextureUnit(2, ctx.res.gbuffer.normal.id());
        // Producer: ssr.resolve (image stores).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(0, st_->resolved.id());
        glBindImageTexture(0, st_->blurTemp.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        gl::dispatch(h, t.x, t.y);
        // Producer: the horizontal dispatch above.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(0, st_->blurTemp.id());
        glBindImageTexture(0, st_->blurred.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        gl::dispatch(v, t.x, t.y);
    }
    std::vector<Output> checkedOutputs(const FrameResources&) const override {
        return {{"ssr.blur_temp", &st_->blurTemp}, {"ssr.blurred", &st_->blurred}};
    }
};

// ---- ssr.temporal ----------------------------------------------------------
class TemporalPass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    std::string name() const override { return "ssr.temporal"; }
    std::vector<std::string> reads() const override { return {"gbuffer.linearDepth", "gbuffer.velocity"}; }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 t = st_->traceSize(ctx);
        for (int i = 0; i < 2; ++i) {
            const std::string n = std::to_string(i);
            if (st_->temporal[i].ensure(ctx.ledger, "ssr.temporal" + n, {GL_TEXTURE_2D, GL_RGBA16F, t.x, t.y}))
                st_->temporalValid = false;
            st_->temporalDepth[i].ensure(ctx.ledger, "ssr.temporal_depth" + n, {GL_TEXTURE_2D, GL_R32F, t.x, t.y});
            st_->temporal[i].setSampling(GL_LINEAR, GL_LINEAR);
            st_->temporalDepth[i].setSampling(GL_NEAREST, GL_NEAREST);
        }
        st_->current = 1 - st_->current;
        const int cur = st_->current, prev = 1 - cur;
        const gl::Program& prog = ctx.programs.compute("ssr/temporal.comp");
        st_->bindUniforms(ctx);
        // Producer: ssr.blur (image stores); the previous frame's ssr.temporal.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(0, st_->blurred.id());
        glBindTextureUnit(1, st_->temporal[prev].id());
        glBindTextureUnit(2, st_->temporalDepth[prev].id());
        glBindTextureUnit(3, ctx.res.gbuffer.linearDepth.id());
        glBindTextureUnit(4, ctx.res.gbuffer.velocity.id());
        glBindImageTexture(0, st_->temporal[cur].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        glBindImageTexture(1, st_->temporalDepth[cur].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        gl::dispatch(prog, t.x, t.y);
        // A frame resolved without history is all misses: never blend it in later.
        st_->temporalValid = st_->resolvedHadHistory;
    }
    std::vector<DebugImage> debugImages() const override {
        return {{"ssr.temporal.reflection", &st_->temporal[st_->current], 1.0f}};
    }
    std::vector<Output> checkedOutputs(const FrameResources&) const override {
        return {{"ssr.temporal", &st_->temporal[st_->current]},
                {"ssr.temporal_depth", &st_->temporalDepth[st_->current]}};
    }
};

// ---- ssr.shade -------------------------------------------------------------
class ShadePass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    std::string name() const override { return "ssr.shade"; }
    std::vector<std::string> reads() const override {
        return {"brdfLut", "gbuffer.linearDepth", "gbuffer.normal", "gbuffer.albedo", "gbuffer.material"};
    }
    std::vector<std::string> writes() const override { return {"specular", "specularOcclusion"}; }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 s = ctx.view.size;
        FrameResources& r = ctx.res;
        bool haveLpv = bool(r.specular);  // written by lpv.apply when LPV specular runs
        r.specular.ensure(ctx.ledger, "specular", {GL_TEXTURE_2D, GL_RGBA16F, s.x, s.y});
        r.specularOcclusion.ensure(ctx.ledger, "ssr.specular_occlusion", {GL_TEXTURE_2D, GL_R16F, s.x, s.y});
        const gl::Program& prog = ctx.programs.compute("ssr/shade.comp");
        st_->bindUniforms(ctx);
        const gl::Texture& reflection = st_->temporal[st_->current];
        // Producers: ssr.temporal, brdf_lut, lpv.apply (image stores).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        glBindTextureUnit(0, reflection.id());
        glBindTextureUnit(1, r.brdfLut.id());
        glBindTextureUnit(2, r.gbuffer.linearDepth.id());
        glBindTextureUnit(3, r.gbuffer.normal.id());
        glBindTextureUnit(4, r.gbuffer.albedo.id());
        glBindTextureUnit(5, r.gbuffer.material.id());
        prog.set(0, haveLpv ? 1 : 0);
        glBindImageTexture(0, r.specular.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA16F);
        glBindImageTexture(1, r.specularOcclusion.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
        gl::dispatch(prog, s.x, s.y);
    }
};

// ---- ssr.diffuse_history ---------------------------------------------------
// Seed 000 6.2.6 / SPEC erratum 6: the reflected radiance without specular
// light. post/direct.comp and post/compose.comp compiled with
// RTGI_DIFFUSE_ONLY give emission + diffuse direct + sky ambient·AO +
// indirect diffuse, kept for the next frame's ssr.resolve.
class DiffuseHistoryPass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    std::string name() const override { return "ssr.diffuse_history"; }
    Need needed(const Scene& scene, const Settings& s) const override {
        Need n = ssrNeed(scene, s);
        if (n.needed && !s.ssr.diffuseHistory) return Need::no("ssr.diffuse_history=off (full HDR history)");
        return n;
    }
    std::vector<std::string> reads() const override {
        return {"gbuffer.linearDepth", "gbuffer.normal", "gbuffer.albedo", "gbuffer.material", "gbuffer.emissive"};
    }
    std::vector<std::string> writes() const override { return {"diffuseHistory"}; }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 s = ctx.view.size;
        FrameResources& r = ctx.res;
        st_->directDiffuse.ensure(ctx.ledger, "ssr.direct_diffuse", {GL_TEXTURE_2D, GL_RGBA16F, s.x, s.y});
        r.diffuseHistory.ensure(ctx.ledger, "ssr.diffuse_history", {GL_TEXTURE_2D, GL_RGBA16F, s.x, s.y});
        r.diffuseHistory.setSampling(GL_LINEAR, GL_LINEAR);
        const gl::Defines diffuseOnly{{"RTGI_DIFFUSE_ONLY", ""}};
        const gl::Program& direct = ctx.programs.compute("post/direct.comp", diffuseOnly);
        const gl::Program& compose = ctx.programs.compute("post/compose.comp", diffuseOnly);
        const GBuffer& g = r.gbuffer;
        // Producers: gbuffer, shadow (raster writes); ao.*, lpv.apply (image stores).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(0, g.linearDepth.id());
        glBindTextureUnit(1, g.normal.id());
        glBindTextureUnit(2, g.albedo.id());
        glBindTextureUnit(3, g.material.id());
        glBindTextureUnit(4, g.emissive.id());
        bool shadow = bool(r.shadowMap);
        glBindTextureUnit(5, shadow ? r.shadowMap.id() : 0);
        direct.set(0, shadow ? 1 : 0);
        ctx.gpuScene.bindTables();
        glBindImageTexture(0, st_->directDiffuse.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        gl::dispatch(direct, s.x, s.y);
        // Producer: the diffuse-only direct dispatch above.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(0, st_->directDiffuse.id());
        glBindTextureUnit(1, g.albedo.id());
        glBindTextureUnit(2, g.material.id());
        glBindTextureUnit(3, r.indirectDiffuse ? r.indirectDiffuse.id() : 0);
        glBindTextureUnit(4, 0);
        glBindTextureUnit(5, r.ao ? r.ao.id() : 0);
        bool aoInLpv = ctx.settings.ao.directional != AoSettings::Directional::Off && bool(r.indirectDiffuse) &&
                       bool(r.bentNormal.id() || r.s3ho.id());
        compose.set(0, glm::ivec4(bool(r.indirectDiffuse), 0, bool(r.ao), aoInLpv));
        glBindImageTexture(0, r.diffuseHistory.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        gl::dispatch(compose, s.x, s.y);
        for (int u = 3; u <= 5; ++u) glBindTextureUnit(GLuint(u), 0);
        st_->diffuseHistoryValid = true;
    }
    // res.diffuseHistory through writes(); the diffuse-only direct light is private.
    std::vector<Output> checkedOutputs(const FrameResources& res) const override {
        std::vector<Output> o = Pass::checkedOutputs(res);
        o.push_back({"ssr.direct_diffuse", &st_->directDiffuse});
        return o;
    }
};

}  // namespace

void appendSsrPasses(std::vector<std::unique_ptr<Pass>>& f) {
    auto st = std::make_shared<SsrState>();
    f.push_back(std::make_unique<HizPass>(st));       // min-depth pyramid (hiz tracer only)
    f.push_back(std::make_unique<TracePass>(st));     // ray march: hit offset + confidence
    f.push_back(std::make_unique<ResolvePass>(st));   // reproject the hit, fetch last frame's radiance
    f.push_back(std::make_unique<BlurPass>(st));            // separable edge-preserving Gaussian
    f.push_back(std::make_unique<TemporalPass>(st));        // seed 000 listing 11 reprojection
    f.push_back(std::make_unique<ShadePass>(st));           // split-sum × reflection × occlusion + LPV fill
    f.push_back(std::make_unique<DiffuseHistoryPass>(st));  // next frame's diffuse-only history
}

SsrSettings::Tracer effectiveSsrTracer(const Scene& scene, const Settings& s) {
    if (s.ssr.tracer == SsrSettings::Tracer::Off) return SsrSettings::Tracer::Off;
    if (s.ssr.tracer != SsrSettings::Tracer::Auto) return s.ssr.tracer;  // forced on by the user
    // auto: the seed's linear tracer when a drawn material, after overrides
    // (floor.roughness), is at most ssr.roughness_cutoff rough.
    const std::vector<Material> mats = resolveMaterials(scene, s);
    for (const DrawRange& d : scene.draws)
        if (mats[std::size_t(d.material)].roughness <= s.ssr.roughnessCutoff) return SsrSettings::Tracer::Linear;
    return SsrSettings::Tracer::Off;
}

}  // namespace rtgi
