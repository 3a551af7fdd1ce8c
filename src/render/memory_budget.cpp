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
#include "render/ssr/ssr_constants.h"
#include "scene/bvh.h"
#include "scene/emitters.h"

#include <algorithm>
#include <cstdio>
#include <map>

namespace rtgi {

namespace {

// A BVH of the scene's triangles (the reference's, lpv.visibility's): every
// triangle once in leaf order and at most 2n - 1 nodes (scene/bvh.h, buildBvh).
double bvhBytesBound(std::int64_t triangles) {
    const double n = double(std::max<std::int64_t>(triangles, 1));
    return n * double(sizeof(gpu::BvhTriangle)) + (2.0 * n - 1.0) * double(sizeof(gpu::BvhNode));
}

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
    // The passes' private textures: the descriptors their execute() allocates
    // from (Pass::privateTextures); the LPV's volumes go to lpv.grid, the
    // screen-sized targets of AO, SSR, the reference and lpv.apply to --res.
    const std::string gridKey = s.lpv.grid.x == s.lpv.grid.y && s.lpv.grid.y == s.lpv.grid.z
                                    ? std::to_string(s.lpv.grid.x)
                                    : std::to_string(s.lpv.grid.x) + "x" + std::to_string(s.lpv.grid.y) + "x" +
                                          std::to_string(s.lpv.grid.z);
    MemoryEstimate e;
    for (auto& p : r.passes()) {
        const bool volume = p->name().rfind("lpv.", 0) == 0 && p->name() != "lpv.apply";
        for (auto& t : p->privateTextures(s, res)) {
            const std::int64_t bytes = gl::textureBytes(t.desc);
            e.privateTextures[t.label] += bytes;
            by[volume ? "lpv.grid=" + gridKey : resKey] += double(bytes);
        }
    }
    const std::string fixedKey = "the scene (" + std::to_string(r.scene().triangleCount()) + " triangles)";
    // The blue noise of the screen-space estimators, ao.nearfield and the SSR tracer (ao.rtao draws its own).
    const bool screenSpaceAo = hasFamily(r, "ao.") && s.ao.variant != AoSettings::Variant::Rtao;
    if (screenSpaceAo || hasFamily(r, "ao.nearfield") || hasFamily(r, "ssr."))
        by[fixedKey] += double(gl::textureBytes(blueNoiseDesc()));
    // The AoParams block: one for the AO chain, one for ao.nearfield's own.
    for (auto& p : r.passes())
        if (p->name() == "ao.nearfield" || p->name() == "ao." + std::string(toString(s.ao.variant)))
            by[fixedKey] += double(sizeof(gpu::AoParams));
    if (hasFamily(r, "ssr.")) by[fixedKey] += double(sizeof(gpu::SsrUniforms));
    // The reference: its BVH, the emitter table (two words per emissive
    // triangle, at least one entry) and one ray counter per sample.
    const std::int64_t triangleCount = std::int64_t(r.scene().triangleCount());
    if (hasFamily(r, "ref.")) {
        const std::size_t emitters = emissiveTriangles(r.scene(), resolveMaterials(r.scene(), s)).size();
        by[fixedKey] += bvhBytesBound(triangleCount) + 8.0 * double(std::max<std::size_t>(emitters, 1)) +
                        4.0 * double(s.reference.spp);
    }
    // ao.rtao: its own BVH of the scene (as lpv.visibility's).
    if (hasFamily(r, "ao.rtao")) by[fixedKey] += bvhBytesBound(triangleCount);

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
        // The volumes are private textures (above). lpv.visibility traces
        // against one BVH of the scene (docs/lpv.md, "Visibility moments").
        const int cascades = s.lpv.path == LpvSettings::Path::Raster ? 1 : s.lpv.cascades;
        if (hasFamily(r, "lpv.visibility")) by["lpv.grid=" + gridKey] += bvhBytesBound(triangleCount);
        // The uniform block of every cascade and the two dropped-texel counters.
        by[fixedKey] += double(cascades) * double(sizeof(gpu::LpvUniforms)) + 8.0;
        // The sun's RSM and one layer per face of every local light (spot 1,
        // point / area 6, render/lights.h) at FrameResources::localRsmSize in
        // the local RSM arrays, and lpv.inject's face list (at most every face
        // once for the frame's volumes and once per cascade's injection
        // cache): what lpv.rsm and lpv.inject allocate.
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
                double(faces) * (rsmBytes(ln) + double(1 + cascades) * double(sizeof(gpu::LpvRsmFace)));
    }
    // What the renderer holds already (the GPU scene, for one: vertices,
    // indices, BVH, textures) and the small fixed resources.
    auto& ledger = const_cast<Renderer&>(r).ledger();
    by["the scene (" + std::to_string(r.scene().triangleCount()) + " triangles)"] += double(ledger.total());

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
