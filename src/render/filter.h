#pragma once
// Shared screen-space filter chain (SPEC 6.2-6.4): separable edge-preserving
// blur, the temporal reprojection filter of seed 000 listing 11, depth-aware
// upsampling. Used by the AO family; SSR reuses it with another value format
// (compute/filter/*.comp are parameterized by FILTER_FORMAT, not copied).
#include "gl/program.h"
#include "gl/resources.h"
#include "render/view.h"

#include <cstdint>

#include <string>
#include <vector>

namespace rtgi {

struct FilterFormat {
    GLenum internal = GL_R16F;  // texture format of values
    std::string glsl = "r16f";  // matching image format qualifier
};

struct BlurThresholds {
    float depth = 0.05f;   // relative depth difference above which a tap is dropped
    float normal = 0.8f;   // minimum cosine between centre and tap normals
};

// The textures the filters allocate for values of `size`, by ledger label
// (they allocate from these; the memory estimate sums them): the blur's
// temporary `label.tmp` and output `label`, the temporal filter's two values
// and depths `label.a`, `label.a.depth`, `label.b`, `label.b.depth`, the
// upsampled output `label`.
std::vector<gl::NamedTextureDesc> blurTextures(const std::string& label, const FilterFormat& fmt, glm::ivec2 size);
std::vector<gl::NamedTextureDesc> temporalTextures(const std::string& label, const FilterFormat& fmt, glm::ivec2 size);
gl::NamedTextureDesc upsampleTexture(const std::string& label, const FilterFormat& fmt, glm::ivec2 fullSize);

// out = vertical(horizontal(in)); tmp and out are (re)allocated at in's size.
void separableBlur(gl::ProgramCache& programs, gl::MemoryLedger& ledger, const std::string& label,
                   const FilterFormat& fmt, const gl::Texture& in, const gl::Texture& depth,
                   const gl::Texture& normal, gl::Texture& tmp, gl::Texture& out, BlurThresholds t = {});

// The camera motion the temporal filter's disocclusion test needs: current
// view space -> previous view space, and the projection's tan(fovY/2)·aspect,
// tan(fovY/2). The default is a still camera.
struct TemporalCamera {
    glm::mat4 curToPrevView{1.0f};
    glm::vec2 projScale{1.0f};
};
TemporalCamera temporalCamera(const View& view);

// Temporal filter with its own ping-pong history (value + linear depth).
class TemporalFilter {
public:
    // Blends `current` with the reprojected history; returns this frame's
    // output (valid until the next run). reset: camera cut or no history.
    // History whose depth disagrees with the reprojected surface is rejected
    // (docs/temporal.md, "Disocclusion").
    const gl::Texture& run(gl::ProgramCache& programs, gl::MemoryLedger& ledger, const std::string& label,
                           const FilterFormat& fmt, const gl::Texture& current, const gl::Texture& depth,
                           const gl::Texture& velocity, bool reset, const TemporalCamera& camera = {});
    const gl::Texture& output() const { return value_[cur_]; }
    // Pixels of the last run whose history was rejected (disoccluded or
    // reprojected off-screen); 0 after a reset. Reads back from the GPU (a stall).
    std::uint32_t disoccludedPixels() const;

private:
    gl::Texture value_[2], depth_[2];
    // The disocclusion counter, three in turn, so that a frame's clear never meets a buffer the previous frame's
    // dispatch may still use (session 13's suspect for the Cornell box's ao.temporal stall, whose causes were
    // elsewhere: docs/lpv.md "Closed scenes"; kept, it costs two words).
    static constexpr int kCountBuffers = 3;
    gl::Buffer counts_[kCountBuffers];
    int lastCount_ = -1;
    int cur_ = 0;
    bool valid_ = false;
};

// dst = src texel for texel (same size and format), as a dispatch: glCopyImageSubData in the frame left the
// GPU idle for 5-36 ms inside later passes' scopes on the H200 (docs/BENCHMARKS.md "Session 14 device run").
// The caller orders src's producer (texture fetch); dst's readers need an image-access barrier.
void copyTexture(gl::ProgramCache& programs, const FilterFormat& fmt, const gl::Texture& src, const gl::Texture& dst);

// Half -> full resolution into `out` (allocated at fullDepth's size).
void upsample(gl::ProgramCache& programs, gl::MemoryLedger& ledger, const std::string& label,
              const FilterFormat& fmt, const gl::Texture& low, const gl::Texture& lowDepth,
              const gl::Texture& fullDepth, gl::Texture& out, bool depthAware);

}  // namespace rtgi
