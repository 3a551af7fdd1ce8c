// The LPV passes (seed 000 sections 3, 5.2; SPEC 3): lpv.rsm -> lpv.inject
// -> lpv.pack -> lpv.inject_geometry -> lpv.propagate -> lpv.temporal ->
// lpv.apply. They share one LpvState (volumes, uniform block, RSM); the
// kernels live in lpv_volumes.cpp, the pure math in lpv_math.cpp.
#include "render/lpv/lpv_passes.h"

#include "gl/profiler.h"
#include "render/gpu_scene.h"
#include "render/lights.h"
#include "render/lpv/lpv_math.h"
#include "render/lpv/lpv_volumes.h"
#include "gl/image_io.h"
#include "render/passes/core_passes.h"
#include "render/visibility/visibility.h"
#include "compute/lib/raster_shared.h"
#include "compute/lib/visibility_shared.h"

#include <algorithm>

namespace rtgi {
namespace {

// One RSM of the frame: its targets, its view-projection and its copy of the
// uniform block (rsmViewProj / rsmInvViewProj of this RSM), so injection loops
// over the list (docs/lpv.md "RSMs of local lights").
struct LocalRsm {
    lpv::Rsm rsm;
    gl::FramebufferHandle fbo;
    gl::Buffer ubo;
};

struct LpvState {
    lpv::Volumes volumes;
    lpv::Rsm rsm;  // the sun's (orthographic), when there is a sun
    gl::FramebufferHandle rsmFbo;
    bool sunRsm = false;
    std::vector<LocalRsm> local;  // one per face of a kept spot / point / area light
    int localUsed = 0;            // how many of `local` this frame rendered
    VisibilityTarget rsmVis{"lpv.rsm"};  // raster.path=compute
    gl::Buffer ubo, stats;
    lpv::Placement placement, previous;
    bool havePrevious = false;
    int historyTarget = 0;
    const lpv::Rgb* result = nullptr;  // volume read by lpv.apply
    int lastStep = 0;                  // step[lastStep] holds the last propagation iteration
    gl::ProgramCache* programs = nullptr;  // for the debug slices made on request
    // Debug slices (made when a debug image is requested, outside the measured frame).
    mutable gl::Texture lightSlice, geometrySlice;
    gl::MemoryLedger* ledger = nullptr;
};

bool geometryNeeded(const Settings& s) { return s.lpv.occlusion || s.lpv.bounce; }

// --check entries of one R, G, B volume triple (SH coefficients: signed);
// `volume` picks the triple when the frame runs (it may alternate).
void outputRgb(PassDecl& d, const std::string& name, std::function<const lpv::Rgb*()> volume) {
    for (std::size_t c = 0; c < 3; ++c)
        d.output(name + "." + "rgb"[c], [volume, c] { return &(*volume())[c]; }, Check::signedValues);
}

class LpvPass : public Pass {
public:
    explicit LpvPass(std::shared_ptr<LpvState> st) : st_(std::move(st)) {}

protected:
    std::shared_ptr<LpvState> st_;
};

// lpv.rsm: places the volume, fills the uniform block, rasterizes the RSM.
class RsmPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.rsm"; }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        st.programs = &ctx.programs;
        st.ledger = &ctx.ledger;
        const LpvSettings& ls = ctx.settings.lpv;
        st.placement = lpv::placeVolume(ls, ctx.scene.bounds(), ctx.view.position, ctx.view.forward());
        auto sun = resolveSun(ctx.scene, ctx.settings);
        st.sunRsm = sun.has_value();
        lpv::UniformInputs in;
        in.placement = st.placement;
        in.rsmViewProj = orthoLightViewProj(st.placement.box(), sun ? sun->towardSun : glm::vec3(0, 1, 0));
        in.specular = lpvSpecularActive(ctx.scene, ctx.settings);
        bool compatible = st.havePrevious && lpv::historyCompatible(st.placement, st.previous);
        in.historyValid = compatible && !ctx.view.cut;
        in.shift = compatible ? lpv::temporalShift(st.placement, st.previous) : glm::ivec3(0);
        gpu::LpvUniforms u = lpv::makeUniforms(ls, in);
        if (!st.ubo) st.ubo = gl::Buffer(ctx.ledger, "lpv.uniforms", sizeof(u));
        st.ubo.upload(&u, sizeof(u));
        st.previous = st.placement;
        st.havePrevious = true;

