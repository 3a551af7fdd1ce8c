// The frame script: every candidate pass, in execution order, and the
// families that decide whether their passes run. What each pass reads and
// writes is in its declare(); the renderer builds the frame from those
// declarations (render/frame_plan.h) and lists the passes that do not run,
// with the reason, under "skipped" (rtgi-bench --print-frame shows it).
#include "render/ao/ao_passes.h"
#include "render/lpv/lpv_passes.h"
#include "render/passes/core_passes.h"
#include "render/reference/reference_passes.h"
#include "render/renderer.h"
#include "render/ssr/ssr_passes.h"
#include "render/visibility/visibility_passes.h"

namespace rtgi {
namespace {

// post.history: keeps this frame's radiance for the next frame's
// reprojecting passes. In the frame only while one of them declares
// readPrevious(R::history) (near-field light; SSR without its own history).
// The image is written by post.compose (RTGI_COMPOSE_HISTORY: the radiance it
// computes, the linear depth in alpha for the readers' disocclusion test), which
// saves a full-resolution copy; this pass keeps the declaration, so the plan
// keeps or drops the history (and its allocation) with its readers.
class HistoryPass final : public Pass {
public:
    std::string name() const override { return "post.history"; }
    void declare(PassDecl& d, const Scene&, const Settings&) const override {
        d.read(R::hdr).read(R::linearDepth).write(R::history).onlyIfRead();
    }
    void execute(FrameContext&) override {}
};

}  // namespace

std::vector<std::unique_ptr<Pass>> frameScript() {
    std::vector<std::unique_ptr<Pass>> f;
    f.push_back(makeGBufferPass());  // rasterize depth, normals, albedo, material, emission, velocity
    appendVisibilityPasses(f);       // raster.path=compute: visibility.raster -> visibility.resolve (the same G-buffer)
    f.push_back(makeShadowPass());   // sun shadow map (rasterized)
    f.push_back(makeLocalShadowPass());  // spot / point / area-light shadow maps
    f.push_back(makeShadowRasterPass());  // raster.path=compute: the same shadow map from the compute rasterizer
    f.push_back(makeDirectPass());   // direct sun + punctual lights + emission (compute)
    f.push_back(makeBrdfLutPass());  // split-sum BRDF table, once, while SSR or LPV specular reads it
    appendAoPasses(f);               // ao.<variant> -> blur -> temporal -> upsample (+ bent normals / S3HO)
    appendLpvPasses(f);              // lpv.rsm -> inject -> inject_geometry -> propagate xN -> apply
    appendNearFieldPasses(f);        // ao.nearfield accumulates reprojected near-field light into indirectDiffuse
    appendSsrPasses(f);              // ssr.hiz -> trace -> resolve -> filter -> shade (accumulates into specular)
    f.push_back(makeComposePass());  // hdr = direct + ambient + indirect + specular; tonemap -> ldr
    f.push_back(std::make_unique<HistoryPass>());  // this frame's radiance for the next frame's reprojection
    appendReferencePasses(f);        // ref.* (reference != off)
    return f;
}

std::vector<Family> frameFamilies() {
    return {
        {"ao.", "ao", aoFamily, [](const Settings& s) { return s.ao.variant != AoSettings::Variant::Off; },
         validateAoSettings},
        {"lpv.", "lpv", lpvFamily, [](const Settings& s) { return s.lpv.mode == Toggle::On; }, validateLpvSettings},
        {"ssr.", "ssr", ssrFamily,
         [](const Settings& s) {
             return s.ssr.tracer != SsrSettings::Tracer::Auto && s.ssr.tracer != SsrSettings::Tracer::Off;
         },
         nullptr},
        {"ref.", "reference", referenceFamily,
         [](const Settings& s) { return s.reference.kind != ReferenceSettings::Kind::Off; }, nullptr},
    };
}

}  // namespace rtgi
