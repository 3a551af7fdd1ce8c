// Screen-space reflections (seed 000 4.4, 5.4; SPEC 5):
//   ssr.hiz -> ssr.trace -> ssr.resolve -> ssr.blur -> ssr.temporal
//   -> ssr.shade (+ ssr.diffuse_history with ssr.diffuse_history=on).
// Blur and temporal filter are the shared chain of render/filter.h (the AO
// family's code) on the premultiplied RGBA16F reflection; at half resolution
// ssr.shade upsamples it with the chain's joint bilateral weights (lib/filter.glsl).
// The passes share one SsrState (private targets and the constant block); all
// of it is created inside execute(), so nothing is allocated when SSR is off.
#include "render/ssr/ssr_passes.h"
#include "render/passes/core_passes.h"

#include "gl/program.h"
#include "render/filter.h"
#include "render/gpu_scene.h"
#include "render/noise.h"
#include "render/ssr/ssr_constants.h"

#include <cstdio>

namespace rtgi {
namespace {

// The reflection's value format in the shared filter chain: premultiplied (L·c, c).
const FilterFormat kSsrFormat{GL_RGBA16F, "rgba16f"};

// The family's own textures (view size `v`, trace size `t`): execute() allocates
// from these, privateTextures() lists them for the memory estimate.
gl::NamedTextureDesc hizTex(glm::ivec2 v) { return {"ssr.hiz", {GL_TEXTURE_2D, GL_R32F, v.x, v.y, 1, hizLevelCount(v)}}; }
gl::NamedTextureDesc hitTex(glm::ivec2 t) { return {"ssr.hit", {GL_TEXTURE_2D, GL_RG16F, t.x, t.y}}; }
gl::NamedTextureDesc confidenceTex(glm::ivec2 t) { return {"ssr.confidence", {GL_TEXTURE_2D, GL_R16F, t.x, t.y}}; }
gl::NamedTextureDesc hitDistanceTex(glm::ivec2 t) { return {"ssr.hit_distance", {GL_TEXTURE_2D, GL_R16F, t.x, t.y}}; }
gl::NamedTextureDesc traceDepthTex(glm::ivec2 t) { return {"ssr.trace.depth", {GL_TEXTURE_2D, GL_R32F, t.x, t.y}}; }
gl::NamedTextureDesc traceNormalTex(glm::ivec2 t) { return {"ssr.trace.normal", {GL_TEXTURE_2D, GL_RGBA16F, t.x, t.y}}; }
gl::NamedTextureDesc resolvedTex(glm::ivec2 t) { return {"ssr.resolved", {GL_TEXTURE_2D, GL_RGBA16F, t.x, t.y}}; }
gl::NamedTextureDesc directDiffuseTex(glm::ivec2 v) { return {"ssr.direct_diffuse", {GL_TEXTURE_2D, GL_RGBA16F, v.x, v.y}}; }
glm::ivec2 traceSizeFor(const Settings& s, glm::ivec2 view) { return ssrTraceSize(view, s.ssr.halfResolution); }

struct SsrState {
    gl::Texture hiz;                           // R32F min-depth pyramid (full resolution, all levels)
    gl::Texture hit, confidence, hitDistance;  // trace outputs
    gl::Texture traceDepth, traceNormal;       // the traced pixels' depth / normal (half resolution only)
    gl::Texture resolved, blurTemp, blurred;   // premultiplied (L·c, c)
    TemporalFilter temporal;                   // shared temporal filter with its own history
    gl::Texture directDiffuse;                 // diffuse-only direct light (ssr.diffuse_history)
    gl::Buffer ubo;
    const gl::Texture* reflection = nullptr;  // what ssr.shade reads this frame (trace resolution)
    bool resolvedHadHistory = false;   // this frame's resolve fetched a valid history
    bool temporalHasReflections = false;  // the temporal history comes from a frame that resolved a history

