// The compute rasterizer's host side: buffer sizing, the dispatch sequence
// clear -> setup -> bin -> tile (twice on the 32-bit path) and the depth copy.
#include "render/visibility/visibility.h"

#include "gl/context.h"
#include "gl/profiler.h"
#include "render/gpu_scene.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "compute/lib/visibility_shared.h"

namespace rtgi {

static_assert(sizeof(VisCounters) == sizeof(VisibilityCounters));

namespace {

constexpr std::int64_t kTriangleRecordBytes = 208;  // VisTriangle (lib/raster.glsl: the set-up triangle, std430)
constexpr std::int64_t kMaxBufferBytes = std::int64_t(1) << 31;  // per buffer, well under every driver's limit

// glDispatchCompute with at most 65535 groups per dimension.
// `program` names the sub-step for profile.dispatches.
void dispatchLinear(const gl::Program& program, std::int64_t groups) {
    if (groups <= 0) return;
    std::int64_t x = std::min<std::int64_t>(groups, 65535);
    std::int64_t y = (groups + x - 1) / x;
    gl::Profiler::noteDispatch();
    auto scope = gl::Profiler::dispatchScope(program.name());
    glUseProgram(program.id());
    glDispatchCompute(GLuint(x), GLuint(y), 1);
}

void ensureBuffer(gl::Buffer& b, gl::MemoryLedger& ledger, const std::string& label, std::int64_t bytes) {
    if (bytes > kMaxBufferBytes)
        throw std::runtime_error(label + ": the compute rasterizer would need " + std::to_string(bytes >> 20) +
                                 " MiB (limit " + std::to_string(kMaxBufferBytes >> 20) +
                                 " MiB); lower the resolution or raster.bin_scale");
    if (b.size() < bytes || !b) b.ensure(ledger, label, bytes);
}

}  // namespace

bool visibilityAtomic64Supported() {
    // Without a loaded GL context (--print-frame, --validate-only, settings
    // checks before the context exists) the answer is unknown: say no, and do
    // not cache it, so a later call with a context asks the driver.
    if (!glGetIntegerv || !glGetStringi) return false;
    static const bool supported =
        gl::hasExtension("GL_NV_shader_atomic_int64") && gl::hasExtension("GL_ARB_gpu_shader_int64");
    return supported;
}

bool useComputeRaster(const Settings& s) {
    return s.raster.path == RasterSettings::Path::Compute ||
           (s.raster.path == RasterSettings::Path::Auto && visibilityAtomic64Supported());
}

bool useComputeRasterLightViews(const Settings& s) { return s.raster.path == RasterSettings::Path::Compute; }

std::string rasterPathReason(const Settings& s, bool lightViews) {
    const bool compute = lightViews ? useComputeRasterLightViews(s) : useComputeRaster(s);
    return std::string("raster.path=") + toString(s.raster.path) + ": the " +
           (compute ? "compute rasterizer" : "hardware rasterizer") + " runs" +
           (lightViews && s.raster.path == RasterSettings::Path::Auto ? " the light views" : "");
}

VisibilityOptions visibilityOptions(const Settings& s) {
    VisibilityOptions o;
    if (s.raster.atomic64 == Toggle::On && !visibilityAtomic64Supported())
        throw ConfigError("setting 'raster.atomic64': on, but this OpenGL context lacks GL_NV_shader_atomic_int64");
    o.atomic64 = s.raster.atomic64 != Toggle::Off;
    o.binScale = s.raster.binScale;
    return o;
}

gl::Defines visibilityDefines(const VisibilityTarget& t) {
    gl::Defines d;
    if (t.atomic64) d.push_back({"RTGI_VISIBILITY_ATOMIC64", ""});
    d.push_back({"RTGI_VISIBILITY_TILE_SLOTS", std::to_string(t.tileSlots)});
    return d;
}

VisibilityCounters VisibilityTarget::readCounters() const {
    VisibilityCounters c;
    if (counters) counters.download(&c, sizeof(c));
    return c;
}

void VisibilityTarget::checkOverflow(const std::string& pass) const {
    VisibilityCounters c = readCounters();
    auto fail = [&](const char* what, std::uint32_t need, std::int64_t have) {
        throw std::runtime_error(pass + ": the compute rasterizer's " + what + " overflowed (" + std::to_string(need) +
                                 " needed, " + std::to_string(have) + " available at " + std::to_string(size.x) + "x" +
                                 std::to_string(size.y) + "); raise raster.bin_scale");
    };
    if (c.largeCount > largeCapacity) fail("large-triangle list", c.largeCount, largeCapacity);
    if (c.nodeCount > nodeCapacity) fail("tile bins", c.nodeCount, nodeCapacity);
}

void bindVisibility(const gl::Program& prog, const GpuScene& scene, const glm::mat4& viewProj,
                    const VisibilityTarget& t) {
    prog.set(RTGI_VISIBILITY_LOC_VIEW_PROJ, viewProj);
    prog.set(RTGI_VISIBILITY_LOC_SIZE, t.size);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_VISIBILITY_SSBO_VERTICES, scene.vertices().id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_VISIBILITY_SSBO_INDICES, scene.indices().id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_VISIBILITY_SSBO_VISBUF, t.vis.id());
    scene.bindTables();
}

