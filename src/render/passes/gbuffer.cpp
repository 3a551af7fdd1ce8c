// gbuffer: rasterizes the whole scene once into the G-buffer targets.
#include "gl/profiler.h"
#include "gl/program.h"
#include "render/gpu_scene.h"
#include "render/passes/core_passes.h"
#include "render/visibility/visibility.h"

namespace rtgi {
namespace {

class GBufferPass final : public Pass {
public:
    std::string name() const override { return "gbuffer"; }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (useComputeRaster(s)) return d.skip(rasterPathReason(s) + " (visibility.raster)");
        d.write(R::depth).write(R::linearDepth).write(R::normal).write(R::albedo).write(R::material);
        d.write(R::emissive).write(R::velocity);
    }

    void execute(FrameContext& ctx) override {
        GBuffer& g = ctx.res.gbuffer;
        const glm::ivec2 s = ctx.view.size;
        if (epoch_ != ctx.res.allocationEpoch || !fbo_) {
            epoch_ = ctx.res.allocationEpoch;
            GLuint f = 0;
            glCreateFramebuffers(1, &f);
            fbo_ = gl::FramebufferHandle(f);
            fbo_.label("gbuffer.fbo");
            glNamedFramebufferTexture(f, GL_DEPTH_ATTACHMENT, g.depth.id(), 0);
            const gl::Texture* color[] = {&g.linearDepth, &g.normal, &g.albedo, &g.material, &g.emissive, &g.velocity};
            GLenum bufs[6];
            for (int i = 0; i < 6; ++i) {
                glNamedFramebufferTexture(f, GLenum(GL_COLOR_ATTACHMENT0 + i), color[i]->id(), 0);
                bufs[i] = GLenum(GL_COLOR_ATTACHMENT0 + i);
            }
            glNamedFramebufferDrawBuffers(f, 6, bufs);
            if (glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
                throw std::runtime_error("gbuffer: framebuffer incomplete");
        }
        const gl::Program& prog = ctx.programs.raster("raster/scene.vert", "raster/gbuffer.frag");
        rasterizeScene(ctx, prog, fbo_.id(), s, 6);
    }

private:
    gl::FramebufferHandle fbo_;
    unsigned epoch_ = 0;  // FrameResources::allocationEpoch the framebuffer was made for
};

}  // namespace

std::unique_ptr<Pass> makeGBufferPass() { return std::make_unique<GBufferPass>(); }

}  // namespace rtgi
