// Screen-space AO family (SPEC 4, 6): ao.downsample -> ao.radius ->
// ao.<variant> -> ao.blur -> ao.temporal -> ao.upsample, and ao.nearfield.
// The passes share one AoChain (private textures + the AoParams block); the
// last stage of the chain writes res.ao (R16F, full resolution).
#include "render/ao/ao_passes.h"

#include "gl/bindings.h"
#include "gl/program.h"
#include "render/ao/ao_params.h"
#include "render/filter.h"
#include "render/gpu_scene.h"
#include "render/lpv/lpv_passes.h"
#include "render/lpv/lpv_probe.h"  // SceneBvh: the scene BVH on the GPU (ao.rtao)
#include "render/noise.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <cstring>

namespace rtgi {
namespace {

using Variant = AoSettings::Variant;

bool dynamicRadius(const AoSettings& a) { return int(a.radiusMode) >= int(AoSettings::RadiusMode::Dynamic1); }
const FilterFormat kAoFormat{GL_R16F, "r16f"};

enum class Stage { Estimate, Blur, Temporal, Blur2, Upsample };
// ao.filter_chain=blur-temporal-blur: a second blur after the temporal filter ([Wes14]).
bool secondBlur(const AoSettings& a) { return a.blurAfterTemporal && a.blur && a.temporal; }
// The stage that writes res.ao: the last one of the configured chain.
Stage lastStage(const AoSettings& a) {
    if (a.halfResolution) return Stage::Upsample;
    if (secondBlur(a)) return Stage::Blur2;
    if (a.temporal) return Stage::Temporal;
    if (a.blur) return Stage::Blur;
    return Stage::Estimate;
}

// The AO resolution (half: rounded up, at least 1).
glm::ivec2 aoSizeFor(const AoSettings& s, glm::ivec2 view) { return s.halfResolution ? glm::max((view + 1) / 2, glm::ivec2(1)) : view; }
// The chain's own textures at AO resolution `a` (the near field at the view's):
// execute() allocates from these, privateTextures() lists them for the memory estimate.
gl::NamedTextureDesc halfDepthTex(glm::ivec2 a) { return {"ao.half.depth", {GL_TEXTURE_2D, GL_R32F, a.x, a.y}}; }
gl::NamedTextureDesc halfNormalTex(glm::ivec2 a) { return {"ao.half.normal", {GL_TEXTURE_2D, GL_RGBA16F, a.x, a.y}}; }
gl::NamedTextureDesc radiusScaleTex(glm::ivec2 a) { return {"ao.radius.scale", {GL_TEXTURE_2D, GL_R16F, a.x, a.y}}; }
gl::NamedTextureDesc radiusColorTex(glm::ivec2 a) { return {"ao.radius.color", {GL_TEXTURE_2D, GL_RGBA8, a.x, a.y}}; }
gl::NamedTextureDesc rawTex(glm::ivec2 a) { return {"ao.raw", {GL_TEXTURE_2D, kAoFormat.internal, a.x, a.y}}; }
gl::NamedTextureDesc nearFieldTex(glm::ivec2 v) { return {"ao.nearfield", {GL_TEXTURE_2D, GL_R11F_G11F_B10F, v.x, v.y}}; }
// The label of a blur's output: res.ao ("ao") when it is the chain's last stage.
std::string blurLabel(const AoSettings& s, bool second) {
    return lastStage(s) == (second ? Stage::Blur2 : Stage::Blur) ? "ao" : second ? "ao.blur2" : "ao.blur";
}

struct AoChain {
    gl::Texture halfDepth, halfNormal;       // ao.downsample
    gl::Texture radiusScale, radiusColor;    // ao.radius
    gl::Texture raw;                         // ao.<variant> (unless it is the last stage)
    gl::Texture blurTmp, blurred;            // ao.blur
    gl::Texture blurred2;                    // ao.blur2 (blur-temporal-blur)
    TemporalFilter temporal;                 // ao.temporal
    gl::Texture nearField;                   // ao.nearfield
    gl::Buffer params;
    // ao.depth_source=light reads the shadow map's depth values, but the map
    // keeps compare mode on for the shadow lookups (passes/shadow.cpp), and a
    // plain sampler2D on a compare-mode depth texture is undefined in GL
    // (llvmpipe returns 0: no occlusion at all). A sampler object bound to the
    // unit overrides the texture's own state: compare mode off, nearest (a
    // blend of depths across an edge is no surface).
    gl::SamplerHandle rawDepthSampler;
    const gl::Texture* current = nullptr;    // output of the last stage run this frame
    // Cache key of the AoParams block (sample sets are generated on the CPU).
    AoSettings lastSettings;
    glm::ivec4 lastSizes{-1};
    float lastFov = -1;

