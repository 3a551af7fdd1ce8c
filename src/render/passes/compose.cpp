// post.compose: direct + sky ambient·AO + indirect + specular, tonemapped.
#include "gl/bindings.h"
#include "gl/program.h"
#include "render/frame_plan.h"
#include "render/passes/core_passes.h"
#include "compute/lib/post_shared.h"

namespace rtgi {
namespace {

class ComposePass final : public Pass {
public:
    std::string name() const override { return "post.compose"; }
    void declare(PassDecl& d, const Scene&, const Settings&) const override {
        d.read(R::direct).read(R::albedo).read(R::material);
        d.readIfWritten(R::indirectDiffuse).readIfWritten(R::specular).readIfWritten(R::ao);
        d.readIfWritten(R::bentNormal).readIfWritten(R::s3ho);
        d.write(R::hdr).write(R::ldr);
    }

    void execute(FrameContext& ctx) override {
        FrameResources& r = ctx.res;
        dispatchCompose(ctx, r.direct, r.hdr, &r.ldr, false);
    }
};

}  // namespace

void dispatchCompose(FrameContext& ctx, const gl::Texture& direct, const gl::Texture& hdr, const gl::Texture* ldr,
                     bool diffuseOnly) {
    const FrameResources& r = ctx.res;
    // post.history is in the frame (a pass reads the previous frame's radiance): compose writes its
    // image too, one full-resolution dispatch fewer (src/render/frame.cpp, HistoryPass).
    const bool history = !diffuseOnly && ctx.plan && ctx.plan->written(R::history);
    gl::Defines defines;
    if (diffuseOnly) defines.push_back({"RTGI_DIFFUSE_ONLY", ""});
    if (history) defines.push_back({"RTGI_COMPOSE_HISTORY", ""});
    const gl::Program& prog = ctx.programs.compute("post/compose.comp", defines);
    // Producers: direct, ao.*, lpv.apply, ssr.* (all image stores).
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    bool specular = ctx.has(R::specular) && !diffuseOnly;
    bool indirect = ctx.has(R::indirectDiffuse), ao = ctx.has(R::ao);
    gl::ScopedBindings b;
    b.texture(RTGI_POST_TEX_DIRECT, direct)
        .texture(RTGI_POST_COMPOSE_TEX_ALBEDO, r.gbuffer.albedo)
        .texture(RTGI_POST_COMPOSE_TEX_MATERIAL, r.gbuffer.material)
        .texture(RTGI_POST_TEX_INDIRECT, indirect ? &r.indirectDiffuse : nullptr)
        .texture(RTGI_POST_TEX_SPECULAR, specular ? &r.specular : nullptr)
        .texture(RTGI_POST_TEX_AO, ao ? &r.ao : nullptr)
        .texture(RTGI_POST_COMPOSE_TEX_LINEAR_DEPTH, diffuseOnly || history ? &r.gbuffer.linearDepth : nullptr);
    // Occlusion is not applied to the indirect term twice when the LPV lookup
    // already used bent normals or S3HO.
    bool aoInLpv = indirect && (ctx.has(R::bentNormal) || ctx.has(R::s3ho));
    prog.set(RTGI_POST_LOC_HAVE, glm::ivec4(indirect, specular, ao, aoInLpv));
    b.image(RTGI_POST_IMG_HDR, hdr, GL_WRITE_ONLY, diffuseOnly ? GL_RGBA16F : GL_RGBA32F);
    if (ldr) b.image(RTGI_POST_IMG_LDR, *ldr, GL_WRITE_ONLY, GL_RGBA8);
    if (history) b.image(RTGI_POST_COMPOSE_IMG_HISTORY, r.history, GL_WRITE_ONLY, GL_RGBA16F);
    gl::dispatch(prog, hdr.width(), hdr.height());
}

std::unique_ptr<Pass> makeComposePass() { return std::make_unique<ComposePass>(); }

}  // namespace rtgi