VisibilityCapacity visibilityCapacity(glm::ivec2 size, std::int64_t triangles, int binScale) {
    const std::int64_t pixels = std::int64_t(size.x) * size.y;
    const glm::ivec2 tiles = (size + RTGI_VISIBILITY_TILE - 1) / RTGI_VISIBILITY_TILE;
    const std::int64_t tileCount = std::int64_t(tiles.x) * tiles.y;
    // Large triangles: at most twice the scene's (clipping adds pieces) and
    // at most one per 8 pixels; bin entries: 64 per tile or 4 per large
    // triangle, whichever is more. Overflow is counted, never written.
    VisibilityCapacity c;
    c.largeTriangles = binScale * std::min<std::int64_t>(2 * triangles + 1024, std::max<std::int64_t>(65536, pixels / 8));
    c.binEntries = binScale * std::max<std::int64_t>(tileCount * 64, 4 * c.largeTriangles);
    c.largeTriangles = std::min<std::int64_t>(c.largeTriangles, kMaxBufferBytes / kTriangleRecordBytes);
    c.binEntries = std::min<std::int64_t>(c.binEntries, kMaxBufferBytes / 8);
    c.bytes = 8 * pixels + kTriangleRecordBytes * c.largeTriangles + 8 * c.binEntries + 4 * tileCount +
              4 * (1 + RTGI_VISIBILITY_TILE_SLOTS_DEFAULT) * tileCount + std::int64_t(sizeof(VisCounters));
    return c;
}

namespace {
// The buffers the setup, bin and tile kernels share.
void bindRasterBuffers(const VisibilityTarget& t) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_VISIBILITY_SSBO_LARGE, t.large.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_VISIBILITY_SSBO_TILEHEADS, t.tileHeads.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_VISIBILITY_SSBO_NODES, t.nodes.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_VISIBILITY_SSBO_COUNTERS, t.counters.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_VISIBILITY_SSBO_TILESLOTS, t.slots.id());
}
// One setup thread per scene triangle.
void dispatchSetup(const gl::Program& setup, const VisibilityTarget& t) {
    dispatchLinear(setup, (std::int64_t(t.triangles) + RTGI_VISIBILITY_SETUP_GROUP - 1) / RTGI_VISIBILITY_SETUP_GROUP);
}
// One workgroup per screen tile, timed as its own dispatch.
void dispatchTiles(const gl::Program& tile, glm::ivec2 size) {
    const glm::ivec2 tiles = (size + RTGI_VISIBILITY_TILE - 1) / RTGI_VISIBILITY_TILE;
    glUseProgram(tile.id());
    gl::Profiler::noteDispatch();
    auto scope = gl::Profiler::dispatchScope(tile.name());
    glDispatchCompute(GLuint(tiles.x), GLuint(tiles.y), 1);
}
}  // namespace

