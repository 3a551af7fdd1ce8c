#pragma once
// Which reference a frame's output is compared with (rtgi-bench --reference,
// sweeps, rtgi-view's live comparison).
#include "render/frame_resources.h"
#include "render/settings.h"

namespace rtgi {

// res.ao with ray-traced AO (the run has an AO variant), res.indirectDiffuse
// with path-traced indirect light (an indirect technique wrote it), else
// res.hdr with the full path-traced image. An explicit `reference=KIND` in
// the settings wins.
ReferenceSettings::Kind referenceKindFor(const Settings& settings, const FrameResources& res);
// The texture of `res` compared with a reference of `kind`.
const gl::Texture& comparedTexture(ReferenceSettings::Kind kind, const FrameResources& res);
// The settings of the reference renderer for `run`: the same scene, camera
// and lights, the real-time techniques off (they would only cost time).
Settings referenceRunSettings(const Settings& run, ReferenceSettings::Kind kind);

}  // namespace rtgi