    glm::ivec2 aoSize(const FrameContext& ctx) const { return aoSizeFor(ctx.settings.ao, ctx.view.size); }
    const gl::Texture& depth(const FrameContext& ctx) const {
        return ctx.settings.ao.halfResolution ? halfDepth : ctx.res.gbuffer.linearDepth;
    }
    const gl::Texture& normal(const FrameContext& ctx) const {
        return ctx.settings.ao.halfResolution ? halfNormal : ctx.res.gbuffer.normal;
    }
    // Binds AoParams at RTGI_UBO_AO, regenerating it when settings or sizes change.
    void bindParams(FrameContext& ctx) {
        glm::ivec2 a = aoSize(ctx), f = ctx.view.size;
        glm::ivec4 sizes(a, f);
        const AoSettings& s = ctx.settings.ao;
        bool same = params && sizes == lastSizes && lastFov == ctx.view.fovY &&
                    std::memcmp(&s, &lastSettings, sizeof s) == 0;
        if (!same) {
            gpu::AoParams p = makeAoParams(s, a, f, ctx.view.fovY);
            params.ensure(ctx.ledger, "ao.params", sizeof p);
            params.upload(&p, sizeof p);
            lastSettings = s;
            lastSizes = sizes;
            lastFov = ctx.view.fovY;
        }
        glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_AO, params.id());
    }
    GLuint rawDepth() {
        if (!rawDepthSampler) {
            GLuint id = 0;
            glCreateSamplers(1, &id);
            rawDepthSampler = gl::SamplerHandle(id);
            rawDepthSampler.label("ao.shadow_depth.sampler");
            glSamplerParameteri(id, GL_TEXTURE_COMPARE_MODE, GL_NONE);
            glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            glSamplerParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            glSamplerParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        }
        return rawDepthSampler.id();
    }
    // Output texture of a stage: res.ao when it is the last stage.
    gl::Texture& target(FrameContext& ctx, Stage st, gl::Texture& own) {
        return lastStage(ctx.settings.ao) == st ? ctx.res.ao : own;
    }
};

class AoPassBase : public Pass {
public:
    explicit AoPassBase(std::shared_ptr<AoChain> c) : chain_(std::move(c)) {}

protected:
    // The estimator's output: the chain's ao.raw (allocated here) or the next stage's target.
    gl::Texture& estimateTarget(FrameContext& ctx) const {
        AoChain& c = *chain_;
        glm::ivec2 a = c.aoSize(ctx);
        gl::Texture& out = c.target(ctx, Stage::Estimate, c.raw);
        if (&out == &c.raw) out.ensure(ctx.ledger, rawTex(a).label, rawTex(a).desc);
        return out;
    }
    // The directional term the estimator writes (ao.directional), or none.
    static gl::Texture* directionalTarget(FrameContext& ctx) {
        switch (ctx.settings.ao.directional) {
            case AoSettings::Directional::BentNormals: return &ctx.res.bentNormal;
            case AoSettings::Directional::S3ho: return &ctx.res.s3ho;
            default: return nullptr;
        }
    }
    std::shared_ptr<AoChain> chain_;
};

// What an estimator (screen-space or ao.rtao) writes: the directional term it
// is asked for, and ao itself when no filter follows, else the chain's ao.raw.
void declareEstimateOutputs(PassDecl& d, const Settings& s, AoChain& chain) {
    if (s.ao.directional == AoSettings::Directional::BentNormals) d.write(R::bentNormal);
    if (s.ao.directional == AoSettings::Directional::S3ho) d.write(R::s3ho);
    if (lastStage(s.ao) == Stage::Estimate) {
        d.write(R::ao);
    } else {
        d.output("ao.raw", &chain.raw).debugImage("ao.raw", &chain.raw);
    }
}

// ---- ao.downsample ------------------------------------------------------------
class DownsamplePass final : public AoPassBase {
public:
    using AoPassBase::AoPassBase;
    std::string name() const override { return "ao.downsample"; }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!s.ao.halfResolution) return d.skip("ao.resolution=full");
        d.read(R::linearDepth).read(R::normal);
        d.output("ao.half.depth", &chain_->halfDepth).output("ao.half.normal", &chain_->halfNormal, Check::signedValues);
    }
    void execute(FrameContext& ctx) override {
        AoChain& c = *chain_;
        glm::ivec2 a = c.aoSize(ctx);
        c.halfDepth.ensure(ctx.ledger, halfDepthTex(a).label, halfDepthTex(a).desc);
        c.halfNormal.ensure(ctx.ledger, halfNormalTex(a).label, halfNormalTex(a).desc);
        const gl::Program& prog = ctx.programs.compute("ao/downsample.comp");
        // Producer: gbuffer (framebuffer writes).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(RTGI_AO_TEX_DEPTH, ctx.res.gbuffer.linearDepth.id());
        glBindTextureUnit(RTGI_AO_TEX_NORMAL, ctx.res.gbuffer.normal.id());
        glBindImageTexture(RTGI_AO_IMG_HALF_DEPTH, c.halfDepth.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        glBindImageTexture(RTGI_AO_IMG_HALF_NORMAL, c.halfNormal.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        gl::dispatch(prog, a.x, a.y);
    }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2 view) const override {
        const glm::ivec2 a = aoSizeFor(s.ao, view);
        return {halfDepthTex(a), halfNormalTex(a)};
    }
};