    SsrSettings::Tracer tracer(const FrameContext& ctx) const { return effectiveSsrTracer(ctx.scene, ctx.settings); }
    glm::ivec2 traceSize(const FrameContext& ctx) const {
        return ssrTraceSize(ctx.view.size, ctx.settings.ssr.halfResolution);
    }
    // Depth and normal of the traced pixels, at trace resolution (the filters' guides).
    const gl::Texture& depth(const FrameContext& ctx) const {
        return ctx.settings.ssr.halfResolution ? traceDepth : ctx.res.gbuffer.linearDepth;
    }
    const gl::Texture& normal(const FrameContext& ctx) const {
        return ctx.settings.ssr.halfResolution ? traceNormal : ctx.res.gbuffer.normal;
    }
    // Uploads the constant block for this frame and binds it.
    void bindUniforms(FrameContext& ctx) {
        if (!ubo) ubo = gl::Buffer(ctx.ledger, "ssr.uniforms", sizeof(gpu::SsrUniforms));
        gpu::SsrUniforms u = makeSsrUniforms(ctx.settings.ssr, tracer(ctx), ctx.view.size);
        ubo.upload(&u, sizeof(u));
        glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_SSR, ubo.id());
    }
};

}  // namespace

Need ssrFamily(const Scene& scene, const Settings& s) {
    if (s.ssr.tracer == SsrSettings::Tracer::Off) return Need::no("ssr=off");
    if (effectiveSsrTracer(scene, s) == SsrSettings::Tracer::Off) {
        char why[160];
        std::snprintf(why, sizeof why, "no material is glossy enough (roughness <= ssr.roughness_cutoff = %g)",
                      double(s.ssr.roughnessCutoff));
        return Need::no(why);
    }
    return Need::yes();
}

