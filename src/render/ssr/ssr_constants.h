#pragma once
// Settings -> GPU constants of the SSR family (one pure function, unit-tested
// without GL; XeGTAO's GTAOUpdateConstants pattern).
#include "render/gpu_types.h"
#include "render/settings.h"

#include "compute/lib/ssr_shared.h"

namespace rtgi {
namespace gpu {
static_assert(sizeof(SsrUniforms) == 3 * 16, "SsrUniforms must match std140 layout");
}

// Constants where SPEC and seed are silent (docs/ssr.md). The blur itself
// (sigma 2, radius 4 trace pixels) is the shared chain's (render/filter.h).
struct SsrFilterConstants {
    static constexpr float kDepthThreshold = 0.1f;   // relative depth difference that stops the blur
    static constexpr float kNormalThreshold = 0.9f;  // cosine between normals that stops the blur
    static constexpr float kEdgeFade = 0.1f;         // uv width of the screen-edge confidence fade
};

// Trace resolution for a full-resolution frame: half rounds up so every
// full-resolution pixel has a trace pixel within one texel.
glm::ivec2 ssrTraceSize(glm::ivec2 full, bool half);
// Levels of the min-depth pyramid over a w x h depth buffer (down to 1x1).
int hizLevelCount(glm::ivec2 full);
// Size of pyramid level `level` (each level halves, rounding down, at least 1).
glm::ivec2 hizLevelSize(glm::ivec2 full, int level);
// The SsrUniforms block for these settings, tracer (not Auto/Off) and frame.
gpu::SsrUniforms makeSsrUniforms(const SsrSettings& s, SsrSettings::Tracer tracer, glm::ivec2 full);
// The RTGI_SSR_* id of a tracer (throws for Auto/Off: they never reach the GPU).
int ssrTracerId(SsrSettings::Tracer t);

}  // namespace rtgi
