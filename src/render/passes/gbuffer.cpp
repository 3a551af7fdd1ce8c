// gbuffer: rasterizes the whole scene once into the G-buffer targets.
#include "gl/profiler.h"
#include "gl/program.h"
#include "render/gpu_scene.h"
#include "render/passes/core_passes.h"
#include "render/visibility/visibility.h"

namespace rtgi {

bool ensureGBuffer(FrameContext& ctx) {
    GBuffer& g = ctx.res.gbuffer;
    const glm::ivec2 s = ctx.view.size;
    bool changed = false;
    changed |= g.depth.ensure(ctx.ledger, "gbuffer.depth", {GL_TEXTURE_2D, GL_DEPTH_COMPONENT32F, s.x, s.y});
    changed |= g.linearDepth.ensure(ctx.ledger, "gbuffer.linearDepth", {GL_TEXTURE_2D, GL_R32F, s.x, s.y});
    changed |= g.normal.ensure(ctx.ledger, "gbuffer.normal", {GL_TEXTURE_2D, GL_RGBA16F, s.x, s.y});
    changed |= g.albedo.ensure(ctx.ledger, "gbuffer.albedo", {GL_TEXTURE_2D, GL_RGBA8, s.x, s.y});
    changed |= g.material.ensure(ctx.ledger, "gbuffer.material", {GL_TEXTURE_2D, GL_RGBA8, s.x, s.y});
    changed |= g.emissive.ensure(ctx.ledger, "gbuffer.emissive", {GL_TEXTURE_2D, GL_R11F_G11F_B10F, s.x, s.y});
    changed |= g.velocity.ensure(ctx.ledger, "gbuffer.velocity", {GL_TEXTURE_2D, GL_RG16F, s.x, s.y});
    return changed;
}

namespace {

class GBufferPass final : public Pass {
public:
    std::string name() const override { return "gbuffer"; }
    Need needed(const Scene&, const Settings& s) const override {
        if (useComputeRaster(s)) return Need::no(rasterPathReason(s) + " (visibility.raster)");
        return Need::yes();
    }
    std::vector<std::string> writes() const override {
        return {"gbuffer.depth", "gbuffer.linearDepth", "gbuffer.normal", "gbuffer.albedo",
                "gbuffer.material", "gbuffer.emissive", "gbuffer.velocity"};
    }

    void execute(FrameContext& ctx) override {
        GBuffer& g = ctx.res.gbuffer;
        const glm::ivec2 s = ctx.view.size;
        bool changed = ensureGBuffer(ctx);
        if (changed || !fbo_) {
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
};

}  // namespace

std::unique_ptr<Pass> makeGBufferPass() { return std::make_unique<GBufferPass>(); }

}  // namespace rtgi
