#include "render/filter.h"

namespace rtgi {

namespace {
gl::Defines formatDefines(const FilterFormat& fmt) { return {{"FILTER_FORMAT", fmt.glsl}}; }
}  // namespace

void separableBlur(gl::ProgramCache& programs, gl::MemoryLedger& ledger, const std::string& label,
                   const FilterFormat& fmt, const gl::Texture& in, const gl::Texture& depth,
                   const gl::Texture& normal, gl::Texture& tmp, gl::Texture& out, BlurThresholds t) {
    const int w = in.width(), h = in.height();
    tmp.ensure(ledger, label + ".tmp", {GL_TEXTURE_2D, fmt.internal, w, h});
    out.ensure(ledger, label, {GL_TEXTURE_2D, fmt.internal, w, h});
    const gl::Program& prog = programs.compute("filter/blur.comp", formatDefines(fmt));
    prog.set(1, t.depth);
    prog.set(2, t.normal);
    glBindTextureUnit(1, depth.id());
    glBindTextureUnit(2, normal.id());
    const gl::Texture* src[2] = {&in, &tmp};
    gl::Texture* dst[2] = {&tmp, &out};
    for (int pass = 0; pass < 2; ++pass) {
        // Producer: the previous pass / dispatch wrote src with image stores.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        prog.set(0, pass == 0 ? glm::ivec2(1, 0) : glm::ivec2(0, 1));
        glBindTextureUnit(0, src[pass]->id());
        glBindImageTexture(0, dst[pass]->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, fmt.internal);
        gl::dispatch(prog, w, h);
    }
}

const gl::Texture& TemporalFilter::run(gl::ProgramCache& programs, gl::MemoryLedger& ledger,
                                       const std::string& label, const FilterFormat& fmt,
                                       const gl::Texture& current, const gl::Texture& depth,
                                       const gl::Texture& velocity, bool reset) {
    const int w = current.width(), h = current.height();
    bool fresh = false;
    for (int i = 0; i < 2; ++i) {
        std::string n = label + (i == 0 ? ".a" : ".b");
        fresh |= value_[i].ensure(ledger, n, {GL_TEXTURE_2D, fmt.internal, w, h});
        fresh |= depth_[i].ensure(ledger, n + ".depth", {GL_TEXTURE_2D, GL_R32F, w, h});
        value_[i].setSampling(GL_LINEAR, GL_LINEAR);
        depth_[i].setSampling(GL_LINEAR, GL_LINEAR);
    }
    if (fresh) valid_ = false;
    const int prev = cur_, next = 1 - cur_;
    const gl::Program& prog = programs.compute("filter/temporal.comp", formatDefines(fmt));
    // Producer: the value pass before (image stores) and last frame's run.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindTextureUnit(0, current.id());
    glBindTextureUnit(1, value_[prev].id());
    glBindTextureUnit(2, depth.id());
    glBindTextureUnit(3, depth_[prev].id());
    glBindTextureUnit(4, velocity.id());
    prog.set(0, (reset || !valid_) ? 1 : 0);
    glBindImageTexture(0, value_[next].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, fmt.internal);
    glBindImageTexture(1, depth_[next].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    gl::dispatch(prog, w, h);
    cur_ = next;
    valid_ = true;
    return value_[cur_];
}

void upsample(gl::ProgramCache& programs, gl::MemoryLedger& ledger, const std::string& label,
              const FilterFormat& fmt, const gl::Texture& low, const gl::Texture& lowDepth,
              const gl::Texture& fullDepth, gl::Texture& out, bool depthAware) {
    out.ensure(ledger, label, {GL_TEXTURE_2D, fmt.internal, fullDepth.width(), fullDepth.height()});
    gl::Defines defs = formatDefines(fmt);
    defs.push_back({"UPSAMPLE_DEPTH_AWARE", depthAware ? "1" : "0"});
    const gl::Program& prog = programs.compute("filter/upsample.comp", defs);
    // Producer: the low-resolution pass before (image stores).
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    low.setSampling(GL_LINEAR, GL_LINEAR);
    glBindTextureUnit(0, low.id());
    glBindTextureUnit(1, lowDepth.id());
    glBindTextureUnit(2, fullDepth.id());
    glBindImageTexture(0, out.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, fmt.internal);
    gl::dispatch(prog, out.width(), out.height());
}

}  // namespace rtgi
