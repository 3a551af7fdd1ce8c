#pragma once
// Stage attribution of the LPV (issue 12, docs/lpv.md "Stage attribution"):
// lpv.source=probe fills every cascade's accumulated volume with path-traced
// light at its cell centres (compute/lpv/probe.comp, the reference's BVH and
// transport), so the same lpv.apply shows the error of the lookup alone;
// the run with the propagated volumes minus it shows the propagation's.
#include "gl/program.h"
#include "gl/resources.h"
#include "gl/image_io.h"
#include "render/lpv/lpv_volumes.h"
#include "render/pass.h"

namespace rtgi {
class Renderer;
struct View;
}

namespace rtgi::lpv {

// What probe.comp traces per cell.
struct ProbeParams {
    int directions = 256;       // lpv.probe_directions
    int bounces = 1;            // the matching-bounce reference's: 1, 2 with lpv.bounce=on
    unsigned seed = 1;          // reference.seed
};
ProbeParams probeParams(const Settings& settings);

// The scene's BVH on the GPU (bvh_shared.h layout), built on first use and rebuilt when
// the geometry moved (GpuScene::geometryVersion, issue 23); bind() binds it and the
// scene's vertex / index buffers at their bvh_shared.h bindings.
struct SceneBvh {
    gl::Buffer nodes, triangles;
    std::uint64_t geometryVersion = 0;  // of the scene it was built from
    void ensure(FrameContext& ctx, const std::string& label);
    void bind(FrameContext& ctx) const;
};

// Owns the BVH buffers (built from the scene on first use).
class ProbeTracer {
public:
    // Overwrites v.accum of the cascade whose uniform block is `ubo` with the
    // probe volume, and v.near too when `near` (cascades i > 0: with near =
    // total, lpv.apply's weights blend the cascades' probes, docs/lpv.md).
    // The frame uniforms must be bound.
    void fill(FrameContext& ctx, const gl::Buffer& ubo, Volumes& v, bool near);

private:
    SceneBvh bvh_;
};

// lpv.lookup=visibility (docs/lpv.md, "Visibility moments"): per-cell distance moments of
// the cascade whose uniform block is `ubo` (lpv/visibility.comp) into v.visibility
// (v.ensureVisibility first).
void visibilityMoments(FrameContext& ctx, const gl::Buffer& ubo, const SceneBvh& bvh, Volumes& v);
// lpv.sky=visibility (docs/lpv.md, "Sky visibility"): band-1 SH of each cell's sky visibility
// into v.sky (v.ensureSky first).
void skyVisibility(FrameContext& ctx, const gl::Buffer& ubo, const SceneBvh& bvh, Volumes& v);
// lpv.blocking=visibility (docs/lpv.md, "Face openness"): per cell the open fraction of the slab
// to its +x, +y, +z neighbour's centre into v.faces (v.ensureFaces first).
void faceVisibility(FrameContext& ctx, const gl::Buffer& ubo, const SceneBvh& bvh, Volumes& v);

// --reference: the run's indirect light again with lpv.source=probe (the same
// scene, settings and view, no reference pass).
FloatImage renderProbeIndirect(const Renderer& run, const View& view);

}  // namespace rtgi::lpv