// ---- ao.radius (dynamic radius probe) ------------------------------------------
class RadiusPass final : public AoPassBase {
public:
    using AoPassBase::AoPassBase;
    std::string name() const override { return "ao.radius"; }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!dynamicRadius(s.ao)) return d.skip("ao.radius_mode is not dynamic1..dynamic6");
        d.read(R::linearDepth).read(R::normal);
        d.output("ao.radius.scale", &chain_->radiusScale).debugImage("ao.radius.scale", &chain_->radiusColor);
    }
    void execute(FrameContext& ctx) override {
        AoChain& c = *chain_;
        glm::ivec2 a = c.aoSize(ctx);
        c.radiusScale.ensure(ctx.ledger, radiusScaleTex(a).label, radiusScaleTex(a).desc);
        c.radiusColor.ensure(ctx.ledger, radiusColorTex(a).label, radiusColorTex(a).desc);
        int alg = int(ctx.settings.ao.radiusMode) - int(AoSettings::RadiusMode::Dynamic1) + 1;
        const gl::Program& prog = ctx.programs.compute("ao/radius.comp", {{"AO_RADIUS_ALG", std::to_string(alg)}});
        c.bindParams(ctx);
        // Producer: ao.downsample or gbuffer.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(RTGI_AO_TEX_DEPTH, c.depth(ctx).id());
        glBindTextureUnit(RTGI_AO_TEX_NORMAL, c.normal(ctx).id());
        glBindImageTexture(RTGI_AO_IMG_SCALE, c.radiusScale.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
        glBindImageTexture(RTGI_AO_IMG_SCALE_COLOR, c.radiusColor.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
        gl::dispatch(prog, a.x, a.y);
    }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2 view) const override {
        const glm::ivec2 a = aoSizeFor(s.ao, view);
        return {radiusScaleTex(a), radiusColorTex(a)};
    }
};

