// visibility.raster, visibility.resolve and shadow.raster: the camera's
// G-buffer and the sun's shadow map through the compute rasterizer.
#include "render/visibility/visibility_passes.h"

#include "gl/profiler.h"
#include "render/gpu_scene.h"
#include "render/passes/core_passes.h"
#include "render/visibility/visibility.h"

#include "compute/lib/visibility_shared.h"

namespace rtgi {
namespace {

bool computePath(const Settings& s) { return useComputeRaster(s); }

std::vector<std::pair<std::string, double>> counterStats(const VisibilityTarget& t) {
    if (!t.counters) return {};
    VisibilityCounters c = t.readCounters();
    return {{"triangles", t.triangles},          {"culled", c.culledCount},
            {"small", c.smallCount},             {"large", c.largeCount},
            {"bin_entries", c.nodeCount},        {"atomic64", t.atomic64 ? 1.0 : 0.0}};
}

struct VisibilityState {
    VisibilityTarget target{"visibility"};
};

// visibility.raster: the camera's visibility buffer.
class VisibilityRasterPass final : public Pass {
public:
    explicit VisibilityRasterPass(std::shared_ptr<VisibilityState> st) : st_(std::move(st)) {}
    std::string name() const override { return "visibility.raster"; }
    // Its output is the private visibility buffer (st_), read only by
    // visibility.resolve, which runs under the same condition right after it.
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!computePath(s)) return d.skip(rasterPathReason(s) + " (gbuffer)");
    }
    void execute(FrameContext& ctx) override {
        rasterizeVisibility(ctx.programs, ctx.ledger, ctx.gpuScene, ctx.view.viewProj(), ctx.view.size, st_->target,
                            visibilityOptions(ctx.settings));
        if (!st_->target.checked) {  // one stall, on the first frame (warm-up)
            st_->target.checkOverflow(name());
            st_->target.checked = true;
        }
    }
    std::vector<std::pair<std::string, double>> stats() override {
        st_->target.checkOverflow(name());
        return counterStats(st_->target);
    }

private:
    std::shared_ptr<VisibilityState> st_;
};

