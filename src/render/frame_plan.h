#pragma once
// The frame built from the passes' declarations (Filament's frame graph in
// miniature): which passes run and why the others do not, the execution
// order checked against what each pass reads, and for every accumulate
// whether it adds to an earlier writer or is the first writer.
#include "render/pass.h"

#include <bitset>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rtgi {

// A family of passes (name prefix "ao.", "lpv.", ...): one decision whether
// it runs; a pass adds only its own condition in declare().
struct Family {
    std::string prefix;  // "lpv."
    std::string key;     // the setting that asks for it ("lpv"), named in errors
    std::function<Need(const Scene&, const Settings&)> runs;
    // Explicitly asked for: must run, or the frame build says why not.
    std::function<bool(const Settings&)> requested;
    // Throws ConfigError for an impossible combination of settings (optional; called when the family runs).
    std::function<void(const Scene&, const Settings&)> validate;
};

struct SkippedPass {
    std::string name;
    std::string reason;
};

class FramePlan {
public:
    // Prunes and checks `script` (in execution order) for scene + settings.
    // Throws ConfigError, naming the pass and the resource, when a pass reads
    // what no earlier pass of the frame writes, or writes what an earlier one
    // already wrote; and when passes.off names no pass.
    static FramePlan build(std::vector<std::unique_ptr<Pass>> script, const std::vector<Family>& families,
                           const Scene& scene, const Settings& settings);

    const std::vector<std::unique_ptr<Pass>>& passes() const { return passes_; }
    const PassDecl& decl(int i) const { return decls_[std::size_t(i)]; }
    const std::vector<SkippedPass>& skipped() const { return skipped_; }
    // Resource r was written by a pass before pass i.
    bool writtenBefore(int i, Resource r) const { return before_[std::size_t(i)][std::size_t(r.index)]; }
    // Some pass of the frame writes r.
    bool written(Resource r) const { return all_[std::size_t(r.index)]; }
    // The frame as a table: pass, reads, writes; then the skipped passes with why (--print-frame).
    std::string table() const;

private:
    std::vector<std::unique_ptr<Pass>> passes_;
    std::vector<PassDecl> decls_;
    std::vector<std::bitset<R::count>> before_;
    std::bitset<R::count> all_;
    std::vector<SkippedPass> skipped_;
};

}  // namespace rtgi
