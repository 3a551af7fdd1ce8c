// brdf_lut: the split-sum BRDF table (seed 000 3.6.2, [Kar13]; SPEC 3.6)
// shared by ssr.shade and lpv.apply. Computed once per configuration (the
// renderer releases resources on configure); later frames skip the dispatch.
#include "gl/program.h"
#include "compute/lib/post_shared.h"
#include "render/lpv/lpv_passes.h"
#include "render/passes/core_passes.h"
#include "render/ssr/ssr_passes.h"

namespace rtgi {
namespace {

class BrdfLutPass final : public Pass {
public:
    std::string name() const override { return "brdf_lut"; }
    Need needed(const Scene& scene, const Settings& s) const override {
        if (effectiveSsrTracer(scene, s) != SsrSettings::Tracer::Off || lpvSpecularActive(scene, s))
            return Need::yes();
        return Need::no("neither SSR nor LPV specular runs");
    }
    std::vector<std::string> writes() const override { return {"brdfLut"}; }
    void execute(FrameContext& ctx) override {
        if (ctx.res.brdfLut) return;
        ctx.res.brdfLut.ensure(ctx.ledger, "brdf_lut", {GL_TEXTURE_2D, GL_RG16F, kBrdfLutSize, kBrdfLutSize});
        ctx.res.brdfLut.setSampling(GL_LINEAR, GL_LINEAR);
        const gl::Program& prog = ctx.programs.compute("post/brdf_lut.comp");
        prog.set(RTGI_POST_LOC_SAMPLES, kBrdfLutSamples);
        glBindImageTexture(RTGI_POST_IMG_LUT, ctx.res.brdfLut.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG16F);
        gl::dispatch(prog, kBrdfLutSize, kBrdfLutSize);
    }
    std::vector<Output> checkedOutputs(const FrameResources& res) const override {
        return {{"brdf_lut:brdfLut", &res.brdfLut}};
    }
};

}  // namespace

std::unique_ptr<Pass> makeBrdfLutPass() { return std::make_unique<BrdfLutPass>(); }

}  // namespace rtgi
