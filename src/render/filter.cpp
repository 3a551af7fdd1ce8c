#include "render/filter.h"

#include "compute/lib/filter_shared.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rtgi {

namespace {
gl::Defines formatDefines(const FilterFormat& fmt) { return {{"FILTER_FORMAT", fmt.glsl}}; }
gl::TextureDesc valueDesc(const FilterFormat& fmt, glm::ivec2 size) { return {GL_TEXTURE_2D, fmt.internal, size.x, size.y}; }
}  // namespace

std::vector<gl::NamedTextureDesc> blurTextures(const std::string& label, const FilterFormat& fmt, glm::ivec2 size) {
    return {{label + ".tmp", valueDesc(fmt, size)}, {label, valueDesc(fmt, size)}};
}

std::vector<gl::NamedTextureDesc> temporalTextures(const std::string& label, const FilterFormat& fmt, glm::ivec2 size) {
    std::vector<gl::NamedTextureDesc> t;
    for (const char* ab : {".a", ".b"}) {
        t.push_back({label + ab, valueDesc(fmt, size)});
        t.push_back({label + ab + ".depth", {GL_TEXTURE_2D, GL_R32F, size.x, size.y}});
    }
    return t;
}

gl::NamedTextureDesc upsampleTexture(const std::string& label, const FilterFormat& fmt, glm::ivec2 fullSize) {
    return {label, valueDesc(fmt, fullSize)};
}

void separableBlur(gl::ProgramCache& programs, gl::MemoryLedger& ledger, const std::string& label,
                   const FilterFormat& fmt, const gl::Texture& in, const gl::Texture& depth,
                   const gl::Texture& normal, gl::Texture& tmp, gl::Texture& out, BlurThresholds t) {
    const int w = in.width(), h = in.height();
    const auto own = blurTextures(label, fmt, {w, h});
    tmp.ensure(ledger, own[0].label, own[0].desc);
    out.ensure(ledger, own[1].label, own[1].desc);
    const gl::Program& prog = programs.compute("filter/blur.comp", formatDefines(fmt));
    prog.set(RTGI_FILTER_LOC_DEPTH_THRESHOLD, t.depth);
    prog.set(RTGI_FILTER_LOC_NORMAL_THRESHOLD, t.normal);
    glBindTextureUnit(RTGI_FILTER_BLUR_TEX_DEPTH, depth.id());
    glBindTextureUnit(RTGI_FILTER_TEX_NORMAL, normal.id());
    const gl::Texture* src[2] = {&in, &tmp};
    gl::Texture* dst[2] = {&tmp, &out};
    for (int pass = 0; pass < 2; ++pass) {
        // Producer: the previous pass / dispatch wrote src with image stores.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        prog.set(RTGI_FILTER_LOC_DIRECTION, pass == 0 ? glm::ivec2(1, 0) : glm::ivec2(0, 1));
        glBindTextureUnit(RTGI_FILTER_TEX_VALUE, src[pass]->id());
        glBindImageTexture(RTGI_FILTER_IMG_OUT, dst[pass]->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, fmt.internal);
        gl::dispatch(prog, w, h);
    }
}

TemporalCamera temporalCamera(const View& view) {
    TemporalCamera c;
    c.curToPrevView = view.prevView * glm::inverse(view.view);
    const float t = std::tan(0.5f * view.fovY);
    c.projScale = {t * float(view.size.x) / float(std::max(view.size.y, 1)), t};
    return c;
}

std::uint32_t TemporalFilter::disoccludedPixels() const {
    if (lastCount_ < 0) return 0;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // producer: the last run's atomics
    std::uint32_t n = 0;
    counts_[lastCount_].download(&n, sizeof(n));
    return n;
}