        int n = ls.rsm;
        if (st.sunRsm) ensureTargets(ctx, st.rsm, st.rsmFbo, "lpv.rsm", n);
        if (st.sunRsm && useComputeRasterLightViews(ctx.settings)) {
            // Compute rasterizer (sun RSM only; local lights' RSMs stay on the
            // hardware rasterizer): visibility buffer of the light's view, then
            // a resolve into flux/normal (lpv/rsm.glsl) and the depth copy.
            glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, st.ubo.id());
            VisibilityTarget& t = st.rsmVis;
            rasterizeVisibility(ctx.programs, ctx.ledger, ctx.gpuScene, in.rsmViewProj, {n, n}, t,
                                visibilityOptions(ctx.settings));
            if (!t.checked) {
                t.checkOverflow(name());
                t.checked = true;
            }
            const gl::Program& resolve = ctx.programs.compute("visibility/rsm_resolve.comp", visibilityDefines(t));
            bindVisibility(resolve, ctx.gpuScene, in.rsmViewProj, t);
            glBindImageTexture(RTGI_VISIBILITY_IMG_RSM_FLUX, st.rsm.flux.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
            glBindImageTexture(RTGI_VISIBILITY_IMG_RSM_NORMAL, st.rsm.normal.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
            gl::dispatch(resolve, n, n);
            copyVisibilityDepth(ctx.programs, t, st.rsm.depth);
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        } else if (st.sunRsm) {
            const gl::Program& prog =
                ctx.programs.raster("raster/scene.vert", "lpv/rsm.frag", {{"RTGI_LIGHT_VIEW", ""}});
            prog.set(RTGI_RASTER_LOC_LIGHT_VIEW_PROJ, in.rsmViewProj);
            glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, st.ubo.id());
            rasterizeScene(ctx, prog, st.rsmFbo.id(), {n, n}, 2);
        }
        // Local lights: one perspective RSM per spot light, six per point /
        // area light, each with its own uniform block (its view-projection).
        const auto& views = ctx.res.localRsmViews;
        if (st.local.size() < views.size()) st.local.resize(views.size());
        st.localUsed = int(views.size());
        const gl::Program& local = ctx.programs.raster("raster/scene.vert", "lpv/rsm.frag",
                                                       {{"RTGI_LIGHT_VIEW", ""}, {"RTGI_RSM_LOCAL", ""}});
        for (std::size_t i = 0; i < views.size(); ++i) {
            LocalRsm& r = st.local[i];
            ensureTargets(ctx, r.rsm, r.fbo, "lpv.rsm.local" + std::to_string(i), n);
            gpu::LpvUniforms lu = u;
            lu.rsmViewProj = views[i].viewProj;
            lu.rsmInvViewProj = glm::inverse(views[i].viewProj);
            if (!r.ubo) r.ubo = gl::Buffer(ctx.ledger, "lpv.uniforms.local" + std::to_string(i), sizeof(lu));
            r.ubo.upload(&lu, sizeof(lu));
            const gpu::GpuLight& g = ctx.res.localLightsCpu[std::size_t(views[i].light)];
            local.set(RTGI_RASTER_LOC_LIGHT_VIEW_PROJ, views[i].viewProj);
            glProgramUniform4fv(local.id(), RTGI_LPV_RSM_LOC_LIGHT, 4, &g.positionRange.x);
            local.set(RTGI_LPV_RSM_LOC_FACE, glm::vec2(views[i].tanHalfFov, float(n)));
            glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, r.ubo.id());
            rasterizeScene(ctx, local, r.fbo.id(), {n, n}, 2);
        }
        glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, st.ubo.id());
    }
    std::vector<std::pair<std::string, double>> stats() override {
        return {{"rsms", double(st_->localUsed + (st_->sunRsm ? 1 : 0))}};
    }
    void declare(PassDecl& d, const Scene& scene, const Settings& s) const override {
        d.output("lpv.rsm.flux", &st_->rsm.flux).output("lpv.rsm.normal", &st_->rsm.normal, Check::signedValues);
        // One flux map per local-light face; the frame renders the kept ones (culling).
        const int faces = maxShadowLayers(resolveLocalLights(scene, s));
        for (int i = 0; i < faces; ++i)
            d.output("lpv.rsm.local" + std::to_string(i) + ".flux", [st = st_, i]() -> const gl::Texture* {
                return i < st->localUsed ? &st->local[std::size_t(i)].rsm.flux : nullptr;
            });
        d.debugImage("lpv.rsm.flux", [this] {
            return DebugImage{"lpv.rsm.flux", &st_->rsm.flux, 1.0f / std::max(maxFlux(), 1e-30f)};
        });
        d.debugImage("lpv.rsm.normal", &st_->rsm.normal);
    }

