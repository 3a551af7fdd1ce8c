// direct: sun + punctual lights + emission into res.direct (compute).
#include "gl/bindings.h"
#include "gl/program.h"
#include "render/gpu_scene.h"
#include "render/passes/core_passes.h"
#include "compute/lib/post_shared.h"

namespace rtgi {
namespace {

class DirectPass final : public Pass {
public:
    std::string name() const override { return "direct"; }
    void declare(PassDecl& d, const Scene&, const Settings&) const override {
        d.read(R::linearDepth).read(R::normal).read(R::albedo).read(R::material).read(R::emissive);
        d.readIfWritten(R::shadowMap).readIfWritten(R::localShadowMaps).write(R::direct);
    }

    void execute(FrameContext& ctx) override {
        dispatchDirect(ctx, ctx.res.direct, false);
    }
};

GLuint localShadowDepthSampler(FrameResources& res) {
    if (!res.localShadowDepthSampler) {
        GLuint id = 0;
        glCreateSamplers(1, &id);
        res.localShadowDepthSampler = gl::SamplerHandle(id);
        res.localShadowDepthSampler.label("shadow.local.depth_sampler");
        glSamplerParameteri(id, GL_TEXTURE_COMPARE_MODE, GL_NONE);
        glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glSamplerParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    return res.localShadowDepthSampler.id();
}

}  // namespace

void dispatchDirect(FrameContext& ctx, const gl::Texture& target, bool diffuseOnly) {
    const GBuffer& g = ctx.res.gbuffer;
    gl::Defines defs;
    if (diffuseOnly) defs.push_back({"RTGI_DIFFUSE_ONLY", ""});
    const bool local = ctx.has(R::localShadowMaps);
    if (local) defs.push_back({"RTGI_LOCAL_SHADOWS", ""});
    const bool shadow = ctx.has(R::shadowMap);
    if (shadow) defs.push_back({"RTGI_SUN_SHADOW_MAP", ""});
    const gl::Program& prog = ctx.programs.compute("post/direct.comp", defs);
    // Producer: gbuffer and shadow raster passes (framebuffer writes).
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    gl::ScopedBindings b;
    b.texture(RTGI_POST_TEX_LINEAR_DEPTH, g.linearDepth)
        .texture(RTGI_POST_TEX_NORMAL, g.normal)
        .texture(RTGI_POST_DIRECT_TEX_ALBEDO, g.albedo)
        .texture(RTGI_POST_DIRECT_TEX_MATERIAL, g.material)
        .texture(RTGI_POST_TEX_EMISSIVE, g.emissive)
        .texture(RTGI_POST_TEX_SHADOW_MAP, shadow ? &ctx.res.shadowMap : nullptr);
    ctx.gpuScene.bindTables();
    // The real-time light list (culled, with shadow layers) replaces the scene's.
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_LIGHTS, ctx.res.localLights.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_LIGHT_SHAPES, ctx.res.localLightShapes.id());
    if (local) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_LOCAL_SHADOW_MATRICES, ctx.res.localShadowMatrices.id());
        b.texture(RTGI_POST_DIRECT_TEX_LOCAL_SHADOWS, ctx.res.localShadowMaps);
        // The same layers once more, read as raw depth (blocker search of the soft shadows).
        b.texture(RTGI_POST_DIRECT_TEX_LOCAL_DEPTH, ctx.res.localShadowMaps);
        glBindSampler(RTGI_POST_DIRECT_TEX_LOCAL_DEPTH, localShadowDepthSampler(ctx.res));
    }
    b.image(RTGI_POST_IMG_DIRECT, target, GL_WRITE_ONLY, GL_RGBA16F);
    gl::dispatch(prog, target.width(), target.height());
    if (local) glBindSampler(RTGI_POST_DIRECT_TEX_LOCAL_DEPTH, 0);  // the unit's next user samples with its texture's state
}

std::unique_ptr<Pass> makeDirectPass() { return std::make_unique<DirectPass>(); }

}  // namespace rtgi