const gl::Texture& TemporalFilter::run(gl::ProgramCache& programs, gl::MemoryLedger& ledger,
                                       const std::string& label, const FilterFormat& fmt,
                                       const gl::Texture& current, const gl::Texture& depth,
                                       const gl::Texture& velocity, bool reset, const TemporalCamera& camera) {
    const int w = current.width(), h = current.height();
    bool fresh = false;
    const auto t = temporalTextures(label, fmt, {w, h});
    for (int i = 0; i < 2; ++i) {
        fresh |= value_[i].ensure(ledger, t[std::size_t(2 * i)].label, t[std::size_t(2 * i)].desc);
        fresh |= depth_[i].ensure(ledger, t[std::size_t(2 * i + 1)].label, t[std::size_t(2 * i + 1)].desc);
        value_[i].setSampling(GL_LINEAR, GL_LINEAR);
        depth_[i].setSampling(GL_LINEAR, GL_LINEAR);
    }
    if (fresh) valid_ = false;
    const int prev = cur_, next = 1 - cur_;
    const gl::Program& prog = programs.compute("filter/temporal.comp", formatDefines(fmt));
    // Producer: the value pass before (image stores) and last frame's run.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindTextureUnit(RTGI_FILTER_TEX_CURRENT, current.id());
    glBindTextureUnit(RTGI_FILTER_TEX_HISTORY, value_[prev].id());
    glBindTextureUnit(RTGI_FILTER_TEMPORAL_TEX_DEPTH, depth.id());
    glBindTextureUnit(RTGI_FILTER_TEX_HISTORY_DEPTH, depth_[prev].id());
    glBindTextureUnit(RTGI_FILTER_TEX_VELOCITY, velocity.id());
    prog.set(RTGI_FILTER_LOC_RESET, (reset || !valid_) ? 1 : 0);
    prog.set(RTGI_FILTER_LOC_CUR_TO_PREV_VIEW, camera.curToPrevView);
    prog.set(RTGI_FILTER_LOC_PROJ_SCALE, camera.projScale);
    lastCount_ = (lastCount_ + 1) % kCountBuffers;
    gl::Buffer& count = counts_[lastCount_];
    if (!count) count = gl::Buffer(ledger, label + ".disoccluded", sizeof(std::uint32_t));
    count.clearZero();
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_FILTER_SSBO_COUNTS, count.id());
    glBindImageTexture(RTGI_FILTER_IMG_OUT, value_[next].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, fmt.internal);
    glBindImageTexture(RTGI_FILTER_IMG_OUT_DEPTH, depth_[next].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    gl::dispatch(prog, w, h);
    cur_ = next;
    valid_ = true;
    return value_[cur_];
}

void copyTexture(gl::ProgramCache& programs, const FilterFormat& fmt, const gl::Texture& src, const gl::Texture& dst) {
    if (src.desc() != dst.desc()) throw std::logic_error("copyTexture: '" + src.label() + "' and '" + dst.label() + "' differ");
    gl::Defines defs = formatDefines(fmt);
    defs.push_back({"UPSAMPLE_COPY", ""});
    const gl::Program& prog = programs.compute("filter/upsample.comp", defs);
    glBindTextureUnit(RTGI_FILTER_TEX_LOW, src.id());
    glBindImageTexture(RTGI_FILTER_IMG_OUT, dst.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, fmt.internal);
    gl::dispatch(prog, dst.width(), dst.height());
}

void upsample(gl::ProgramCache& programs, gl::MemoryLedger& ledger, const std::string& label,
              const FilterFormat& fmt, const gl::Texture& low, const gl::Texture& lowDepth,
              const gl::Texture& fullDepth, gl::Texture& out, bool depthAware) {
    const gl::NamedTextureDesc t = upsampleTexture(label, fmt, {fullDepth.width(), fullDepth.height()});
    out.ensure(ledger, t.label, t.desc);
    gl::Defines defs = formatDefines(fmt);
    defs.push_back({"UPSAMPLE_DEPTH_AWARE", depthAware ? "1" : "0"});
    const gl::Program& prog = programs.compute("filter/upsample.comp", defs);
    // Producer: the low-resolution pass before (image stores).
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    low.setSampling(GL_LINEAR, GL_LINEAR);
    glBindTextureUnit(RTGI_FILTER_TEX_LOW, low.id());
    glBindTextureUnit(RTGI_FILTER_TEX_LOW_DEPTH, lowDepth.id());
    glBindTextureUnit(RTGI_FILTER_TEX_FULL_DEPTH, fullDepth.id());
    glBindImageTexture(RTGI_FILTER_IMG_OUT, out.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, fmt.internal);
    gl::dispatch(prog, out.width(), out.height());
}

}  // namespace rtgi
