#pragma once
// The compute rasterizer (docs/visibility.md): any view-projection of the
// whole scene into a visibility buffer (depth + triangle id per pixel),
// then resolves that turn it into G-buffer targets, RSM texels or a D32F
// depth texture. Used by visibility.raster / visibility.resolve,
// shadow.raster and the compute path of lpv.rsm; other shadow maps call
// rasterizeVisibility + copyVisibilityDepth the same way.
#include "gl/program.h"
#include "gl/resources.h"
#include "render/settings.h"
#include "compute/lib/visibility_shared.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <map>
#include <string>

namespace rtgi {
class GpuScene;
struct FrameContext;

// GL_NV_shader_atomic_int64 (64-bit atomicMin on SSBOs) in this context;
// queried once through glGetStringi(GL_EXTENSIONS).
bool visibilityAtomic64Supported();

struct VisibilityOptions {
    bool depthBias = false;   // glPolygonOffset(1.5, 2) of the hardware shadow passes
    bool cullBack = false;    // counter-clockwise = front (off for every view today: scenes may be open)
    bool atomic64 = true;     // use the 64-bit path when supported (false: force the two-pass 32-bit path)
    bool countHits = false;   // tests: count fragments written per pixel (VisibilityTarget::hits)
    int binScale = 1;         // multiplier on the bin capacities (setting raster.bin_scale)
    std::int64_t largeCapacity = 0, nodeCapacity = 0;  // > 0: fixed capacities instead (tests)
    int tileSlots = RTGI_VISIBILITY_TILE_SLOTS_DEFAULT;  // bin entries per tile held in its slot array (0: lists only)
};

struct VisibilityCounters {
    std::uint32_t largeCount = 0, nodeCount = 0, smallCount = 0, culledCount = 0;
};

// One view's visibility buffer and bins, kept between frames.
struct VisibilityTarget {
    std::string label;           // ledger prefix, e.g. "visibility" or "shadow.raster"
    glm::ivec2 size{0};
    bool atomic64 = false;       // layout of `vis` (set by rasterizeVisibility)
    int triangles = 0;
    std::int64_t largeCapacity = 0, nodeCapacity = 0;
    int tileSlots = 0;           // bin entries per tile held in `slots` (the rest in the node lists)
    gl::Buffer vis;              // 8 bytes per pixel: uint64 depth|id, or uint depth[N] then uint id[N]
    gl::Buffer large, tileHeads, nodes, counters, hits;
    gl::Buffer slots;            // per tile its entry count, then tileSlots large-triangle ids per tile
    // copyVisibilityDepth targets by (texture, layer): one per layer of a
    // local-light shadow array, made once, dropped with resetDepthTargets().
    std::map<std::pair<GLuint, int>, gl::FramebufferHandle> depthFbos;
    gl::VertexArrayHandle emptyVao;
    bool checked = false;        // overflow checked once after the first frame

    // Reads the counters back (stalls); for stats and the overflow check.
    VisibilityCounters readCounters() const;
    // Throws a one-sentence error naming `pass` and raster.bin_scale when a
    // bin buffer overflowed in the last rasterization.
    void checkOverflow(const std::string& pass) const;
    // After a reallocation (texture names may be reused).
    void resetDepthTargets() { depthFbos.clear(); }
};

// Buffer capacities of one view (docs/visibility.md "Scale and memory"):
// bounded by the resolution once the scene is large.
struct VisibilityCapacity {
    std::int64_t largeTriangles = 0, binEntries = 0;
    std::int64_t bytes = 0;  // every buffer of the view together
};
VisibilityCapacity visibilityCapacity(glm::ivec2 size, std::int64_t triangles, int binScale);

// Rasterizes every scene triangle with `viewProj` into `target` (size in
// pixels). Binds its own buffers; leaves GL_SHADER_STORAGE_BARRIER issued.
void rasterizeVisibility(gl::ProgramCache& programs, gl::MemoryLedger& ledger, const GpuScene& scene,
                         const glm::mat4& viewProj, glm::ivec2 size, VisibilityTarget& target,
                         const VisibilityOptions& options);

// The second depth layer of the view last rasterized into `target` (docs/ao.md
// "Second depth layer"): setup (small triangles) and tile run again over its
// bins and write into `layer2` (R32F, cleared to FLT_MAX = none) the nearest
// linear depth farther than `layer1` (the view's linear depth) + separation,
// separation = x, or x * the first layer's depth when depthScaled. `proj` is
// the view's perspective projection (window depth -> linear depth).
struct SecondLayerOptions {
    float separation = 0.0f;
    bool depthScaled = false;
};
void rasterizeSecondLayer(gl::ProgramCache& programs, const GpuScene& scene, const glm::mat4& viewProj,
                          const glm::mat4& proj, const VisibilityTarget& target, const gl::Texture& layer1,
                          const gl::Texture& layer2, const SecondLayerOptions& options);

// Binds the visibility buffer, scene buffers and uniforms of `target` for a
// resolve program (viewProj = the rasterized view's).
void bindVisibility(const gl::Program& prog, const GpuScene& scene, const glm::mat4& viewProj,
                    const VisibilityTarget& target);
// Program defines matching the target's buffer layout.
gl::Defines visibilityDefines(const VisibilityTarget& target);

// Writes the visibility buffer's depth (1 where empty) into a D32F texture
// (2D, or one layer of an array/cube when layer >= 0) with one full-screen
// triangle writing gl_FragDepth.
void copyVisibilityDepth(gl::ProgramCache& programs, VisibilityTarget& target, const gl::Texture& depth,
                         int layer = -1);

// raster.path after `auto` for the camera view (the G-buffer): compute where
// GL_NV_shader_atomic_int64 exists.
bool useComputeRaster(const Settings& settings);
// The same for the light views (sun / spot / point / area shadow maps, the
// sun's RSM): `auto` keeps them on the hardware rasterizer, which is faster
// there on the H100 (docs/BENCHMARKS.md: 2048² sun map 1.08 vs 1.21 ms, cube
// faces 0.10 vs 2.0 ms at 256²); only raster.path=compute moves them.
bool useComputeRasterLightViews(const Settings& settings);
// Why the other path's passes are skipped (results.json "skipped").
std::string rasterPathReason(const Settings& settings, bool lightViews = false);

// Options from the settings (raster.atomic64, raster.bin_scale).

VisibilityOptions visibilityOptions(const Settings& settings);

}  // namespace rtgi