void rasterizeVisibility(gl::ProgramCache& programs, gl::MemoryLedger& ledger, const GpuScene& scene,
                         const glm::mat4& viewProj, glm::ivec2 size, VisibilityTarget& t,
                         const VisibilityOptions& o) {
    if (size.x <= 0 || size.y <= 0 || size.x > 32768 || size.y > 32768)
        throw std::runtime_error(t.label + ": compute rasterizer target " + std::to_string(size.x) + "x" +
                                 std::to_string(size.y) + " outside 1..32768");
    t.size = size;
    t.atomic64 = o.atomic64 && visibilityAtomic64Supported();
    t.triangles = scene.indexCount() / 3;
    const std::int64_t pixels = std::int64_t(size.x) * size.y;
    const glm::ivec2 tiles = (size + RTGI_VISIBILITY_TILE - 1) / RTGI_VISIBILITY_TILE;
    const std::int64_t tileCount = std::int64_t(tiles.x) * tiles.y;
    VisibilityCapacity cap = visibilityCapacity(size, t.triangles, o.binScale);
    t.largeCapacity = o.largeCapacity > 0 ? o.largeCapacity : cap.largeTriangles;
    t.nodeCapacity = o.nodeCapacity > 0 ? o.nodeCapacity : cap.binEntries;
    t.tileSlots = std::max(o.tileSlots, 0);
    ensureBuffer(t.vis, ledger, t.label + ".vis", pixels * 8);
    ensureBuffer(t.large, ledger, t.label + ".large", t.largeCapacity * kTriangleRecordBytes);
    ensureBuffer(t.tileHeads, ledger, t.label + ".tiles", tileCount * 4);
    ensureBuffer(t.nodes, ledger, t.label + ".bins", t.nodeCapacity * 8);
    ensureBuffer(t.slots, ledger, t.label + ".tile_slots", (1 + t.tileSlots) * tileCount * 4);
    ensureBuffer(t.counters, ledger, t.label + ".counters", sizeof(VisCounters));
    if (o.countHits) ensureBuffer(t.hits, ledger, t.label + ".hits", pixels * 4);

    // Write after read: the previous view rasterized into this target (one
    // target serves every face of the local-light shadow array) may still be
    // read by its depth copy or resolve. Mesa llvmpipe queues draws and runs
    // compute at once: without the barrier the clear below overtook the copy
    // and left every other layer empty.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    gl::Defines defs = visibilityDefines(t);
    if (o.countHits) defs.push_back({"RTGI_VISIBILITY_COUNT_HITS", ""});
    const gl::Program& clear = programs.compute("visibility/clear.comp", defs);
    const gl::Program& setup = programs.compute("visibility/setup.comp", defs);
    const gl::Program& bin = programs.compute("visibility/bin.comp", defs);
    const gl::Program& tile = programs.compute("visibility/tile.comp", defs);
    const int flags = (o.depthBias ? RTGI_VISIBILITY_FLAG_DEPTH_BIAS : 0) | (o.cullBack ? RTGI_VISIBILITY_FLAG_CULL_BACK : 0);
    const glm::ivec2 capacity(int(t.largeCapacity), int(t.nodeCapacity));
    // Only the uniforms each kernel reads (setting an inactive location may be an error).
    bindVisibility(setup, scene, viewProj, t);
    setup.set(RTGI_VISIBILITY_LOC_TRIANGLES, t.triangles);
    setup.set(RTGI_VISIBILITY_LOC_FLAGS, flags);
    setup.set(RTGI_VISIBILITY_LOC_CAPACITY, capacity);
    clear.set(RTGI_VISIBILITY_LOC_SIZE, t.size);
    bin.set(RTGI_VISIBILITY_LOC_SIZE, t.size);
    bin.set(RTGI_VISIBILITY_LOC_FLAGS, flags);
    bin.set(RTGI_VISIBILITY_LOC_CAPACITY, capacity);
    tile.set(RTGI_VISIBILITY_LOC_SIZE, t.size);
    tile.set(RTGI_VISIBILITY_LOC_FLAGS, flags);
    const bool tileReadsPhase = !t.atomic64 || o.countHits;  // the 64-bit write needs no phase
    bindRasterBuffers(t);
    if (o.countHits) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_VISIBILITY_SSBO_HITS, t.hits.id());

    dispatchLinear(clear, (std::max(pixels, tileCount) + 255) / 256);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    const int phases = t.atomic64 ? 1 : 2;
    for (int phase = 0; phase < phases; ++phase) {
        setup.set(RTGI_VISIBILITY_LOC_PHASE, phase);
        if (tileReadsPhase) tile.set(RTGI_VISIBILITY_LOC_PHASE, phase);
        dispatchSetup(setup, t);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        if (phase == 0) {
            glUseProgram(bin.id());
            gl::Profiler::noteDispatch();
            auto scope = gl::Profiler::dispatchScope(bin.name());
            glDispatchCompute(RTGI_VISIBILITY_BIN_GROUPS, 1, 1);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        }
        dispatchTiles(tile, t.size);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
}

