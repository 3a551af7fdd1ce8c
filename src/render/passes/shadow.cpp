// shadow: depth map of the sun (orthographic, fitted to the scene bounds).
// shadow.local: perspective maps of spot lights and cubes of point / area
// lights (render/lights.h), one layer of a D32F array each.
#include "gl/profiler.h"
#include "gl/program.h"
#include "compute/lib/raster_shared.h"
#include "render/gpu_scene.h"
#include "render/lights.h"
#include "render/passes/core_passes.h"
#include "render/visibility/visibility.h"

#include <glm/gtc/matrix_transform.hpp>

namespace rtgi {

glm::mat4 orthoLightViewProj(const Aabb& box, glm::vec3 towardLight) {
    glm::vec3 c = box.center();
    float r = std::max(0.5f * glm::length(box.extent()), 1e-6f);
    glm::vec3 l = glm::normalize(towardLight);
    glm::vec3 up = std::abs(l.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    glm::mat4 view = glm::lookAt(c + l * (2.0f * r), c, up);
    // Tight x/y/z crop of the box corners in light space (seed eq. 18).
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (int i = 0; i < 8; ++i) {
        glm::vec3 corner((i & 1) ? box.hi.x : box.lo.x, (i & 2) ? box.hi.y : box.lo.y, (i & 4) ? box.hi.z : box.lo.z);
        glm::vec3 q = glm::vec3(view * glm::vec4(corner, 1.0f));
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    float pad = 1e-4f * r;
    glm::mat4 proj = glm::ortho(lo.x - pad, hi.x + pad, lo.y - pad, hi.y + pad, -hi.z - pad, -lo.z + pad);
    return proj * view;
}

namespace {

class ShadowPass final : public Pass {
public:
    std::string name() const override { return "shadow"; }
    void declare(PassDecl& d, const Scene& scene, const Settings& settings) const override {
        if (!resolveSun(scene, settings)) return d.skip("the scene has no directional light");
        if (useComputeRasterLightViews(settings)) return d.skip(rasterPathReason(settings, true) + " (shadow.raster)");
        d.write(R::shadowMap);
    }

    void execute(FrameContext& ctx) override {
        int n = ctx.settings.light.shadowSize;
        if (epoch_ != ctx.res.allocationEpoch || !fbo_) {
            epoch_ = ctx.res.allocationEpoch;
            glTextureParameteri(ctx.res.shadowMap.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
            glTextureParameteri(ctx.res.shadowMap.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
            GLuint f = 0;
            glCreateFramebuffers(1, &f);
            fbo_ = gl::FramebufferHandle(f);
            fbo_.label("shadow.fbo");
            glNamedFramebufferTexture(f, GL_DEPTH_ATTACHMENT, ctx.res.shadowMap.id(), 0);
            glNamedFramebufferDrawBuffer(f, GL_NONE);
        }
        if (shadowMapCurrent(ctx, 0)) return;
        renderShadowDepth(ctx, ctx.res.shadowViewProj, fbo_.id(), {n, n});
        ++redraws_;
    }
    // Frames (warm-up included) that drew the map; the rest reused it (shadow.cache).
    std::vector<std::pair<std::string, double>> stats() override { return {{"redraws", double(redraws_)}}; }

private:
    gl::FramebufferHandle fbo_;
    unsigned epoch_ = 0;  // FrameResources::allocationEpoch the framebuffer was made for
    int redraws_ = 0;
};

class LocalShadowPass final : public Pass {
public:
    std::string name() const override { return "shadow.local"; }
    void declare(PassDecl& d, const Scene& scene, const Settings& settings) const override {
        LocalLights ll = resolveLocalLights(scene, settings);
        bool lit = false;
        for (auto& l : ll.lights)
            lit |= l.gpu.colorIntensity.x > 0 || l.gpu.colorIntensity.y > 0 || l.gpu.colorIntensity.z > 0;
        if (!lit)
            return d.skip(ll.lights.empty() ? "the scene has no point, spot or emissive-region light"
                                            : "every point, spot or emissive-region light has zero intensity");
        // Allocated by the renderer (Extent::localShadow: every light's layers
        // at once, so culling never reallocates); this pass only fills layers.
        d.write(R::localShadowMaps);
    }

    void execute(FrameContext& ctx) override {
        FrameResources& r = ctx.res;
        const int n = ctx.settings.light.localShadowSize;
        const int layers = r.localShadowMaps.depth();
        if (epoch_ != r.allocationEpoch || fbos_.size() != std::size_t(layers)) {
            epoch_ = r.allocationEpoch;
            glTextureParameteri(r.localShadowMaps.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
            glTextureParameteri(r.localShadowMaps.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
            fbos_.clear();
            for (int l = 0; l < layers; ++l) {
                GLuint f = 0;
                glCreateFramebuffers(1, &f);
                fbos_.emplace_back(f);
                fbos_.back().label(("shadow.local.fbo" + std::to_string(l)).c_str());
                glNamedFramebufferTextureLayer(f, GL_DEPTH_ATTACHMENT, r.localShadowMaps.id(), 0, l);
                glNamedFramebufferDrawBuffer(f, GL_NONE);
            }
        }
        if (useComputeRasterLightViews(ctx.settings)) {
            // The compute rasterizer (issue 14: every rasterized view): each
            // face into one visibility target, its depth copied into the layer
            // with the same slope-scaled bias as the hardware pass.
            if (targetEpoch_ != r.allocationEpoch) {
                targetEpoch_ = r.allocationEpoch;
                target_.resetDepthTargets();
            }
            VisibilityOptions o = visibilityOptions(ctx.settings);
            o.depthBias = true;
            for (auto& v : r.localShadowViews) {
                rasterizeVisibility(ctx.programs, ctx.ledger, ctx.gpuScene, v.viewProj, {n, n}, target_, o);
                copyVisibilityDepth(ctx.programs, target_, r.localShadowMaps, v.layer);
                if (!target_.checked) {
                    target_.checkOverflow(name());
                    target_.checked = true;
                }
            }
            compute_ = true;
        } else {
            for (auto& v : r.localShadowViews)
                renderShadowDepth(ctx, v.viewProj, fbos_[std::size_t(v.layer)].id(), {n, n});
            compute_ = false;
        }
        layersDrawn_ = int(r.localShadowViews.size());
        culled_ = r.localLightsCulled;
        waiting_ = r.localLightsWaiting;
        cached_ = r.localFacesCached;
    }
    // Lights left out this frame (their influence sphere misses the view
    // frustum, or zero intensity), the layers drawn for the others, and from
    // the light budget: lights waiting for their first maps, shadow and RSM
    // faces reused from earlier frames.
    std::vector<std::pair<std::string, double>> stats() override {
        return {{"layers", double(layersDrawn_)}, {"lights_culled", double(culled_)},
                {"lights_waiting", double(waiting_)}, {"faces_cached", double(cached_)},
                {"compute", compute_ ? 1.0 : 0.0}};
    }

private:
    std::vector<gl::FramebufferHandle> fbos_;
    unsigned epoch_ = 0;  // FrameResources::allocationEpoch the framebuffers were made for
    VisibilityTarget target_{"shadow.local"};
    unsigned targetEpoch_ = 0;
    int layersDrawn_ = 0, culled_ = 0, waiting_ = 0, cached_ = 0;
    bool compute_ = false;
};

}  // namespace

std::unique_ptr<Pass> makeShadowPass() { return std::make_unique<ShadowPass>(); }
std::unique_ptr<Pass> makeLocalShadowPass() { return std::make_unique<LocalShadowPass>(); }

bool shadowMapCurrent(FrameContext& ctx, int writer) {
    FrameResources::ShadowKey key{ctx.res.shadowViewProj, ctx.settings.light.shadowSize,
                                  ctx.gpuScene.geometryVersion(), ctx.res.allocationEpoch, writer};
    bool current = ctx.settings.light.shadowCache && key == ctx.res.shadowKey;
    ctx.res.shadowKey = key;
    return current;
}

void renderShadowDepth(FrameContext& ctx, const glm::mat4& viewProj, GLuint fbo, glm::ivec2 size) {
    const gl::Program& prog =
        ctx.programs.raster("raster/scene.vert", "raster/depth_only.frag", {{"RTGI_LIGHT_VIEW", ""}});
    prog.set(RTGI_RASTER_LOC_LIGHT_VIEW_PROJ, viewProj);
    rasterizeScene(ctx, prog, fbo, size, 0, /*depthBias=*/true);
}

}  // namespace rtgi