namespace {

// Base of every ssr.* pass: its name and the shared state.
class SsrPass : public Pass {
public:
    SsrPass(std::shared_ptr<SsrState> st, std::string name) : st_(std::move(st)), name_(std::move(name)) {}
    std::string name() const override { return name_; }

protected:
    std::shared_ptr<SsrState> st_;

private:
    std::string name_;
};

// ---- ssr.hiz ---------------------------------------------------------------
class HizPass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    void declare(PassDecl& d, const Scene& scene, const Settings& s) const override {
        if (effectiveSsrTracer(scene, s) != SsrSettings::Tracer::Hiz)
            return d.skip("only the hiz tracer reads the depth pyramid");
        d.read(R::linearDepth).output("ssr.hiz", &st_->hiz).debugImage("ssr.hiz.level0", &st_->hiz, 0.05f);
    }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 s = ctx.view.size;
        const gl::NamedTextureDesc hiz = hizTex(s);
        const int levels = hiz.desc.levels;
        st_->hiz.ensure(ctx.ledger, hiz.label, hiz.desc);
        const gl::Program& copy = ctx.programs.compute("ssr/hiz.comp", {{"RTGI_HIZ_COPY", ""}});
        const gl::Program& reduce = ctx.programs.compute("ssr/hiz.comp");
        // Producer: gbuffer (framebuffer writes of linearDepth).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(RTGI_SSR_HIZ_TEX_LINEAR_DEPTH, ctx.res.gbuffer.linearDepth.id());
        glBindImageTexture(RTGI_SSR_IMG_TARGET, st_->hiz.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        gl::dispatch(copy, s.x, s.y);
        for (int l = 1; l < levels; ++l) {
            glm::ivec2 ls = hizLevelSize(s, l);
            // Producer: the previous dispatch of this loop (level l-1 image stores).
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            glBindImageTexture(RTGI_SSR_IMG_SOURCE, st_->hiz.id(), l - 1, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
            glBindImageTexture(RTGI_SSR_IMG_TARGET, st_->hiz.id(), l, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
            gl::dispatch(reduce, ls.x, ls.y);
        }
    }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings&, glm::ivec2 view) const override { return {hizTex(view)}; }
};

// ---- ssr.trace -------------------------------------------------------------
class TracePass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        d.read(R::linearDepth).read(R::normal).read(R::material);
        d.output("ssr.hit", &st_->hit, Check::signedValues).output("ssr.confidence", &st_->confidence);
        d.output("ssr.hit_distance", &st_->hitDistance);
        if (s.ssr.halfResolution)
            d.output("ssr.trace.depth", &st_->traceDepth).output("ssr.trace.normal", &st_->traceNormal, Check::signedValues);
        d.debugImage("ssr.trace.hit_mask", &st_->confidence).debugImage("ssr.trace.hit_offset", &st_->hit);
        d.debugImage("ssr.trace.hit_distance", &st_->hitDistance, 0.1f);
    }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 t = st_->traceSize(ctx);
        st_->hit.ensure(ctx.ledger, hitTex(t).label, hitTex(t).desc);
        st_->confidence.ensure(ctx.ledger, confidenceTex(t).label, confidenceTex(t).desc);
        st_->hitDistance.ensure(ctx.ledger, hitDistanceTex(t).label, hitDistanceTex(t).desc);
        const bool half = ctx.settings.ssr.halfResolution;
        if (half) {
            st_->traceDepth.ensure(ctx.ledger, traceDepthTex(t).label, traceDepthTex(t).desc);
            st_->traceNormal.ensure(ctx.ledger, traceNormalTex(t).label, traceNormalTex(t).desc);
        }
        SsrSettings::Tracer tracer = st_->tracer(ctx);
        gl::Defines defs{{"RTGI_SSR_TRACER", std::to_string(ssrTracerId(tracer))}};
        if (half) defs.push_back({"RTGI_SSR_HALF", ""});
        const gl::Program& prog = ctx.programs.compute("ssr/trace.comp", defs);
        const gl::Texture& noise = ensureBlueNoise(ctx.res, ctx.ledger);
        st_->bindUniforms(ctx);
        const GBuffer& g = ctx.res.gbuffer;
        // Producers: gbuffer (framebuffer writes), ssr.hiz (image stores).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(RTGI_SSR_TRACE_TEX_LINEAR_DEPTH, g.linearDepth.id());
        glBindTextureUnit(RTGI_SSR_TRACE_TEX_NORMAL, g.normal.id());
        glBindTextureUnit(RTGI_SSR_TRACE_TEX_MATERIAL, g.material.id());
        glBindTextureUnit(RTGI_SSR_TEX_HIZ, tracer == SsrSettings::Tracer::Hiz ? st_->hiz.id() : g.linearDepth.id());
        glBindTextureUnit(RTGI_SSR_TEX_NOISE, noise.id());
        glBindImageTexture(RTGI_SSR_IMG_HIT, st_->hit.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG16F);
        glBindImageTexture(RTGI_SSR_IMG_CONFIDENCE, st_->confidence.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
        glBindImageTexture(RTGI_SSR_IMG_HIT_DISTANCE, st_->hitDistance.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
        if (half) {
            glBindImageTexture(RTGI_SSR_IMG_TRACE_DEPTH, st_->traceDepth.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
            glBindImageTexture(RTGI_SSR_IMG_TRACE_NORMAL, st_->traceNormal.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                               GL_RGBA16F);
        }
        gl::dispatch(prog, t.x, t.y);
    }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2 view) const override {
        const glm::ivec2 t = traceSizeFor(s, view);
        std::vector<gl::NamedTextureDesc> own{hitTex(t), confidenceTex(t), hitDistanceTex(t)};
        if (s.ssr.halfResolution) own.insert(own.end(), {traceDepthTex(t), traceNormalTex(t)});
        return own;
    }
};