// ---- ao.<variant> -------------------------------------------------------------
class EstimatePass final : public AoPassBase {
public:
    EstimatePass(std::shared_ptr<AoChain> c, Variant v) : AoPassBase(std::move(c)), variant_(v) {}
    std::string name() const override { return std::string("ao.") + toString(variant_); }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (s.ao.variant != variant_) return d.skip(std::string("ao=") + toString(s.ao.variant));
        d.read(R::linearDepth).read(R::normal).read(R::albedo);
        if (s.ao.depthSource == AoSettings::DepthSource::Light) d.read(R::shadowMap);
        // visibility.layer2 writes it on the compute raster path only.
        if (variant_ == Variant::Vbao && s.ao.secondLayer) d.readIfWritten(R::linearDepth2);
        declareEstimateOutputs(d, s, *chain_);
    }
    void execute(FrameContext& ctx) override {
        AoChain& c = *chain_;
        const AoSettings& s = ctx.settings.ao;
        glm::ivec2 a = c.aoSize(ctx);
        gl::Texture& out = estimateTarget(ctx);
        int directional = int(s.directional);
        gl::Texture* dirTex = directionalTarget(ctx);
        bool light = s.depthSource == AoSettings::DepthSource::Light;
        bool layer2 = variant_ == Variant::Vbao && s.secondLayer && ctx.has(R::linearDepth2);
        // ao.bent_normals=slices: GTAO's bent normal from its own slices (fixed radius: one estimate).
        bool sliceBent = variant_ == Variant::Gtao && s.sliceBentNormals &&
                         s.directional == AoSettings::Directional::BentNormals && s.radiusMode != AoSettings::RadiusMode::Dual;
        int radius = s.radiusMode == AoSettings::RadiusMode::Fixed ? 0
                     : s.radiusMode == AoSettings::RadiusMode::Dual ? 1
                                                                     : 2;
        const gl::Program& prog = ctx.programs.compute(
            "ao/ao.comp", {{"AO_VARIANT", std::to_string(int(variant_))},
                           {"AO_DIRECTIONAL", std::to_string(directional)},
                           {"AO_RADIUS", std::to_string(radius)},
                           {"AO_DEPTH_LIGHT", light ? "1" : "0"},
                           {"AO_SECOND_LAYER", layer2 ? "1" : "0"},
                           {"AO_SLICE_BENT", sliceBent ? "1" : "0"}});
        c.bindParams(ctx);
        const gl::Texture& noise = ensureBlueNoise(ctx.res, ctx.ledger);
        if (light) {
            glm::mat4 toShadow = ctx.res.shadowViewProj * glm::inverse(ctx.view.view);
            prog.set(RTGI_AO_LOC_VIEW_TO_SHADOW, toShadow);
            prog.set(RTGI_AO_LOC_SHADOW_TO_VIEW, glm::inverse(toShadow));
        }
        // Producers: ao.downsample / ao.radius (image stores), gbuffer, shadow, visibility.layer2 (image atomics).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        {
            gl::ScopedBindings b;
            b.texture(RTGI_AO_TEX_DEPTH, c.depth(ctx))
                .texture(RTGI_AO_TEX_NORMAL, c.normal(ctx))
                .texture(RTGI_AO_ESTIMATE_TEX_NOISE, noise)
                .texture(RTGI_AO_TEX_RADIUS_SCALE, radius == 2 ? &c.radiusScale : nullptr)
                .texture(RTGI_AO_TEX_SHADOW_MAP, light ? &ctx.res.shadowMap : nullptr)
                .texture(RTGI_AO_ESTIMATE_TEX_ALBEDO, ctx.res.gbuffer.albedo)
                .texture(RTGI_AO_ESTIMATE_TEX_DEPTH2, layer2 ? &ctx.res.gbuffer.linearDepth2 : nullptr)
                .image(RTGI_AO_IMG_AO, out, GL_WRITE_ONLY, GL_R16F);
            if (dirTex) b.image(RTGI_AO_IMG_DIRECTIONAL, *dirTex, GL_WRITE_ONLY, GL_RGBA16F);
            if (light) glBindSampler(RTGI_AO_TEX_SHADOW_MAP, c.rawDepth());
            gl::dispatch(prog, a.x, a.y);
            if (light) glBindSampler(RTGI_AO_TEX_SHADOW_MAP, 0);  // the unit's next user samples with its texture's state
        }
        c.current = &out;
    }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2 view) const override {
        if (lastStage(s.ao) == Stage::Estimate) return {};  // writes res.ao
        return {rawTex(aoSizeFor(s.ao, view))};
    }

private:
    Variant variant_;
};

