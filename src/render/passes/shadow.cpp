// shadow: depth map of the sun (orthographic, fitted to the scene bounds).
#include "gl/profiler.h"
#include "gl/program.h"
#include "compute/lib/raster_shared.h"
#include "render/gpu_scene.h"
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
        if (useComputeRaster(settings)) return d.skip(rasterPathReason(settings) + " (shadow.raster)");
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
        const gl::Program& prog =
            ctx.programs.raster("raster/scene.vert", "raster/depth_only.frag", {{"RTGI_LIGHT_VIEW", ""}});
        prog.set(RTGI_RASTER_LOC_LIGHT_VIEW_PROJ, ctx.res.shadowViewProj);
        rasterizeScene(ctx, prog, fbo_.id(), {n, n}, 0, /*depthBias=*/true);
    }

private:
    gl::FramebufferHandle fbo_;
    unsigned epoch_ = 0;  // FrameResources::allocationEpoch the framebuffer was made for
};

}  // namespace

std::unique_ptr<Pass> makeShadowPass() { return std::make_unique<ShadowPass>(); }

}  // namespace rtgi
