#pragma once
// A pass: small unit with declared inputs/outputs, a decision whether the
// scene + settings need it (with the reason when not), and one execute().
// GPU resources are created inside execute() (ensure), so a pass that is
// not in the frame allocates nothing.
#include "render/frame_resources.h"
#include "render/settings.h"
#include "render/view.h"

#include <string>
#include <vector>

namespace rtgi {
namespace gl {
class ProgramCache;
class Profiler;
class MemoryLedger;
}  // namespace gl
class GpuScene;

struct Need {
    bool needed = true;
    std::string reason;  // why not (results.json "skipped")
    static Need yes() { return {true, {}}; }
    static Need no(std::string why) { return {false, std::move(why)}; }
};

// Everything a pass may use while executing.
struct FrameContext {
    gl::ProgramCache& programs;
    gl::MemoryLedger& ledger;
    gl::Profiler& profiler;
    const Scene& scene;
    const GpuScene& gpuScene;
    const Settings& settings;
    FrameResources& res;
    const View& view;
    GLuint frameUbo = 0;  // FrameUniforms, bound at RTGI_UBO_FRAME before every pass
};

class Pass {
public:
    virtual ~Pass() = default;
    // Family-prefixed name as it appears in results ("lpv.inject").
    virtual std::string name() const = 0;
    virtual Need needed(const Scene& scene, const Settings& settings) const = 0;
    // Names of FrameResources fields read / written (checked for order).
    virtual std::vector<std::string> reads() const { return {}; }
    virtual std::vector<std::string> writes() const { return {}; }
    virtual void execute(FrameContext& ctx) = 0;
    // Extra images a pass writes for inspection (debug views): written by
    // rtgi-bench into --out and shown by rtgi-view. Default: none.
    struct DebugImage {
        std::string name;        // file stem, e.g. "lpv.rsm.flux"
        const gl::Texture* tex;  // 2D texture (or a slice view made by the pass)
        float scale = 1.0f;      // display multiplier for PNG output
    };
    virtual std::vector<DebugImage> debugImages() const { return {}; }
    // Values a pass wants in results.json under "stats" (counters, e.g.
    // texels dropped outside the LPV). Read back once after measuring.
    virtual std::vector<std::pair<std::string, double>> stats() { return {}; }
    // Outputs checked by --check (NaN/Inf/negative/fp16 saturation). The
    // default resolves writes() through FrameResources; passes with private
    // outputs (volumes, half-resolution targets) add them here.
    struct Output {
        std::string name;
        const gl::Texture* tex;
        bool mayBeNegative = false;  // SH coefficients, velocities, normals
    };
    virtual std::vector<Output> checkedOutputs(const FrameResources& res) const;
};

}  // namespace rtgi