// ---- ao.rtao ------------------------------------------------------------------
// Ray-traced AO through the scene BVH (compute/ao/rtao.comp): the same slot in
// the chain as ao.<variant>, so the blur / temporal / upsample stages filter it.
// ao.ray_rate 2 / 4: one pixel of each block traces, the others are filled (docs/ao.md "Sparse rays").
class RtaoPass final : public AoPassBase {
public:
    using AoPassBase::AoPassBase;
    std::string name() const override { return "ao.rtao"; }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (s.ao.variant != Variant::Rtao) return d.skip(std::string("ao=") + toString(s.ao.variant));
        d.read(R::linearDepth).read(R::normal);
        declareEstimateOutputs(d, s, *chain_);
    }
    void execute(FrameContext& ctx) override {
        AoChain& c = *chain_;
        const AoSettings& s = ctx.settings.ao;
        glm::ivec2 a = c.aoSize(ctx);
        gl::Texture& out = estimateTarget(ctx);
        int directional = int(s.directional);
        gl::Texture* dirTex = directionalTarget(ctx);
        bvh_.ensure(ctx, "ao.rtao.bvh");  // built once, rebuilt when the geometry moved
        const gl::Program& prog = ctx.programs.compute(
            "ao/rtao.comp",
            {{"AO_DIRECTIONAL", std::to_string(directional)}, {"RTAO_RAY_RATE", std::to_string(s.rayRate)}});
        if (s.rayRate > 1) {
            // The untraced pixels borrow only across what the blur does not blur across.
            const BlurThresholds edge;
            prog.set(RTGI_AO_RTAO_LOC_FILL_DEPTH, edge.depth);
            prog.set(RTGI_AO_RTAO_LOC_FILL_NORMAL, edge.normal);
        }
        c.bindParams(ctx);
        bvh_.bind(ctx);
        // Producers: ao.downsample (image stores), gbuffer.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        gl::ScopedBindings b;
        b.texture(RTGI_AO_TEX_DEPTH, c.depth(ctx))
            .texture(RTGI_AO_TEX_NORMAL, c.normal(ctx))
            .texture(RTGI_AO_RTAO_TEX_FULL_DEPTH, ctx.res.gbuffer.linearDepth)
            .texture(RTGI_AO_RTAO_TEX_FULL_NORMAL, ctx.res.gbuffer.normal)
            .image(RTGI_AO_IMG_AO, out, GL_WRITE_ONLY, GL_R16F);
        if (dirTex) b.image(RTGI_AO_IMG_DIRECTIONAL, *dirTex, GL_WRITE_ONLY, GL_RGBA16F);
        // One invocation per block of ao.ray_rate pixels.
        const glm::ivec2 block(RTGI_AO_RTAO_BLOCK_X(s.rayRate), RTGI_AO_RTAO_BLOCK_Y(s.rayRate));
        gl::dispatch(prog, int(gl::groupCount(a.x, block.x)), int(gl::groupCount(a.y, block.y)));
        c.current = &out;
    }

private:
    lpv::SceneBvh bvh_;
};

// ---- ao.blur / ao.blur2 -------------------------------------------------------
// ao.blur runs before the temporal filter; ao.blur2 (second = true) after it,
// for ao.filter_chain=blur-temporal-blur. The temporal history stays the
// once-blurred value, so the second blur does not accumulate over frames.
class BlurPass final : public AoPassBase {
public:
    BlurPass(std::shared_ptr<AoChain> c, bool second) : AoPassBase(std::move(c)), second_(second) {}
    std::string name() const override { return second_ ? "ao.blur2" : "ao.blur"; }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!s.ao.blur) return d.skip("ao.blur=off");
        if (second_ && !secondBlur(s.ao))
            return d.skip(s.ao.temporal ? "ao.filter_chain=blur-temporal" : "ao.temporal=off");
        d.read(R::linearDepth).read(R::normal);
        d.output(name() + ".tmp", &chain_->blurTmp);
        const gl::Texture& own = second_ ? chain_->blurred2 : chain_->blurred;
        if (lastStage(s.ao) == (second_ ? Stage::Blur2 : Stage::Blur)) {
            d.write(R::ao);
        } else {
            d.output(second_ ? "ao.blurred2" : "ao.blurred", &own);
            d.debugImage(second_ ? "ao.blurred2" : "ao.blurred", &own);
        }
    }
    void execute(FrameContext& ctx) override {
        AoChain& c = *chain_;
        gl::Texture& own = second_ ? c.blurred2 : c.blurred;
        gl::Texture& out = c.target(ctx, second_ ? Stage::Blur2 : Stage::Blur, own);
        separableBlur(ctx.programs, ctx.ledger, blurLabel(ctx.settings.ao, second_), kAoFormat, *c.current,
                      c.depth(ctx), c.normal(ctx), c.blurTmp, out);
        c.current = &out;
    }
    // The temporary (shared by both blurs, listed by the first) and the output unless it is res.ao.
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2 view) const override {
        const auto t = blurTextures(blurLabel(s.ao, second_), kAoFormat, aoSizeFor(s.ao, view));
        std::vector<gl::NamedTextureDesc> own;
        if (!second_) own.push_back(t[0]);
        if (t[1].label != "ao") own.push_back(t[1]);
        return own;
    }

