// brdf_lut: the split-sum BRDF table (seed 000 3.6.2, [Kar13]; SPEC 3.6)
// shared by ssr.shade and lpv.apply. Computed once per configuration (the
// renderer releases resources on configure); later frames skip the dispatch.
#include "gl/program.h"
#include "compute/lib/post_shared.h"
#include "render/passes/core_passes.h"

namespace rtgi {
namespace {

class BrdfLutPass final : public Pass {
public:
    std::string name() const override { return "brdf_lut"; }
    // In the frame while ssr.shade or lpv.apply (specular) reads the table.
    void declare(PassDecl& d, const Scene&, const Settings&) const override { d.write(R::brdfLut).onlyIfRead(); }
    void execute(FrameContext& ctx) override {
        if (madeFor_ == ctx.res.allocationEpoch && made_) return;  // the table does not change
        made_ = true;
        madeFor_ = ctx.res.allocationEpoch;
        const gl::Program& prog = ctx.programs.compute("post/brdf_lut.comp");
        prog.set(RTGI_POST_LOC_SAMPLES, kBrdfLutSamples);
        glBindImageTexture(RTGI_POST_IMG_LUT, ctx.res.brdfLut.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG16F);
        gl::dispatch(prog, kBrdfLutSize, kBrdfLutSize);
    }

private:
    bool made_ = false;
    unsigned madeFor_ = 0;  // FrameResources::allocationEpoch the table was made in
};

}  // namespace

std::unique_ptr<Pass> makeBrdfLutPass() { return std::make_unique<BrdfLutPass>(); }

}  // namespace rtgi