private:
    static void ensureTargets(FrameContext& ctx, lpv::Rsm& rsm, gl::FramebufferHandle& fbo, const std::string& label,
                              int n) {
        bool changed = rsm.flux.ensure(ctx.ledger, label + ".flux", {GL_TEXTURE_2D, GL_RGBA32F, n, n});
        changed |= rsm.normal.ensure(ctx.ledger, label + ".normal", {GL_TEXTURE_2D, GL_RGBA16F, n, n});
        changed |= rsm.depth.ensure(ctx.ledger, label + ".depth", {GL_TEXTURE_2D, GL_DEPTH_COMPONENT32F, n, n});
        if (!changed && fbo) return;
        GLuint f = 0;
        glCreateFramebuffers(1, &f);
        fbo = gl::FramebufferHandle(f);
        fbo.label((label + ".fbo").c_str());
        glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT0, rsm.flux.id(), 0);
        glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT1, rsm.normal.id(), 0);
        glNamedFramebufferTexture(f, GL_DEPTH_ATTACHMENT, rsm.depth.id(), 0);
        const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        glNamedFramebufferDrawBuffers(f, 2, bufs);
        if (glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw std::runtime_error("lpv.rsm: framebuffer incomplete");
    }
    float maxFlux() const {
        if (!st_->rsm.flux) return 0.0f;
        FloatImage img = readTexture(st_->rsm.flux);
        float m = 0;
        for (std::size_t i = 0; i < img.data.size(); i += 4)
            m = std::max({m, img.data[i], img.data[i + 1], img.data[i + 2]});
        return m;
    }
};

// lpv.inject: compute injection (fp32 atomics) or the seed's raster method.
class InjectPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.inject"; }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        const LpvSettings& ls = ctx.settings.lpv;
        st.volumes.ensureLight(ctx.ledger, st.placement.grid,
                               ls.format == LpvSettings::Format::Rgba32f ? GL_RGBA32F : GL_RGBA16F);
        if (!st.stats) st.stats = gl::Buffer(ctx.ledger, "lpv.stats", sizeof(std::uint32_t));
        // Every RSM of the frame adds into the same accumulation.
        if (ls.path == LpvSettings::Path::Raster) {
            bool first = true;
            if (st.sunRsm) lpv::injectRaster(ctx.programs, st.ubo, st.rsm, ls.rsm, st.volumes, first), first = false;
            for (int i = 0; i < st.localUsed; ++i, first = false)
                lpv::injectRaster(ctx.programs, st.local[std::size_t(i)].ubo, st.local[std::size_t(i)].rsm, ls.rsm,
                                  st.volumes, first);
            if (first) lpv::injectRaster(ctx.programs, st.ubo, st.rsm, 0, st.volumes, true);  // clears only
        } else {
            st.stats.clearZero();
            if (st.sunRsm) lpv::injectCompute(ctx.programs, st.ubo, st.rsm, ls.rsm, st.volumes, st.stats);
            for (int i = 0; i < st.localUsed; ++i)
                lpv::injectCompute(ctx.programs, st.local[std::size_t(i)].ubo, st.local[std::size_t(i)].rsm, ls.rsm,
                                   st.volumes, st.stats);
        }
        glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, st.ubo.id());
    }
    std::vector<std::pair<std::string, double>> stats() override {
        if (!st_->stats) return {};
        std::uint32_t dropped = 0;
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // producer: lpv.inject atomics
        st_->stats.download(&dropped, sizeof(dropped));
        return {{"dropped_texels", double(dropped)}};
    }
    // Compute path: the fp32 accumulation (lpv.pack converts it); raster path: step[0] and accum.
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        lpv::Volumes* v = &st_->volumes;
        if (s.lpv.path == LpvSettings::Path::Raster) {
            outputRgb(d, "lpv.step0", [v] { return &v->step[0]; });
            outputRgb(d, "lpv.accum", [v] { return &v->accum; });
        } else {
            outputRgb(d, "lpv.inject", [v] { return &v->inject; });
        }
    }
};