// ---- ssr.resolve -----------------------------------------------------------
class ResolvePass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    // The previous frame's radiance (post.history), or with ssr.diffuse_history
    // its diffuse-only radiance (written by ssr.diffuse_history at the end of the chain).
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        d.read(R::velocity).read(R::linearDepth).readPrevious(s.ssr.diffuseHistory ? R::diffuseHistory : R::history);
        d.output("ssr.resolved", &st_->resolved).debugImage("ssr.resolve.reflection", &st_->resolved);
    }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 t = st_->traceSize(ctx);
        const bool diffuse = ctx.settings.ssr.diffuseHistory;
        st_->resolved.ensure(ctx.ledger, resolvedTex(t).label, resolvedTex(t).desc);
        const gl::Texture& history = diffuse ? ctx.res.diffuseHistory : ctx.res.history;
        bool have = ctx.hasPrevious(diffuse ? R::diffuseHistory : R::history);
        st_->resolvedHadHistory = have;
        const gl::Program& prog = ctx.programs.compute("ssr/resolve.comp");
        st_->bindUniforms(ctx);
        // Producers: ssr.trace (image stores); post.history / ssr.diffuse_history of the previous frame.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(RTGI_SSR_TEX_HIT, st_->hit.id());
        glBindTextureUnit(RTGI_SSR_TEX_CONFIDENCE, st_->confidence.id());
        glBindTextureUnit(RTGI_SSR_TEX_VELOCITY, ctx.res.gbuffer.velocity.id());
        glBindTextureUnit(RTGI_SSR_RESOLVE_TEX_LINEAR_DEPTH, ctx.res.gbuffer.linearDepth.id());
        glBindTextureUnit(RTGI_SSR_TEX_HISTORY, have ? history.id() : st_->hit.id());  // unread without history
        prog.set(RTGI_SSR_LOC_HAVE_HISTORY, have ? 1 : 0);
        glBindImageTexture(RTGI_SSR_IMG_RESOLVED, st_->resolved.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        gl::dispatch(prog, t.x, t.y);
    }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2 view) const override {
        return {resolvedTex(traceSizeFor(s, view))};
    }
};

// ---- ssr.blur --------------------------------------------------------------
class BlurPass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    void declare(PassDecl& d, const Scene&, const Settings&) const override {
        d.read(R::linearDepth).read(R::normal);
        d.output("ssr.blur_temp", &st_->blurTemp).output("ssr.blurred", &st_->blurred);
    }
    void execute(FrameContext& ctx) override {
        using F = SsrFilterConstants;
        separableBlur(ctx.programs, ctx.ledger, "ssr.blur", kSsrFormat, st_->resolved, st_->depth(ctx),
                      st_->normal(ctx), st_->blurTemp, st_->blurred, {F::kDepthThreshold, F::kNormalThreshold});
    }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2 view) const override {
        return blurTextures("ssr.blur", kSsrFormat, traceSizeFor(s, view));
    }
};

// ---- ssr.temporal ----------------------------------------------------------
class TemporalPass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    // The last frame's pixels whose history was rejected (docs/temporal.md, "Disocclusion").
    std::vector<std::pair<std::string, double>> stats() override {
        return {{"disoccluded_pixels", double(st_->temporal.disoccludedPixels())}};
    }
    void declare(PassDecl& d, const Scene&, const Settings&) const override {
        d.read(R::linearDepth).read(R::velocity);
        auto out = [st = st_] { return &st->temporal.output(); };
        d.output("ssr.temporal", out).debugImage("ssr.temporal.reflection", [out] {
            return DebugImage{"ssr.temporal.reflection", out(), 1.0f};
        });
    }
    void execute(FrameContext& ctx) override {
        // A frame resolved without history is all misses: never blend it in later.
        const bool reset = ctx.view.cut || !st_->temporalHasReflections;
        const gl::Texture& out = st_->temporal.run(ctx.programs, ctx.ledger, "ssr.temporal", kSsrFormat,
                                                   st_->blurred, st_->depth(ctx), ctx.res.gbuffer.velocity, reset,
                                                   temporalCamera(ctx.view));
        st_->temporalHasReflections = st_->resolvedHadHistory;
        st_->reflection = &out;
    }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2 view) const override {
        return temporalTextures("ssr.temporal", kSsrFormat, traceSizeFor(s, view));
    }
};