private:
    bool second_;
};

// ---- ao.temporal --------------------------------------------------------------
class TemporalPass final : public AoPassBase {
public:
    using AoPassBase::AoPassBase;
    std::string name() const override { return "ao.temporal"; }
    // The last frame's pixels whose history was rejected (docs/temporal.md, "Disocclusion").
    std::vector<std::pair<std::string, double>> stats() override {
        return {{"disoccluded_pixels", double(chain_->temporal.disoccludedPixels())}};
    }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!s.ao.temporal) return d.skip("ao.temporal=off");
        d.read(R::linearDepth).read(R::velocity);
        auto filtered = [c = chain_] { return &c->temporal.output(); };
        d.output("ao.temporal", filtered).debugImage("ao.temporal", [filtered] {
            return DebugImage{"ao.temporal", filtered(), 1.0f};
        });
        if (lastStage(s.ao) == Stage::Temporal) d.write(R::ao);
    }
    void execute(FrameContext& ctx) override {
        AoChain& c = *chain_;
        const gl::Texture& filtered = c.temporal.run(ctx.programs, ctx.ledger, "ao.temporal", kAoFormat, *c.current,
                                                     c.depth(ctx), ctx.res.gbuffer.velocity, ctx.view.cut,
                                                     temporalCamera(ctx.view));
        c.current = &filtered;
        if (lastStage(ctx.settings.ao) == Stage::Temporal) {
            // The history must survive the next frame's passes, so res.ao gets a copy.
            // Producer: the temporal dispatch above (image stores).
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
            copyTexture(ctx.programs, kAoFormat, filtered, ctx.res.ao);
            c.current = &ctx.res.ao;
        }
    }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2 view) const override {
        return temporalTextures("ao.temporal", kAoFormat, aoSizeFor(s.ao, view));
    }
};

// ---- ao.upsample --------------------------------------------------------------
class UpsamplePass final : public AoPassBase {
public:
    using AoPassBase::AoPassBase;
    std::string name() const override { return "ao.upsample"; }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!s.ao.halfResolution) return d.skip("ao.resolution=full");
        d.read(R::linearDepth).write(R::ao);
    }
    void execute(FrameContext& ctx) override {
        AoChain& c = *chain_;
        upsample(ctx.programs, ctx.ledger, "ao", kAoFormat, *c.current, c.halfDepth, ctx.res.gbuffer.linearDepth,
                 ctx.res.ao, ctx.settings.ao.upsample);
        c.current = &ctx.res.ao;
    }
};

