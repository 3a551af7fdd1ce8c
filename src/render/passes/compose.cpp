// post.compose: direct + sky ambient·AO + indirect + specular, tonemapped.
#include "gl/program.h"
#include "render/passes/core_passes.h"

namespace rtgi {
namespace {

class ComposePass final : public Pass {
public:
    std::string name() const override { return "post.compose"; }
    Need needed(const Scene&, const Settings&) const override { return Need::yes(); }
    std::vector<std::string> reads() const override { return {"direct", "gbuffer.albedo", "gbuffer.material"}; }
    std::vector<std::string> writes() const override { return {"hdr", "ldr"}; }

    void execute(FrameContext& ctx) override {
        const glm::ivec2 s = ctx.view.size;
        FrameResources& r = ctx.res;
        r.hdr.ensure(ctx.ledger, "post.hdr", {GL_TEXTURE_2D, GL_RGBA32F, s.x, s.y});
        r.ldr.ensure(ctx.ledger, "post.ldr", {GL_TEXTURE_2D, GL_RGBA8, s.x, s.y});
        const gl::Program& prog = ctx.programs.compute("post/compose.comp");
        // Producers: direct, ao.*, lpv.apply, ssr.* (all image stores).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        glBindTextureUnit(0, r.direct.id());
        glBindTextureUnit(1, r.gbuffer.albedo.id());
        glBindTextureUnit(2, r.gbuffer.material.id());
        glBindTextureUnit(3, r.indirectDiffuse ? r.indirectDiffuse.id() : 0);
        glBindTextureUnit(4, r.specular ? r.specular.id() : 0);
        glBindTextureUnit(5, r.ao ? r.ao.id() : 0);
        bool aoInLpv = ctx.settings.ao.directional != AoSettings::Directional::Off && bool(r.indirectDiffuse) &&
                       bool(r.bentNormal.id() || r.s3ho.id());
        prog.set(0, glm::ivec4(bool(r.indirectDiffuse), bool(r.specular), bool(r.ao), aoInLpv));
        glBindImageTexture(0, r.hdr.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glBindImageTexture(1, r.ldr.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
        gl::dispatch(prog, s.x, s.y);
        for (int u = 3; u <= 5; ++u) glBindTextureUnit(GLuint(u), 0);
    }
};

}  // namespace

std::unique_ptr<Pass> makeComposePass() { return std::make_unique<ComposePass>(); }

}  // namespace rtgi