// visibility.resolve: visibility buffer -> G-buffer targets (imageStore).
class VisibilityResolvePass final : public Pass {
public:
    explicit VisibilityResolvePass(std::shared_ptr<VisibilityState> st) : st_(std::move(st)) {}
    std::string name() const override { return "visibility.resolve"; }
    // The G-buffer resources of the hardware pass `gbuffer` but its depth
    // attachment (R::depth, which no pass reads: a full-screen gl_FragDepth copy
    // cost 0.18 ms at 1080p on the H200); the renderer allocates them from
    // their descriptors.
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!computePath(s)) return d.skip(rasterPathReason(s) + " (gbuffer)");
        d.write(R::linearDepth).write(R::normal).write(R::albedo).write(R::material);
        d.write(R::emissive).write(R::velocity);
    }
    void execute(FrameContext& ctx) override {
        GBuffer& g = ctx.res.gbuffer;
        VisibilityTarget& t = st_->target;
        const gl::Program& prog = ctx.programs.compute("visibility/resolve.comp", visibilityDefines(t));
        bindVisibility(prog, ctx.gpuScene, ctx.view.viewProj(), t);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_VISIBILITY_SSBO_PREV_VERTICES, ctx.gpuScene.previousVertices().id());
        glBindImageTexture(RTGI_VISIBILITY_IMG_LINEAR_DEPTH, g.linearDepth.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        glBindImageTexture(RTGI_VISIBILITY_IMG_NORMAL, g.normal.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        glBindImageTexture(RTGI_VISIBILITY_IMG_ALBEDO, g.albedo.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
        glBindImageTexture(RTGI_VISIBILITY_IMG_MATERIAL, g.material.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
        glBindImageTexture(RTGI_VISIBILITY_IMG_EMISSIVE, g.emissive.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R11F_G11F_B10F);
        glBindImageTexture(RTGI_VISIBILITY_IMG_VELOCITY, g.velocity.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG16F);
        gl::dispatch(prog, t.size.x, t.size.y);
        // Consumers sample these as textures; the next passes' barriers are theirs,
        // but image stores need this one before any texture fetch.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }

private:
    std::shared_ptr<VisibilityState> st_;
};

// visibility.layer2: the second depth layer of the camera view for vbao
// (ao.second_layer; docs/ao.md "Second depth layer"): the raster's setup and
// tile again over visibility.raster's bins, keeping the nearest surface at
// least the vbao thickness behind the first layer.
class VisibilityLayer2Pass final : public Pass {
public:
    explicit VisibilityLayer2Pass(std::shared_ptr<VisibilityState> st) : st_(std::move(st)) {}
    std::string name() const override { return "visibility.layer2"; }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!s.ao.secondLayer) return d.skip("ao.second_layer=off");
        if (s.ao.variant != AoSettings::Variant::Vbao)
            throw ConfigError(std::string("setting 'ao.second_layer': on needs ao=vbao (the only estimator that reads a "
                                          "second depth layer), not ao=") + toString(s.ao.variant));
        if (s.ao.thicknessMode == AoSettings::ThicknessMode::Infinite)
            throw ConfigError("setting 'ao.second_layer': on needs ao.thickness_mode=constant or depth (the thickness is "
                              "the layer's minimum separation), not infinite");
        if (!computePath(s))
            return d.skip(rasterPathReason(s) + ": the hardware path omits the second depth layer (vbao uses its "
                          "thickness model)");
        d.read(R::linearDepth).write(R::linearDepth2);
    }
    void execute(FrameContext& ctx) override {
        const AoSettings& a = ctx.settings.ao;
        SecondLayerOptions o;
        o.separation = a.thickness;
        o.depthScaled = a.thicknessMode == AoSettings::ThicknessMode::Depth;
        rasterizeSecondLayer(ctx.programs, ctx.gpuScene, ctx.view.viewProj(), ctx.view.proj, st_->target,
                             ctx.res.gbuffer.linearDepth, ctx.res.gbuffer.linearDepth2, o);
    }

private:
    std::shared_ptr<VisibilityState> st_;
};

// shadow.raster: the sun's depth map (same light frustum and slope-scaled
// bias as the hardware pass `shadow`).
class ShadowRasterPass final : public Pass {
public:
    std::string name() const override { return "shadow.raster"; }
    void declare(PassDecl& d, const Scene& scene, const Settings& s) const override {
        if (!resolveSun(scene, s)) return d.skip("the scene has no directional light");
        if (!useComputeRasterLightViews(s)) return d.skip(rasterPathReason(s, true) + " (shadow)");
        d.write(R::shadowMap);
    }
    void execute(FrameContext& ctx) override {
        if (epoch_ != ctx.res.allocationEpoch) {
            // Same sampling as the hardware pass: readers use sampler2DShadow.
            epoch_ = ctx.res.allocationEpoch;
            glTextureParameteri(ctx.res.shadowMap.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
            glTextureParameteri(ctx.res.shadowMap.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
            target_.resetDepthTargets();
        }
        int n = ctx.settings.light.shadowSize;
        if (shadowMapCurrent(ctx, 1)) return;
        ++redraws_;
        VisibilityOptions o = visibilityOptions(ctx.settings);
        o.depthBias = true;
        rasterizeVisibility(ctx.programs, ctx.ledger, ctx.gpuScene, ctx.res.shadowViewProj, {n, n}, target_, o);
        copyVisibilityDepth(ctx.programs, target_, ctx.res.shadowMap);
        if (!target_.checked) {
            target_.checkOverflow(name());
            target_.checked = true;
        }
    }
    std::vector<std::pair<std::string, double>> stats() override {
        target_.checkOverflow(name());
        auto st = counterStats(target_);
        st.emplace_back("redraws", double(redraws_));  // the other frames reused the map (shadow.cache)
        return st;
    }

private:
    VisibilityTarget target_{"shadow.raster"};
    int redraws_ = 0;
    unsigned epoch_ = 0;  // FrameResources::allocationEpoch the compare mode and copy FBO were set for
};

}  // namespace

void appendVisibilityPasses(std::vector<std::unique_ptr<Pass>>& frame) {
    auto st = std::make_shared<VisibilityState>();
    frame.push_back(std::make_unique<VisibilityRasterPass>(st));
    frame.push_back(std::make_unique<VisibilityResolvePass>(st));
    frame.push_back(std::make_unique<VisibilityLayer2Pass>(st));
}

std::unique_ptr<Pass> makeShadowRasterPass() { return std::make_unique<ShadowRasterPass>(); }

}  // namespace rtgi
