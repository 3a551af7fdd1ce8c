#pragma once
// The LPV volumes and the GPU kernels that fill them, callable on their own
// so tests can drive one step with synthetic inputs. Every kernel binds the
// uniform block, its textures and images itself.
#include "gl/program.h"
#include "gl/resources.h"

#include <glm/glm.hpp>

#include <array>
#include <vector>

namespace rtgi::lpv {

using Rgb = std::array<gl::Texture, 3>;
// lpv.sh_order=2 (docs/lpv.md, "Second-order SH"): the band-2 part of one volume:
// [0..2] coefficients 4-7 of r, g, b (RGBA), [3] coefficient 8 of r, g, b (.rgb).
using Hi = std::array<gl::Texture, 4>;

// RSM targets (lpv.rsm).
struct Rsm {
    gl::Texture flux;    // RGBA32F: albedo * E_perp * A_texel
    gl::Texture normal;  // RGBA16F: world normal of the lit side, a = 1 where a surface was drawn
    gl::Texture depth;   // D32F
};
// Descriptors of an RSM of side n: flux, normal, depth (lpv.rsm allocates
// from them; the memory estimate counts them).
struct RsmDescs {
    gl::TextureDesc flux, normal, depth;
};
// lpv.apply's running sums over cascades (C > 1; two of them), view-sized.
inline gl::TextureDesc applySumDesc(glm::ivec2 view) { return {GL_TEXTURE_2D, GL_RGBA32F, view.x, view.y}; }
// lpv.apply_resolution=half: the apply's size (ceil(view / 2)), its outputs (RGBA16F) and the
// depth + view normal of its texels (RGBA32F) that lpv.upsample weights by.
inline glm::ivec2 applyHalfSize(glm::ivec2 view) { return (view + 1) / 2; }
inline gl::TextureDesc applyLowDesc(glm::ivec2 view) {
    return {GL_TEXTURE_2D, GL_RGBA16F, applyHalfSize(view).x, applyHalfSize(view).y};
}
inline gl::TextureDesc applyLowGeometryDesc(glm::ivec2 view) {
    return {GL_TEXTURE_2D, GL_RGBA32F, applyHalfSize(view).x, applyHalfSize(view).y};
}
inline RsmDescs rsmDescs(int n) {
    return {{GL_TEXTURE_2D, GL_RGBA32F, n, n}, {GL_TEXTURE_2D, GL_RGBA16F, n, n}, {GL_TEXTURE_2D, GL_DEPTH_COMPONENT32F, n, n}};
}
// Local-light RSM faces (lpv.rsm, docs/lpv.md "Injection"): layers of 2D arrays of one side n (an
// Rsm whose textures are arrays), at most kRsmArrayLayers per array (GL 4.5's minimum of
// GL_MAX_ARRAY_TEXTURE_LAYERS, as the local shadow array): face f is layer f % kRsmArrayLayers of
// array f / kRsmArrayLayers.
inline constexpr int kRsmArrayLayers = 2048;
inline RsmDescs rsmArrayDescs(int n, int layers) {
    return {{GL_TEXTURE_2D_ARRAY, GL_RGBA32F, n, n, layers},
            {GL_TEXTURE_2D_ARRAY, GL_RGBA16F, n, n, layers},
            {GL_TEXTURE_2D_ARRAY, GL_DEPTH_COMPONENT32F, n, n, layers}};
}

// The textures Volumes allocates, by ledger label, for a grid, volume format
// and SH order (the ensure functions allocate from the same descriptors; the
// memory estimate sums these lists, one per cascade): ensureLight, ensureNear,
// ensureGeometry, ensureVisibility, ensureSky, ensureHistory / ensureNearHistory.
std::vector<gl::NamedTextureDesc> lightTextures(glm::ivec3 grid, GLenum format, int shOrder);
std::vector<gl::NamedTextureDesc> nearTextures(glm::ivec3 grid, GLenum format, int shOrder);
std::vector<gl::NamedTextureDesc> geometryTextures(glm::ivec3 grid, GLenum format, bool twoSided);
gl::NamedTextureDesc visibilityTexture(glm::ivec3 grid);
gl::NamedTextureDesc skyTexture(glm::ivec3 grid);
gl::NamedTextureDesc faceTexture(glm::ivec3 grid);  // lpv.blocking=visibility: face openness, RGBA8
std::vector<gl::NamedTextureDesc> historyTextures(glm::ivec3 grid, GLenum format, int shOrder, bool near);
// lpv.sun_cache (band 1, compute path; docs/lpv.md "Sun injection cache"): the packed injected volume (step 0)
// of a frame whose only light source is the sun, kept while nothing it depends on changes.
std::vector<gl::NamedTextureDesc> sunCacheTextures(glm::ivec3 grid, GLenum format);
bool ensureSunCache(gl::MemoryLedger& ledger, std::array<gl::Texture, 3>& cache, glm::ivec3 grid, GLenum format);
// Copies the r, g, b volumes (or band 2's hi r, g, b, last) `from` into `to` (grid g, volume format
// `format`) in one compute dispatch (lpv/copy.comp; glCopyImageSubData of a small 3D volume measured ~20 us
// on the H200). `from` is read as textures: the caller issues the barrier for its producer's image stores;
// the copy's are image stores, which the next reader's barrier covers.
void copyVolumes(gl::ProgramCache& programs, const std::array<gl::Texture, 3>& from, std::array<gl::Texture, 3>& to,
                 glm::ivec3 g, GLenum format);
void copyVolumes(gl::ProgramCache& programs, const std::array<gl::Texture, 4>& from, std::array<gl::Texture, 4>& to,
                 glm::ivec3 g, GLenum format);

struct Volumes {
    glm::ivec3 grid{0};
    GLenum format = GL_RGBA16F;
    Rgb inject;                  // R32F (4X, Y, Z): fp32 atomic accumulation, coefficient k at 4x + k; zero between frames
    std::array<Rgb, 2> step;     // propagation ping-pong (format)
    Rgb accum;                   // sum of all iterations (format)
    Rgb near;                    // cascades i > 0: the part of accum the finer cascade covers (format, docs/lpv.md)
    gl::Texture geometryAccum;   // R32F (8(X+1), Y+1, Z+1): blocking SH, sum(A albedo.rgb), sum(A); zero between frames
    gl::Texture geometry;        // format (X+1, Y+1, Z+1): blocking SH on the corner lattice
    gl::Texture geometryAlbedo;  // RGBA16F: mean albedo (rgb) of the blockers
    gl::Texture geometryAxes;    // RGBA16F: sum(A / s^2 |n|) (xyz), two-sided axis blocking (docs/lpv.md, "Leaks"); two-sided only
    gl::Texture visibility;      // RG16F (N X, N Y, Z): per-cell distance moments (lpv.lookup=visibility)
    gl::Texture sky;             // RGBA16F: band-1 SH of each cell's sky visibility (lpv.sky=visibility)
    gl::Texture faces;           // RGBA8: open fraction of the slab to the +x, +y, +z neighbour (lpv.blocking=visibility)
    std::array<Rgb, 2> history;  // temporal blend targets (format)
    std::array<Rgb, 2> nearHistory;  // cascades i > 0: the near part's temporal blend targets (format)
    // lpv.sh_order=2 only (empty otherwise): the band-2 parts of inject, step, accum, near.
    int shOrder = 1;
    Rgb injectHi;                // R32F (4X, Y, Z): coefficient 4 + k at 4x + k
    gl::Texture injectLast;      // R32F (3X, Y, Z): coefficient 8 of colour c at 3x + c
    std::array<Hi, 2> stepHi;
    Hi accumHi;
    Hi nearHi;
    std::array<Hi, 2> historyHi;
    std::array<Hi, 2> nearHistoryHi;
    gl::FramebufferHandle injectFbo;                   // raster baseline: step[0] + accum, additive
    std::array<gl::FramebufferHandle, 2> propagateFbo; // raster baseline: step[k] + accum (blended)
    gl::VertexArrayHandle emptyVao;                    // attribute-less draws need a bound VAO (core profile)