// lpv.pack: fp32 accumulation -> propagation format (compute path only).
class PackPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.pack"; }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (s.lpv.path == LpvSettings::Path::Raster)
            return d.skip("lpv.path=raster injects straight into the propagation format");
        // pack writes step 0 only; accum is first written by lpv.propagate.
        lpv::Volumes* v = &st_->volumes;
        outputRgb(d, "lpv.step0", [v] { return &v->step[0]; });
    }
    void execute(FrameContext& ctx) override { lpv::packLight(ctx.programs, st_->ubo, st_->volumes); }
};

// lpv.inject_geometry: blocking potential from the RSM and the G-buffer.
class GeometryPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.inject_geometry"; }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!geometryNeeded(s)) return d.skip("lpv.occlusion and lpv.bounce are off");
        d.read(R::linearDepth).read(R::normal).read(R::albedo).read(R::material);
        d.output("lpv.geometry", &st_->volumes.geometry, Check::signedValues);
        d.output("lpv.geometry_albedo", &st_->volumes.geometryAlbedo);
        d.debugImage("lpv.geometry.slice", [this] { return geometrySlice(); });
    }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        st.volumes.ensureGeometry(ctx.ledger);
        const GBuffer& g = ctx.res.gbuffer;
        lpv::GBufferView gb{&g.linearDepth, &g.normal, &g.albedo, &g.material, ctx.view.size};
        // Blocking potential from the sun's orthographic RSM (its texel areas)
        // and the G-buffer; local lights' perspective RSMs are not used here.
        lpv::injectGeometry(ctx.programs, st.ubo, st.rsm, st.sunRsm ? ctx.settings.lpv.rsm : 0, gb, st.volumes);
    }
    DebugImage geometrySlice() const {
        const lpv::Volumes& v = st_->volumes;
        if (!v.geometry || !st_->programs) return {"lpv.geometry.slice", nullptr};
        glm::ivec3 d = v.grid + 1;
        st_->geometrySlice.ensure(*st_->ledger, "lpv.debug.geometry_slice", {GL_TEXTURE_2D, GL_RGBA32F, d.x, d.y});
        const gl::Program& prog = st_->programs->compute("lpv/slice.comp", {{"RTGI_LPV_SLICE_GEOMETRY", ""}});
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);  // producer: lpv.pack (geometry)
        glBindTextureUnit(RTGI_LPV_SLICE_TEX_A, v.geometry.id());
        glBindTextureUnit(RTGI_LPV_SLICE_TEX_B, v.geometryAlbedo.id());
        glBindImageTexture(RTGI_LPV_IMG_SLICE, st_->geometrySlice.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        prog.set(RTGI_LPV_LOC_Z, d.z / 2);
        gl::dispatch(prog, d.x, d.y);
        return {"lpv.geometry.slice", &st_->geometrySlice, 1.0f};
    }
};

// lpv.propagate: all iterations inside one pass scope.
class PropagatePass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.propagate"; }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        const LpvSettings& ls = ctx.settings.lpv;
        if (ls.path == LpvSettings::Path::Raster)
            st.lastStep = lpv::propagateRaster(ctx.programs, st.ubo, st.volumes, ls.iterations);
        else
            st.lastStep = lpv::propagateCompute(ctx.programs, st.ubo, st.volumes, ls.iterations);
        st.result = &st.volumes.accum;
    }
    void declare(PassDecl& d, const Scene&, const Settings&) const override {
        LpvState* st = st_.get();
        outputRgb(d, "lpv.accum", [st] { return &st->volumes.accum; });
        outputRgb(d, "lpv.last_step", [st] { return &st->volumes.step[std::size_t(st->lastStep)]; });
        d.debugImage("lpv.volume.slice", [this] { return lightSlice(); });
    }
    DebugImage lightSlice() const {
        const lpv::Volumes& v = st_->volumes;
        if (!st_->result || !st_->programs) return {"lpv.volume.slice", nullptr};
        st_->lightSlice.ensure(*st_->ledger, "lpv.debug.light_slice", {GL_TEXTURE_2D, GL_RGBA32F, v.grid.x, v.grid.y});
        const gl::Program& prog = st_->programs->compute("lpv/slice.comp");
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);  // producer: lpv.propagate / lpv.temporal
        const lpv::Rgb& r = *st_->result;
        for (GLuint c = 0; c < 3; ++c) glBindTextureUnit(RTGI_LPV_SLICE_TEX_A + c, r[c].id());
        glBindImageTexture(RTGI_LPV_IMG_SLICE, st_->lightSlice.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        prog.set(RTGI_LPV_LOC_Z, v.grid.z / 2);
        gl::dispatch(prog, v.grid.x, v.grid.y);
        FloatImage img = readTexture(st_->lightSlice);
        float m = 0;
        for (std::size_t i = 0; i < img.data.size(); i += 4)
            m = std::max({m, img.data[i], img.data[i + 1], img.data[i + 2]});
        return {"lpv.volume.slice", &st_->lightSlice, m > 0 ? 1.0f / m : 1.0f};
    }
};