// ---- ssr.shade -------------------------------------------------------------
class ShadePass final : public SsrPass {
public:
    using SsrPass::SsrPass;
    // Accumulates: adds to lpv.apply's specular when LPV specular runs, else is its first writer.
    void declare(PassDecl& d, const Scene&, const Settings&) const override {
        d.read(R::brdfLut).read(R::linearDepth).read(R::normal).read(R::albedo).read(R::material);
        d.accumulate(R::specular).write(R::specularOcclusion);
    }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 s = ctx.view.size;
        FrameResources& r = ctx.res;
        bool haveLpv = ctx.accumulates(R::specular);
        // ssr.resolution=half: the reflection is upsampled here, per shaded pixel (joint bilateral with the
        // traced pixels' depth, lib/filter.glsl), instead of by a full-resolution pass before.
        const bool half = ctx.settings.ssr.halfResolution;
        const gl::Program& prog =
            ctx.programs.compute("ssr/shade.comp", half ? gl::Defines{{"RTGI_SSR_SHADE_UPSAMPLE", ""}} : gl::Defines{});
        st_->bindUniforms(ctx);
        const gl::Texture& reflection = *st_->reflection;
        // Producers: ssr.temporal, brdf_lut, lpv.apply (image stores).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        glBindTextureUnit(RTGI_SSR_TEX_REFLECTION, reflection.id());
        glBindTextureUnit(RTGI_SSR_SHADE_TEX_LOW_DEPTH, half ? st_->traceDepth.id() : 0);
        glBindTextureUnit(RTGI_SSR_TEX_BRDF_LUT, r.brdfLut.id());
        glBindTextureUnit(RTGI_SSR_SHADE_TEX_LINEAR_DEPTH, r.gbuffer.linearDepth.id());
        glBindTextureUnit(RTGI_SSR_SHADE_TEX_NORMAL, r.gbuffer.normal.id());
        glBindTextureUnit(RTGI_SSR_TEX_ALBEDO, r.gbuffer.albedo.id());
        glBindTextureUnit(RTGI_SSR_SHADE_TEX_MATERIAL, r.gbuffer.material.id());
        prog.set(RTGI_SSR_LOC_HAVE_LPV, haveLpv ? 1 : 0);
        glBindImageTexture(RTGI_SSR_IMG_SPECULAR, r.specular.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA16F);
        glBindImageTexture(RTGI_SSR_IMG_OCCLUSION, r.specularOcclusion.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
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
    // The inputs of dispatchDirect and dispatchCompose.
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!s.ssr.diffuseHistory) return d.skip("ssr.diffuse_history=off (full HDR history)");
        d.read(R::linearDepth).read(R::normal).read(R::albedo).read(R::material).read(R::emissive);
        d.readIfWritten(R::shadowMap).readIfWritten(R::localShadowMaps).readIfWritten(R::indirectDiffuse).readIfWritten(R::ao);
        d.readIfWritten(R::bentNormal).readIfWritten(R::s3ho);
        d.write(R::diffuseHistory).output("ssr.direct_diffuse", &st_->directDiffuse);
    }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 s = ctx.view.size;
        FrameResources& r = ctx.res;
        st_->directDiffuse.ensure(ctx.ledger, directDiffuseTex(s).label, directDiffuseTex(s).desc);
        dispatchDirect(ctx, st_->directDiffuse, true);
        // Producer: the diffuse-only direct dispatch above (barrier inside dispatchCompose).
        dispatchCompose(ctx, st_->directDiffuse, r.diffuseHistory, nullptr, true);
    }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings&, glm::ivec2 view) const override {
        return {directDiffuseTex(view)};
    }
};

}  // namespace

void appendSsrPasses(std::vector<std::unique_ptr<Pass>>& f) {
    auto st = std::make_shared<SsrState>();
    // min-depth pyramid (hiz only) -> ray march -> reproject the hit into last frame's radiance
    // -> shared blur / temporal -> split-sum shading with the depth-aware upsampling (+ diffuse-only history)
    f.push_back(std::make_unique<HizPass>(st, "ssr.hiz"));
    f.push_back(std::make_unique<TracePass>(st, "ssr.trace"));
    f.push_back(std::make_unique<ResolvePass>(st, "ssr.resolve"));
    f.push_back(std::make_unique<BlurPass>(st, "ssr.blur"));
    f.push_back(std::make_unique<TemporalPass>(st, "ssr.temporal"));
    f.push_back(std::make_unique<ShadePass>(st, "ssr.shade"));
    f.push_back(std::make_unique<DiffuseHistoryPass>(st, "ssr.diffuse_history"));
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