void rasterizeSecondLayer(gl::ProgramCache& programs, const GpuScene& scene, const glm::mat4& viewProj,
                          const glm::mat4& proj, const VisibilityTarget& t, const gl::Texture& layer1,
                          const gl::Texture& layer2, const SecondLayerOptions& o) {
    // Only a depth per pixel: the 32-bit layout on every driver, one phase.
    const gl::Defines defs{{"RTGI_VISIBILITY_LAYER2", ""}, {"RTGI_VISIBILITY_TILE_SLOTS", std::to_string(t.tileSlots)}};
    const gl::Program& setup = programs.compute("visibility/setup.comp", defs);
    const gl::Program& tile = programs.compute("visibility/tile.comp", defs);
    const glm::vec4 layer(o.separation, o.depthScaled ? 1.0f : 0.0f, proj[2][2], proj[3][2]);
    bindVisibility(setup, scene, viewProj, t);
    setup.set(RTGI_VISIBILITY_LOC_TRIANGLES, t.triangles);
    setup.set(RTGI_VISIBILITY_LOC_FLAGS, 0);
    setup.set(RTGI_VISIBILITY_LOC_CAPACITY, glm::ivec2(int(t.largeCapacity), int(t.nodeCapacity)));
    setup.set(RTGI_VISIBILITY_LOC_PHASE, 1);  // as the 32-bit path's second phase: small triangles only, no appends
    setup.set(RTGI_VISIBILITY_LOC_LAYER2, layer);
    tile.set(RTGI_VISIBILITY_LOC_SIZE, t.size);
    tile.set(RTGI_VISIBILITY_LOC_FLAGS, 0);
    tile.set(RTGI_VISIBILITY_LOC_LAYER2, layer);
    bindRasterBuffers(t);
    const float none = std::numeric_limits<float>::max();
    glClearTexImage(layer2.id(), 0, GL_RED, GL_FLOAT, &none);
    glBindImageTexture(RTGI_VISIBILITY_IMG_LAYER1, layer1.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    // R32F and R32UI are compatible by size (GL 4.5 table 8.27): atomics on the float bits.
    glBindImageTexture(RTGI_VISIBILITY_IMG_LAYER2, layer2.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    // Producers: the clear above; visibility.resolve's image stores into layer1;
    // the bins of rasterizeVisibility (storage buffers).
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    dispatchSetup(setup, t);
    dispatchTiles(tile, t.size);
    glBindImageTexture(RTGI_VISIBILITY_IMG_LAYER1, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    glBindImageTexture(RTGI_VISIBILITY_IMG_LAYER2, 0, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
}

void copyVisibilityDepth(gl::ProgramCache& programs, VisibilityTarget& t, const gl::Texture& depth, int layer) {
    gl::FramebufferHandle& fbo = t.depthFbos[{depth.id(), layer}];
    if (!fbo) {
        GLuint f = 0;
        glCreateFramebuffers(1, &f);
        fbo = gl::FramebufferHandle(f);
        fbo.label(t.label + ".depth_fbo" + (layer >= 0 ? std::to_string(layer) : std::string()));
        if (layer >= 0)
            glNamedFramebufferTextureLayer(f, GL_DEPTH_ATTACHMENT, depth.id(), 0, layer);
        else
            glNamedFramebufferTexture(f, GL_DEPTH_ATTACHMENT, depth.id(), 0);
        glNamedFramebufferDrawBuffer(f, GL_NONE);
        if (glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw std::runtime_error(t.label + ": depth copy framebuffer incomplete");
    }
    const gl::Program& prog = programs.raster("view/fullscreen.vert", "visibility/depth_copy.frag", visibilityDefines(t));
    prog.set(RTGI_VISIBILITY_LOC_SIZE, t.size);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_VISIBILITY_SSBO_VISBUF, t.vis.id());
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    glViewport(0, 0, t.size.x, t.size.y);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glUseProgram(prog.id());
    if (!t.emptyVao) {
        GLuint vao = 0;
        glCreateVertexArrays(1, &vao);
        t.emptyVao = gl::VertexArrayHandle(vao);
        t.emptyVao.label(t.label + ".empty_vao");
    }
    glBindVertexArray(t.emptyVao.id());
    gl::Profiler::noteDispatch();
    auto scope = gl::Profiler::dispatchScope(prog.name());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glDepthFunc(GL_LESS);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace rtgi
