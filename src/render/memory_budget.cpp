#include "render/memory_budget.h"

#include "gl/context.h"

#include "render/visibility/visibility.h"

#include "render/lights.h"
#include "render/lpv/lpv_math.h"
#include "render/lpv/lpv_passes.h"
#include "render/lpv/lpv_volumes.h"
#include "render/gpu_scene.h"
#include "render/noise.h"
#include "render/ao/ao_params.h"
#include "render/renderer.h"

#include <algorithm>
#include <cstdio>
#include <map>

namespace rtgi {

namespace {

// Private screen-sized targets of the pass families (bytes per pixel; the
// shared ones are counted from their descriptors, Renderer::sharedTextureDesc).
// AO at its own resolution: half depth 4, half normal 8, radius scale 2 and
// colour 4, raw 2, blur temporary + output 4, temporal value and depth (two
// each) 12; at full resolution: near-field 4.
constexpr double kAoBytesPerAoPixel = 36, kAoBytesPerPixel = 4;
// SSR at the trace resolution: hit 4, confidence 2, distance 2, trace depth 4
// and normal 8, resolved 8, blur temporary + output 16, temporal value and
// depth (two each) 24; full resolution: HiZ with mips 4 * 4/3, direct-diffuse temporary 8.
constexpr double kSsrBytesPerTracePixel = 68, kSsrBytesPerPixel = 8 + 4.0 * 4 / 3;
// Reference: mean, standard error, accumulation and its square (RGBA32F), ldr.
constexpr double kReferenceBytesPerPixel = 68;
bool hasFamily(const Renderer& r, const std::string& prefix) {
    for (auto& p : r.passes())
        if (p->name().rfind(prefix, 0) == 0) return true;
    return false;
}

std::string resolutionText(glm::ivec2 s) { return std::to_string(s.x) + "x" + std::to_string(s.y); }

}  // namespace

std::int64_t MemoryEstimate::total() const {
    std::int64_t t = 0;
    for (auto& i : items) t += i.bytes;
    return t;
}

std::string formatBytes(std::int64_t bytes) {
    char buf[48];
    double b = double(bytes);
    if (b >= 1024.0 * 1024 * 1024)
        std::snprintf(buf, sizeof buf, "%.1f GiB", b / (1024.0 * 1024 * 1024));
    else
        std::snprintf(buf, sizeof buf, "%.1f MiB", b / (1024.0 * 1024));
    return buf;
}

MemoryEstimate estimateFrameMemory(const Renderer& r, glm::ivec2 res) {
    const Settings& s = r.settings();
    std::map<std::string, double> by;  // setting -> bytes
    const double pixels = double(res.x) * double(res.y);
    auto half = [](glm::ivec2 v) { return double(std::max((v.x + 1) / 2, 1)) * double(std::max((v.y + 1) / 2, 1)); };
    const std::string resKey = "--res " + resolutionText(res);

    // Shared resources: the descriptors the renderer allocates from.
    for (int i = 0; i < R::count; ++i) {
        const Resource res_i{i};
        if (!r.plan().written(res_i)) continue;
        const ResourceDesc& d = resourceDesc(res_i);
        const double bytes = double(gl::textureBytes(r.sharedTextureDesc(res_i, res)));
        switch (d.extent) {
            case Extent::view: case Extent::ao: by[resKey] += bytes; break;
            case Extent::shadow: by["shadow.size=" + std::to_string(s.light.shadowSize)] += bytes; break;
            case Extent::localShadow:
                by["shadow.local_size=" + std::to_string(s.light.localShadowSize) + " (" +
                   std::to_string(r.resources().localShadowLayers) + " local shadow layers)"] += bytes;
                break;
            case Extent::brdfLut: by["the scene (" + std::to_string(r.scene().triangleCount()) + " triangles)"] += bytes; break;
        }
    }
    double screen = 0;
    if (hasFamily(r, "ao.nearfield")) screen += kAoBytesPerPixel * pixels;
    if (hasFamily(r, "ao.")) screen += kAoBytesPerAoPixel * (s.ao.halfResolution ? half(res) : pixels);
    if (hasFamily(r, "ssr.")) screen += kSsrBytesPerPixel * pixels + kSsrBytesPerTracePixel * (s.ssr.halfResolution ? half(res) : pixels);
    if (hasFamily(r, "ref.")) screen += kReferenceBytesPerPixel * pixels;
    by[resKey] += screen;
    const std::string fixedKey = "the scene (" + std::to_string(r.scene().triangleCount()) + " triangles)";
    if (hasFamily(r, "ao.") || hasFamily(r, "ssr.")) by[fixedKey] += double(gl::textureBytes(blueNoiseDesc()));
    if (hasFamily(r, "ao.")) by[fixedKey] += double(sizeof(gpu::AoParams));

    // The compute rasterizer's visibility buffer and bins, per rasterized view
    // (src/render/visibility/visibility.cpp, visibilityCapacity).
    const std::int64_t triangles = std::int64_t(r.scene().triangleCount());
    auto visibility = [&](glm::ivec2 size) { return double(visibilityCapacity(size, triangles, s.raster.binScale).bytes); };
    if (hasFamily(r, "visibility.")) by[resKey] += visibility(res);
    if (hasFamily(r, "shadow.raster"))
        by["shadow.size=" + std::to_string(s.light.shadowSize)] += visibility(glm::ivec2(s.light.shadowSize));
    if (hasFamily(r, "shadow.local")) {
        // The D32F array is a shared resource (above); on the compute path,
        // one visibility target reused for every face.
        const int n = s.light.localShadowSize;
        if (useComputeRasterLightViews(s)) by["shadow.local_size=" + std::to_string(n)] += visibility(glm::ivec2(n));
    }
    if (hasFamily(r, "lpv.") && useComputeRasterLightViews(s)) by["lpv.rsm=" + std::to_string(s.lpv.rsm)] += visibility(glm::ivec2(s.lpv.rsm));
    if (hasFamily(r, "lpv.")) {
        const glm::dvec3 g(s.lpv.grid);
        const double cells = g.x * g.y * g.z, geometryCells = (g.x + 1) * (g.y + 1) * (g.z + 1);
        const double fmt = s.lpv.format == LpvSettings::Format::Rgba32f ? 16.0 : 8.0;
        // src/render/lpv/lpv_volumes.cpp: inject 3 x R32F x 4 (fp32 accumulation),
        // two propagation steps and the accumulation (3 channels each), the
        // temporal history (two, when lpv.temporal > 0); geometry volume
        // (grid + 1)^3: 11 R32F accumulation channels, the SH in the volume
        // format, albedo and two-sided axis blocking RGBA16F.
        // Per cascade (lpv.cascades, compute path; the raster path has one volume); cascades
        // i > 0 keep a near part (3 channels). lpv.sh_order=2 adds per volume 4 more textures
        // (coefficients 4-7 of r, g, b and 8 of r, g, b) and the fp32 accumulation of
        // coefficients 4-8 (15 R32F) (docs/lpv.md, "Second-order SH").
        const int cascades = s.lpv.path == LpvSettings::Path::Raster ? 1 : s.lpv.cascades;
        const double volumeTextures = s.lpv.shOrder == 2 ? 7.0 : 3.0;
        const double injectBytes = s.lpv.shOrder == 2 ? 108.0 : 48.0;
        // Geometry per corner: 8 R32F channels, the SH, albedo RGBA16F; two-sided blocking adds 3 R32F
        // channels and the axes RGBA16F (only then allocated).
        const bool twoSided = s.lpv.blocking == LpvSettings::Blocking::TwoSided;
        const double geometryBytes = twoSided ? 44.0 + fmt + 16.0 : 32.0 + fmt + 8.0;
        double lpv = cascades * (cells * (injectBytes + 3.0 * volumeTextures * fmt) + geometryCells * geometryBytes) +
                     (cascades - 1) * cells * volumeTextures * fmt;
        // lpv.visibility (docs/lpv.md, "Visibility moments", "Sky visibility"): per cascade the moments
        // (N^2 RG16F per cell) and the sky visibility (RGBA16F per cell), and one BVH of the scene
        // (48 bytes per triangle, at most 2 nodes of 32 bytes per triangle).
        const bool moments = s.lpv.lookup == LpvSettings::Lookup::Visibility ||
                             (s.lpv.blocking == LpvSettings::Blocking::Visibility && s.lpv.path == LpvSettings::Path::Compute);
        const bool sky = s.lpv.sky == LpvSettings::Sky::Visibility;
        if (moments) lpv += cascades * cells * RTGI_LPV_VIS_RES * RTGI_LPV_VIS_RES * 4.0;
        if (sky) lpv += cascades * cells * 8.0;
        if (moments || sky) lpv += double(r.scene().triangleCount()) * (48.0 + 64.0) + 64.0;
        // Temporal: two histories per cascade, and two of the near part for cascades i > 0.
        if (s.lpv.temporal > 0.0f) lpv += (2.0 * cascades - 1.0) * cells * 2.0 * volumeTextures * fmt;
        std::string gridKey = s.lpv.grid.x == s.lpv.grid.y && s.lpv.grid.y == s.lpv.grid.z
                                  ? std::to_string(s.lpv.grid.x)
                                  : std::to_string(s.lpv.grid.x) + "x" + std::to_string(s.lpv.grid.y) + "x" +
                                        std::to_string(s.lpv.grid.z);
        by["lpv.grid=" + gridKey] += lpv;
        // The uniform block of every cascade and the dropped-texel counter;
        // lpv.apply's two running sums over cascades.
        by[fixedKey] += double(cascades) * double(sizeof(gpu::LpvUniforms)) + 4.0;
        // lpv.apply_resolution=half: the sums at half size, plus the low outputs and geometry.
        const bool halfApply = s.lpv.halfApply && hasFamily(r, "lpv.apply");
        const glm::ivec2 applyRes = halfApply ? lpv::applyHalfSize(res) : res;
        if (cascades > 1 && hasFamily(r, "lpv.apply"))
            by[resKey] += 2.0 * double(gl::textureBytes(lpv::applySumDesc(applyRes)));
        if (halfApply)
            by[resKey] += double(gl::textureBytes(lpv::applyLowGeometryDesc(res))) +
                          (lpvSpecularActive(r.scene(), s) ? 2.0 : 1.0) * double(gl::textureBytes(lpv::applyLowDesc(res)));
        // The sun's RSM and one per face of every local light (spot 1, point
        // / area 6, render/lights.h) at FrameResources::localRsmSize, each
        // with one LPV uniform block per cascade: the descriptors lpv.rsm
        // allocates from.
        auto rsmBytes = [](int n) {
            const lpv::RsmDescs d = lpv::rsmDescs(n);
            return double(gl::textureBytes(d.flux) + gl::textureBytes(d.normal) + gl::textureBytes(d.depth));
        };
        if (resolveSun(r.scene(), s)) by["lpv.rsm=" + std::to_string(s.lpv.rsm)] += rsmBytes(s.lpv.rsm);
        const int faces = hasFamily(r, "lpv.rsm") ? r.localLights().faces : 0;
        const int ln = r.resources().localRsmSize;
        if (faces > 0)
            by["local lights (" + std::to_string(faces) + " RSM faces of " + std::to_string(ln) + "^2; light.budget=" +
               std::to_string(s.light.budget) + ")"] +=
                double(faces) * (rsmBytes(ln) + double(cascades) * double(sizeof(gpu::LpvUniforms)));
    }
    // What the renderer holds already (the GPU scene, for one: vertices,
    // indices, BVH, textures) and the small fixed resources.
    auto& ledger = const_cast<Renderer&>(r).ledger();
    by["the scene (" + std::to_string(r.scene().triangleCount()) + " triangles)"] += double(ledger.total());

    MemoryEstimate e;
    for (auto& [k, v] : by) e.items.push_back({k, std::int64_t(std::min(v, 9.0e18))});
    std::sort(e.items.begin(), e.items.end(), [](auto& a, auto& b) { return a.bytes > b.bytes; });
    return e;
}

void checkMemoryBudget(const MemoryEstimate& e, const DeviceMemory& avail) {
    std::int64_t need = e.total();
    if (need <= avail.bytes) return;
    const MemoryItem& top = e.items.front();
    throw ConfigError("the frame needs an estimated " + formatBytes(need) + " of GPU memory, more than the " +
                      formatBytes(avail.bytes) + " available (" + avail.source + "); the largest part is " +
                      top.setting + " with " + formatBytes(top.bytes) +
                      ": lower it, or raise the budget with --max-memory if the device has the memory");
}

void checkMemoryBudget(const Renderer& renderer, glm::ivec2 resolution, std::int64_t maxMemoryOverride) {
    checkMemoryBudget(estimateFrameMemory(renderer, resolution), availableDeviceMemory(maxMemoryOverride));
}

DeviceMemory availableDeviceMemory(std::int64_t override) {
    if (override > 0) return {override, "--max-memory"};
    using gl::hasExtension;
    // Enum values from the extension specifications (not in the generated loader).
    constexpr GLenum kNvxCurrentAvailableVidmem = 0x9049;  // GL_GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX, KiB
    constexpr GLenum kAtiTextureFreeMemory = 0x87FC;       // GL_TEXTURE_FREE_MEMORY_ATI, [0] = KiB free
    if (hasExtension("GL_NVX_gpu_memory_info")) {
        GLint kib = 0;
        glGetIntegerv(kNvxCurrentAvailableVidmem, &kib);
        if (glGetError() == GL_NO_ERROR && kib > 0) return {std::int64_t(kib) * 1024, "reported by GL_NVX_gpu_memory_info"};
    }
    if (hasExtension("GL_ATI_meminfo")) {
        GLint v[4] = {0, 0, 0, 0};
        glGetIntegerv(kAtiTextureFreeMemory, v);
        if (glGetError() == GL_NO_ERROR && v[0] > 0) return {std::int64_t(v[0]) * 1024, "reported by GL_ATI_meminfo"};
    }
    // No report (Mesa llvmpipe among others): the documented default, and
    // never more than the host can give a software renderer.
    std::int64_t host = std::int64_t(sceneHostMemoryLimit());
    if (host < kDefaultMemoryBudget)
        return {host, "no driver report: the 4 GiB default, capped at half of the host's available memory"};
    return {kDefaultMemoryBudget, "no driver report: the 4 GiB default"};
}

}  // namespace rtgi
