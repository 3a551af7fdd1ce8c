#pragma once
// A pass: a small unit that declares once, for a scene + settings, what it
// reads, writes and accumulates into (declare), and runs one execute().
// From the declarations the renderer builds the frame (render/frame_plan.h):
// it drops passes that do not run (with the reason), checks the order,
// allocates the shared resources, decides whether an accumulate adds or
// overwrites, and derives the --check outputs and the debug images.
#include "render/frame_resources.h"
#include "render/settings.h"
#include "render/view.h"

#include <functional>
#include <string>
#include <vector>

namespace rtgi {
namespace gl {
class ProgramCache;
class Profiler;
class MemoryLedger;
}  // namespace gl
class GpuScene;
class FramePlan;

// Whether something runs, and why not (results.json "skipped").
struct Need {
    bool needed = true;
    std::string reason;
    static Need yes() { return {true, {}}; }
    static Need no(std::string why) { return {false, std::move(why)}; }
};

// A texture a pass exposes for inspection (--out images, rtgi-view).
struct DebugImage {
    std::string name;        // file stem, e.g. "lpv.rsm.flux"
    const gl::Texture* tex;  // 2D texture (or a slice view made by the pass)
    float scale = 1.0f;      // display multiplier for PNG output
};

// One pass's declaration (filled by Pass::declare).
class PassDecl {
public:
    enum class Access {
        read,           // written by an earlier pass of this frame (else: error at frame build)
        readIfWritten,  // optional input: ctx.has(r) says whether an earlier pass wrote it
        readPrevious,   // the value of the previous frame (reprojection): some pass of the frame writes it
        write,          // the pass's value replaces the resource (one writer per frame)
        accumulate      // adds to an earlier writer's value; the first writer of the frame overwrites
    };
    struct Use {
        Resource resource;
        Access access;
    };
    using TextureFn = std::function<const gl::Texture*()>;
    struct PrivateOutput {
        std::string name;
        TextureFn tex;
        Check check;
    };
    struct Debug {
        std::string name;
        std::function<DebugImage()> make;  // may dispatch (slices); called outside the measured frame
    };

    PassDecl& read(Resource r) { return use(r, Access::read); }
    PassDecl& readIfWritten(Resource r) { return use(r, Access::readIfWritten); }
    PassDecl& readPrevious(Resource r) { return use(r, Access::readPrevious); }
    PassDecl& write(Resource r) { return use(r, Access::write); }
    PassDecl& accumulate(Resource r) { return use(r, Access::accumulate); }
    // A texture the pass owns, counted by --check after the pass (empty textures are ignored).
    PassDecl& output(std::string name, const gl::Texture* tex, Check check = Check::nonNegative);
    PassDecl& output(std::string name, TextureFn tex, Check check = Check::nonNegative);
    // A private texture shown as a debug image (written by --out, listed by rtgi-view).
    PassDecl& debugImage(std::string name, const gl::Texture* tex, float scale = 1.0f);
    PassDecl& debugImage(std::string name, std::function<DebugImage()> make);
    // The pass does not run in this configuration.
    void skip(std::string why) { skipped_ = std::move(why); }
    // Runs only while a pass of the frame reads (or reads the previous frame's) one of its writes.
    void onlyIfRead() { onlyIfRead_ = true; }

    const std::vector<Use>& uses() const { return uses_; }
    const std::vector<PrivateOutput>& outputs() const { return outputs_; }
    const std::vector<Debug>& debugImages() const { return debug_; }
    bool skipped() const { return !skipped_.empty(); }
    const std::string& skipReason() const { return skipped_; }
    bool isOnlyIfRead() const { return onlyIfRead_; }
    bool uses(Resource r, Access a) const;
    bool writes(Resource r) const { return uses(r, Access::write) || uses(r, Access::accumulate); }

private:
    PassDecl& use(Resource r, Access a) {
        uses_.push_back({r, a});
        return *this;
    }
    std::vector<Use> uses_;
    std::vector<PrivateOutput> outputs_;
    std::vector<Debug> debug_;
    std::string skipped_;
    bool onlyIfRead_ = false;
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
    const FramePlan* plan = nullptr;
    int passIndex = 0;                   // the executing pass's index in plan
    const bool* previousValid = nullptr; // per resource: holds the previous frame's value

    // An earlier pass of this frame wrote r (for readIfWritten inputs).
    bool has(Resource r) const;
    // This pass's accumulate into r adds to an earlier writer's value (else it overwrites).
    bool accumulates(Resource r) const;
    // r holds the previous frame's value (not on the first frame, after a cut or a reallocation).
    bool hasPrevious(Resource r) const { return previousValid && previousValid[r.index]; }
};

class Pass {
public:
    virtual ~Pass() = default;
    // Family-prefixed name as it appears in results ("lpv.inject").
    virtual std::string name() const = 0;
    // The one declaration of what the pass uses for this scene + settings, or d.skip(why).
    virtual void declare(PassDecl& d, const Scene& scene, const Settings& settings) const = 0;
    virtual void execute(FrameContext& ctx) = 0;
    // Values a pass wants in results.json under "stats" (counters, e.g.
    // texels dropped outside the LPV). Read back once after measuring.
    virtual std::vector<std::pair<std::string, double>> stats() { return {}; }
    // The private textures execute() allocates for a view of `viewSize`, by
    // ledger label, from the descriptors execute() allocates from (not the
    // shared resources): the memory estimate sums them over the frame's
    // passes. A texture several passes use is listed by one of them.
    virtual std::vector<gl::NamedTextureDesc> privateTextures(const Settings&, glm::ivec2 /*viewSize*/) const { return {}; }
};

}  // namespace rtgi