// ---- ao.nearfield -------------------------------------------------------------
class NearFieldPass final : public AoPassBase {
public:
    using AoPassBase::AoPassBase;
    std::string name() const override { return "ao.nearfield"; }
    // Accumulates: adds to lpv.apply's indirect light when LPV runs, else is its first writer.
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!(s.ao.nearfield > 0.0f)) return d.skip("ao.nearfield=0");
        d.read(R::linearDepth).read(R::normal).read(R::albedo).read(R::material).read(R::velocity);
        d.readPrevious(R::history).accumulate(R::indirectDiffuse);
        d.output("ao.nearfield", &chain_->nearField).debugImage("ao.nearfield", &chain_->nearField);
    }
    void execute(FrameContext& ctx) override {
        AoChain& c = *chain_;
        FrameResources& r = ctx.res;
        const glm::ivec2 s = ctx.view.size;
        c.nearField.ensure(ctx.ledger, nearFieldTex(s).label, nearFieldTex(s).desc);
        // The frame decides: add when an earlier pass (lpv.apply) wrote the indirect term.
        bool accumulate = ctx.accumulates(R::indirectDiffuse);
        // With ao=vbao the near field is gathered through its bitmask (docs/ao.md, "Bitmask near-field light").
        gl::Defines defs;
        if (ctx.settings.ao.variant == Variant::Vbao) defs.push_back({"RTGI_AO_NEARFIELD_BITMASK", ""});
        const gl::Program& prog = ctx.programs.compute("ao/nearfield.comp", defs);
        c.bindParams(ctx);
        const gl::Texture& noise = ensureBlueNoise(r, ctx.ledger);
        bool history = ctx.hasPrevious(R::history);
        prog.set(RTGI_AO_LOC_ACCUMULATE, accumulate ? 1 : 0);
        prog.set(RTGI_AO_LOC_HISTORY_VALID, history ? 1 : 0);
        // Producers: gbuffer, post.history (last frame), lpv.apply (image stores).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        gl::ScopedBindings b;
        b.texture(RTGI_AO_TEX_DEPTH, r.gbuffer.linearDepth)
            .texture(RTGI_AO_TEX_NORMAL, r.gbuffer.normal)
            .texture(RTGI_AO_NEARFIELD_TEX_ALBEDO, r.gbuffer.albedo)
            .texture(RTGI_AO_TEX_MATERIAL, r.gbuffer.material)
            .texture(RTGI_AO_TEX_HISTORY, history ? &r.history : nullptr)
            .texture(RTGI_AO_TEX_VELOCITY, r.gbuffer.velocity)
            .texture(RTGI_AO_NEARFIELD_TEX_NOISE, noise)
            .image(RTGI_AO_IMG_NEAR_FIELD, c.nearField, GL_WRITE_ONLY, GL_R11F_G11F_B10F)
            .image(RTGI_AO_IMG_INDIRECT, r.indirectDiffuse, GL_READ_WRITE, GL_RGBA16F);
        gl::dispatch(prog, s.x, s.y);
    }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings&, glm::ivec2 view) const override {
        return {nearFieldTex(view)};
    }
};

}  // namespace

void appendAoPasses(std::vector<std::unique_ptr<Pass>>& f) {
    auto chain = std::make_shared<AoChain>();
    f.push_back(std::make_unique<DownsamplePass>(chain));  // half-resolution depth + normals
    f.push_back(std::make_unique<RadiusPass>(chain));      // dynamic radius scale (radius_mode=dynamic*)
    for (Variant v : {Variant::SsaoDisk, Variant::SsaoSphere, Variant::SsaoHemisphere, Variant::Vo, Variant::Hbao,
                      Variant::Gtao, Variant::Vbao})
        f.push_back(std::make_unique<EstimatePass>(chain, v));  // ao.<variant> (+ bent normals / S3HO)
    f.push_back(std::make_unique<RtaoPass>(chain));             // ao.rtao: rays through the scene BVH
    f.push_back(std::make_unique<BlurPass>(chain, false));  // separable edge-preserving blur
    f.push_back(std::make_unique<TemporalPass>(chain));     // seed 000 listing 11
    f.push_back(std::make_unique<BlurPass>(chain, true));   // ao.blur2: blur-temporal-blur ([Wes14])
    f.push_back(std::make_unique<UpsamplePass>(chain));  // depth-aware half -> full
}

void appendNearFieldPasses(std::vector<std::unique_ptr<Pass>>& f) {
    // Its own chain: it needs only the AoParams block and its output image.
    f.push_back(std::make_unique<NearFieldPass>(std::make_shared<AoChain>()));
}

}  // namespace rtgi

namespace rtgi {

Need aoFamily(const Scene&, const Settings& s) {
    if (s.ao.variant == Variant::Off) return Need::no("ao=off");
    return Need::yes();
}

void validateAoSettings(const Scene& scene, const Settings& s) {
    if (s.ao.depthSource != AoSettings::DepthSource::Light) return;
    Variant v = s.ao.variant;
    if (v == Variant::Rtao)
        throw ConfigError("ao.depth_source=light needs a point-sampling variant (ssao-disk, ssao-sphere, "
                          "ssao-hemisphere); rtao traces rays through the scene");
    if (v == Variant::Vo || v == Variant::Hbao || v == Variant::Gtao || v == Variant::Vbao)
        throw ConfigError("ao.depth_source=light needs a point-sampling variant (ssao-disk, ssao-sphere, "
                          "ssao-hemisphere); " + std::string(toString(v)) + " marches the camera depth");
    if (!resolveSun(scene, s)) throw ConfigError("ao.depth_source=light needs a directional light (its shadow map)");
}

}  // namespace rtgi