    // (Re)allocates the light volumes; returns true when they changed.
    bool ensureLight(gl::MemoryLedger& ledger, glm::ivec3 grid, GLenum format, int shOrder = 1);
    void ensureNear(gl::MemoryLedger& ledger);
    // twoSided (lpv.blocking=two-sided): also the axis blocking (3 more accumulation channels and
    // geometryAxes); otherwise neither is allocated and injectGeometry runs the oriented variant.
    void ensureGeometry(gl::MemoryLedger& ledger, bool twoSided = true);
    bool ensureVisibility(gl::MemoryLedger& ledger);  // true when (re)allocated
    bool ensureSky(gl::MemoryLedger& ledger);         // true when (re)allocated
    bool ensureFaces(gl::MemoryLedger& ledger);       // true when (re)allocated
    void ensureHistory(gl::MemoryLedger& ledger);
    void ensureNearHistory(gl::MemoryLedger& ledger);
    void ensureRasterTargets();
};

// #defines selecting the image format of one volume format (and RTGI_LPV_SH2 for order 2).
gl::Defines formatDefines(GLenum format, int shOrder = 1);

// Compute injection of every RSM texel with fp32 image atomics (pre-reduced per
// workgroup) into v.inject, which must be zero (it is after allocation and after
// packLight); `stats` (one uint) counts dropped texels and is not cleared here.
void injectCompute(gl::ProgramCache& programs, const gl::Buffer& ubo, const Rsm& rsm, int rsmSize, Volumes& v,
                   const gl::Buffer& stats);
// fp32 accumulation targets of an injection: a volume's (inject, and with band 2 injectHi and
// injectLast) or an injection cache's (below); hi and last are null for band 1.
struct InjectTarget {
    Rgb* rgb = nullptr;
    Rgb* hi = nullptr;
    gl::Texture* last = nullptr;
};
InjectTarget injectTarget(Volumes& v);
// Batched injection of local-light RSM faces (docs/lpv.md "Injection"): entries [first, first +
// count) of `faces` (gpu::LpvRsmFace: a layer of `rsmArray` and the inverse of the view it was drawn
// with) in one dispatch of side² x count texels; the volume's placement from `ubo` (any of its RSM
// fields are ignored). The same sums as injectCompute of each face with its own uniform block, in
// another order. `statsSlot`: which of the two counters of `stats` gets the dropped texels.
void injectFaces(gl::ProgramCache& programs, const gl::Buffer& ubo, const Rsm& rsmArray, const gl::Buffer& faces,
                 int first, int count, const InjectTarget& target, int shOrder, const gl::Buffer& stats,
                 int statsSlot = 0);
// The local lights' injection cache of one volume (docs/lpv.md "Injection cache"): an fp32
// accumulation of the same layout as Volumes::inject (band 2: injectHi, injectLast), holding the
// sum of the faces injected into it since it was last cleared.
struct InjectCache {
    Rgb rgb, hi;
    gl::Texture last;
    // (Re)allocates for a grid and SH order; true when it did (the new textures are zero).
    bool ensure(gl::MemoryLedger& ledger, glm::ivec3 grid, int shOrder);
    void clear() const;
    void reset();
    explicit operator bool() const { return bool(rgb[0]); }
    InjectTarget target();
};
std::vector<gl::NamedTextureDesc> injectCacheTextures(glm::ivec3 grid, int shOrder);
// v.inject (and band 2's) = the cache: a copy, on which the frame's other injections add.
// v.inject must not be in use by a pending dispatch other than the ones the barrier orders.
void copyInjectCache(gl::ProgramCache& programs, const InjectCache& cache, Volumes& v);
// fp32 accumulation -> step[0] in the propagation format; zeroes v.inject behind
// (the first propagation step starts accum from step[0]).
void packLight(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v);
// Seed method: GL_POINTS + geometry shader + additive blending into step[0] and accum.
// `clear`: start from zero (the first RSM of a frame); later RSMs add on top.
void injectRaster(gl::ProgramCache& programs, const gl::Buffer& ubo, const Rsm& rsm, int rsmSize, Volumes& v,
                  bool clear = true);
// The same for layer `layer` of a local-light RSM array, drawn with the inverse view-projection `invViewProj`.
void injectRasterLayer(gl::ProgramCache& programs, const gl::Buffer& ubo, const Rsm& rsmArray, int layer,
                       const glm::mat4& invViewProj, Volumes& v, bool clear = true);
// Geometry volume from the RSM (skipped when rsmSize is 0: no orthographic sun
// RSM) and (if linearDepth is non-null) the G-buffer at quarter resolution.
struct GBufferView {
    const gl::Texture* linearDepth = nullptr;
    const gl::Texture* normal = nullptr;
    const gl::Texture* albedo = nullptr;
    const gl::Texture* material = nullptr;
    glm::ivec2 size{0};
    int stride = 2;  // lpv.geometry_stride: pixel stride in x and y (2 or 4), each sample stands for stride^2 pixels
};
// lpv.sky_bounce (docs/lpv.md, "Sky bounce"): the G-buffer surfels (every gb.stride-th pixel) lit by
// the sky add (rho pi sky f A / pi) cosLobe(n) into v.inject, f read from v.sky (and, when
// `moments`, weighted by v.visibility's moments with `visibilityExponent` and `visibilityViewBias`, as lpv.apply does).
void injectSky(gl::ProgramCache& programs, const gl::Buffer& ubo, const GBufferView& gb, Volumes& v,
               bool moments, int visibilityExponent, float visibilityViewBias);
void injectGeometry(gl::ProgramCache& programs, const gl::Buffer& ubo, const Rsm& rsm, int rsmSize,
                    const GBufferView& gbuffer, Volumes& v);
// Iterations 1..n; returns the index of step[] holding the last iteration.
// `near` (cascades i > 0): also fills v.near with the steps weighted by
// cascadeNearWeight (v.ensureNear first).
// `visibility` (lpv.blocking=visibility): v.faces holds the traced face openness, which blocks the flow too.
// Most iterations per dispatch of the fused propagation: a 4^3 tile with a halo of 2 is 8^3 cells of
// 3 vec4 = 24 KiB of shared memory (GL guarantees 32 KiB; a halo of 3 would need 47 KiB).
inline constexpr int kMaxFuse = 2;
// `fuse` > 1 (lpv.fuse, band 1 only): up to that many iterations per dispatch (lpv/propagate_fused.comp,
// the same steps; docs/lpv.md, "Fused propagation"), split where the near part is taken.
// `faceKernel` (lpv.propagate_kernel=face): the unfused band-1 steps run lpv/propagate_faces.comp, one
// invocation per cell, neighbour face and colour (the same arithmetic; docs/lpv.md, "Per-face propagation kernel").
int propagateCompute(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v, int iterations,
                     bool near = false, bool visibility = false, int fuse = kMaxFuse, int nearIterations = 0,
                     bool faceKernel = false);
// propagateCompute one dispatch (chunk of iterations) at a time, so the caller can interleave the
// cascades: step(leadingBarrier = false) issues no barrier before its dispatch, which lets it run
// beside another cascade's step issued just before it (independent volumes); the barrier of the
// first step of the next round covers both (docs/lpv.md, "Interleaved cascades").
class ComputePropagation {
public:
    // `nearIterations` (0: iterations): the step count whose near weights make the near part (the finer
    // cascade's reach when the coarsest runs lpv.coarse_iterations).
    ComputePropagation(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v, int iterations, bool near,
                       bool visibility, int fuse, int nearIterations = 0, bool faceKernel = false);
    bool done() const { return k_ > iterations_; }
    void step(bool leadingBarrier = true);
    int last() const { return src_; }  // the last written step's index

private:
    void nearStep(int k);
    gl::ProgramCache& programs_;
    const gl::Buffer& ubo_;
    Volumes& v_;
    int iterations_;
    bool near_, visibility_, sh2_, faceKernel_;
    gl::Defines defines_;
    int nearK_ = 0;
    float nearF_ = 0.0f;
    int maxFuse_ = 1, k_ = 1, src_ = 0;
};
int propagateRaster(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v, int iterations);

// lpv.propagate_cascades=joint (docs/lpv.md, "Joint cascade propagation"): the step ping-pong and
// the sum of up to kJointCascades cascades stacked along z (cascade i's cells at z + i Z), so one
// dispatch per iteration propagates them all (compute path, band 1, unfused, no traced faces).
inline constexpr int kJointCascades = 2;
struct JointVolumes {
    Rgb step[2];
    Rgb accum;
    void ensure(gl::MemoryLedger& ledger, glm::ivec3 grid, GLenum format);
};
std::vector<gl::NamedTextureDesc> jointTextures(glm::ivec3 grid, GLenum format);
// Whether the joint propagation applies to a configuration (else one dispatch per cascade).
bool jointPropagationApplies(int cascades, int shOrder, int fuse, bool visibility);
// Propagates 1..kJointCascades cascades (same grid and format, band 1, geometry volumes as for
// propagateCompute) with one dispatch per iteration: afterwards each one's accum, last step and
// (near[i]) near part equal those of propagateCompute(v_i, near[i]). Returns the last step's index.
int propagateJoint(gl::ProgramCache& programs, const gl::Buffer& ubo, const std::vector<Volumes*>& vs,
                   const std::vector<bool>& near, JointVolumes& joint, int iterations);
// lpv.apply: indirect diffuse (and specular when `specular` is set) radiance from
// `volume` at the G-buffer's pixels; the frame uniforms must be bound (binding 0).
struct ApplyInputs {
    GBufferView gbuffer;
    const Rgb* volume = nullptr;
    const Hi* volumeHi = nullptr;  // lpv.sh_order=2: its band-2 part (and nearHi of `near`)
    const Hi* nearHi = nullptr;
    // Cascades (docs/lpv.md): this dispatch adds cascade `cascade` of `cascades`
    // (its own ubo); `near` its near part (cascade > 0); `sumE`, `sumS` RGBA32F
    // running sums between the dispatches, which run finest first.
    int cascade = 0, cascades = 1;
    const Rgb* near = nullptr;
    const Rsm* rsm = nullptr;  // set: subtract the self-illumination of sunlit receivers (lpv.self_correction)
    gl::Texture* sumE = nullptr;
    gl::Texture* sumS = nullptr;
    const gl::Texture* brdfLut = nullptr;     // split-sum LUT (SSR family), optional
    const gl::Texture* s3ho = nullptr;        // AO hooks, optional; S3HO wins over bent normals
    const gl::Texture* bentNormal = nullptr;
    // Leaks (docs/lpv.md, "Leaks"): set: lpv.lookup=geometry with this cascade's geometry volume.
    const gl::Texture* geometry = nullptr;
    const gl::Texture* geometryAxes = nullptr;  // set with `geometry`: lpv.blocking=two-sided segments
    const gl::Texture* visibility = nullptr;  // set: lpv.lookup=visibility with this cascade's moments
    int visibilityExponent = 3;               // lpv.visibility_exponent
    float visibilityViewBias = 0.35f;         // lpv.visibility_view_bias (cells)
    const gl::Texture* sky = nullptr;         // set: lpv.sky=visibility with this cascade's sky visibility
    // With `sky`: the volume holds the sky bounce (lpv.sky_bounce), whose self-illumination of the
    // receiver (kappa rho pi sky f) is subtracted with the sun's (lpv.self_correction).
    bool skySelf = false;
    bool damping = false;                     // lpv.damping
    gl::Texture* indirect = nullptr;          // RGBA16F outputs
    gl::Texture* specular = nullptr;
    // Set: lpv.apply_resolution=half. `indirect`, `specular`, `sumE`, `sumS` are then
    // half-resolution (applyHalfSize) and hold the albedo-free terms; this RGBA32F image gets
    // each texel's depth and view normal; applyUpsample makes the full-resolution outputs.
    gl::Texture* lowGeometry = nullptr;
};
void applyCompute(gl::ProgramCache& programs, const gl::Buffer& ubo, const ApplyInputs& in);
// lpv.upsample: the half-resolution apply's terms (`lowIndirect`, `lowSpecular` when `specular`
// is set, `lowGeometry`) to the full-resolution `indirect` and `specular` (joint bilateral,
// lib/filter.glsl), times the pixels' albedo and BRDF (docs/lpv.md, "Half-resolution apply").
struct UpsampleInputs {
    GBufferView gbuffer;
    const gl::Texture* lowIndirect = nullptr;
    const gl::Texture* lowSpecular = nullptr;
    const gl::Texture* lowGeometry = nullptr;
    const gl::Texture* brdfLut = nullptr;
    gl::Texture* indirect = nullptr;
    gl::Texture* specular = nullptr;
};
void applyUpsample(gl::ProgramCache& programs, const gl::Buffer& ubo, const UpsampleInputs& in);
// history[target] = mix(accum, history[1 - target] re-indexed, lpv.temporal) (and historyHi with band 2).
void temporalBlend(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v, int target);
// nearHistory[target] = mix(near, nearHistory[1 - target] re-indexed, lpv.temporal): cascades i > 0
// blend their near part with the same factor and shift as the whole, so that the apply's
// u near + U (total - near) stays a blend of consistent volumes.
void temporalBlendNear(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v, int target);

}  // namespace rtgi::lpv