// lpv.temporal: blend with the previous volume, re-indexed by the cell shift.
class TemporalPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.temporal"; }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (s.lpv.temporal <= 0.0f) return d.skip("lpv.temporal = 0");
        LpvState* st = st_.get();
        outputRgb(d, "lpv.history", [st] { return &st->volumes.history[std::size_t(st->historyTarget)]; });
    }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        st.volumes.ensureHistory(ctx.ledger);
        st.historyTarget = 1 - st.historyTarget;
        lpv::temporalBlend(ctx.programs, st.ubo, st.volumes, st.historyTarget);
        st.result = &st.volumes.history[std::size_t(st.historyTarget)];
    }
};

// lpv.apply: indirect diffuse (+ specular) radiance from the volume.
class ApplyPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.apply"; }
    void declare(PassDecl& d, const Scene& scene, const Settings& s) const override {
        d.read(R::linearDepth).read(R::normal).read(R::albedo).read(R::material);
        d.readIfWritten(R::bentNormal).readIfWritten(R::s3ho);  // directional occlusion of the lookup
        d.write(R::indirectDiffuse);
        if (lpvSpecularActive(scene, s)) d.read(R::brdfLut).write(R::specular);
    }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        FrameResources& r = ctx.res;
        const glm::ivec2 s = ctx.view.size;
        bool specular = lpvSpecularActive(ctx.scene, ctx.settings);
        lpv::ApplyInputs in;
        in.gbuffer = {&r.gbuffer.linearDepth, &r.gbuffer.normal, &r.gbuffer.albedo, &r.gbuffer.material, s};
        in.volume = st.result;
        in.brdfLut = specular ? &r.brdfLut : nullptr;
        in.s3ho = ctx.has(R::s3ho) ? &r.s3ho : nullptr;
        in.bentNormal = ctx.has(R::bentNormal) ? &r.bentNormal : nullptr;
        in.indirect = &r.indirectDiffuse;
        in.specular = specular ? &r.specular : nullptr;
        lpv::applyCompute(ctx.programs, st.ubo, in);
    }
};

}  // namespace

void appendLpvPasses(std::vector<std::unique_ptr<Pass>>& f) {
    auto st = std::make_shared<LpvState>();
    f.push_back(std::make_unique<RsmPass>(st));        // reflective shadow map fitted to the volume
    f.push_back(std::make_unique<InjectPass>(st));     // RSM texels -> SH (fp32 atomics | raster points)
    f.push_back(std::make_unique<PackPass>(st));       // fp32 -> lpv.format (compute path)
    f.push_back(std::make_unique<GeometryPass>(st));   // blocking potential (occlusion, bounce)
    f.push_back(std::make_unique<PropagatePass>(st));  // iterations, fused accumulation
    f.push_back(std::make_unique<TemporalPass>(st));   // blend with the re-indexed previous volume
    f.push_back(std::make_unique<ApplyPass>(st));      // indirect diffuse + specular radiance
}

Need lpvFamily(const Scene& scene, const Settings& s) {
    if (s.lpv.mode == Toggle::Off) return Need::no("lpv=off");
    if (!lpvActive(scene, s))
        return Need::no("the scene has no light: no sun, and no point, spot or emissive-region light (no RSM, no LPV)");
    return Need::yes();
}

bool lpvActive(const Scene& scene, const Settings& s) {
    if (s.lpv.mode == Toggle::Off) return false;
    return resolveSun(scene, s).has_value() || hasLocalLights(scene, s);
}

bool lpvSpecularActive(const Scene& scene, const Settings& s) {
    if (!lpvActive(scene, s) || s.lpv.specular == Toggle::Off) return false;
    if (s.lpv.specular == Toggle::On) return true;
    return resolveMaterials(scene, s).size() && scene.minRoughness() <= s.ssr.roughnessCutoff;
}

}  // namespace rtgi
