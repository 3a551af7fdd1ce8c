// The frame script: every candidate pass, in execution order. A pass that
// the scene + settings do not need is dropped by the Renderer (and listed
// under "skipped" with its reason) before anything is allocated.
#include "gl/program.h"
#include "compute/lib/post_shared.h"
#include "render/ao/ao_passes.h"
#include "render/lpv/lpv_passes.h"
#include "render/passes/core_passes.h"
#include "render/reference/reference_passes.h"
#include "render/renderer.h"
#include "render/ssr/ssr_passes.h"
#include "render/visibility/visibility_passes.h"

namespace rtgi {
namespace {

// post.history: keeps the previous frame's radiance for the passes that
// reproject it (near-field light, SSR). Only in the frame when one of them is.
class HistoryPass final : public Pass {
public:
    std::string name() const override { return "post.history"; }
    Need needed(const Scene& scene, const Settings& s) const override {
        // Why each reader does not read it (empty: it does).
        std::string nearfield = s.ao.variant == AoSettings::Variant::Off ? "ao=off"
                                : !(s.ao.nearfield > 0.0f)               ? "ao.nearfield=0"
                                                                         : "";
        std::string ssr = s.ssr.tracer == SsrSettings::Tracer::Off ? "ssr=off"
                          : effectiveSsrTracer(scene, s) == SsrSettings::Tracer::Off
                              ? "SSR skipped (no glossy material)"
                          : s.ssr.diffuseHistory ? "SSR reads its own diffuse-only history (ssr.diffuse_history=on)"
                                                 : "";
        if (nearfield.empty() || ssr.empty()) return Need::yes();
        return Need::no("no pass reads the previous frame: near-field light off (" + nearfield + "), " + ssr);
    }
    std::vector<std::string> reads() const override { return {"hdr"}; }
    std::vector<std::string> writes() const override { return {"history"}; }
    void execute(FrameContext& ctx) override {
        const glm::ivec2 s = ctx.view.size;
        ctx.res.history.ensure(ctx.ledger, "post.history", {GL_TEXTURE_2D, GL_RGBA16F, s.x, s.y});
        ctx.res.history.setSampling(GL_LINEAR, GL_LINEAR);
        const gl::Program& prog = ctx.programs.compute("post/copy.comp");
        // Producer: post.compose (image store into hdr).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glBindTextureUnit(RTGI_POST_TEX_SOURCE, ctx.res.hdr.id());
        glBindImageTexture(RTGI_POST_IMG_TARGET, ctx.res.history.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        gl::dispatch(prog, s.x, s.y);
        ctx.res.historyValid = true;
    }
};

}  // namespace

std::vector<std::unique_ptr<Pass>> frameScript() {
    std::vector<std::unique_ptr<Pass>> f;
    f.push_back(makeGBufferPass());  // rasterize depth, normals, albedo, material, emission, velocity
    appendVisibilityPasses(f);       // raster.path=compute: visibility.raster -> visibility.resolve (the same G-buffer)
    f.push_back(makeShadowPass());   // sun shadow map (rasterized)
    f.push_back(makeShadowRasterPass());  // raster.path=compute: the same shadow map from the compute rasterizer
    f.push_back(makeDirectPass());   // direct sun + punctual lights + emission (compute)
    f.push_back(makeBrdfLutPass());  // split-sum BRDF table, once (SSR / LPV specular)
    appendAoPasses(f);               // ao.<variant> -> blur -> temporal -> upsample (+ bent normals / S3HO)
    appendLpvPasses(f);              // lpv.rsm -> inject -> inject_geometry -> propagate xN -> apply
    appendNearFieldPasses(f);        // ao.nearfield adds reprojected near-field light to the indirect term
    appendSsrPasses(f);              // ssr.hiz -> trace -> resolve -> filter -> shade
    f.push_back(makeComposePass());  // hdr = direct + ambient + indirect + specular; tonemap -> ldr
    f.push_back(std::make_unique<HistoryPass>());  // previous frame for reprojection
    appendReferencePasses(f);        // ref.* (reference != off)
    return f;
}

}  // namespace rtgi
