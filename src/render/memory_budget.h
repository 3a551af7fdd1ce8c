#pragma once
// GPU memory budget: before the first frame allocates anything, the memory
// of every resource the configured frame will create is estimated from the
// settings, the resolution and the passes in the frame (the same formats and
// sizes the passes give their textures; checked against the ledger by
// gpu/memory budget tests), added to what is already allocated (the GPU
// scene), and compared with the memory the device has. Over budget, the run
// stops with a ConfigError (exit 2) naming the memory needed and the setting
// that costs the most, instead of a driver abort or a host swapping for
// minutes (issue 16: lpv.grid=512 grew to 17.5 GB on llvmpipe).
#include <glm/glm.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rtgi {

class Renderer;

struct MemoryItem {
    std::string setting;  // what the user changes to shrink it: "--res 1920x1080", "lpv.grid=32", ...
    std::int64_t bytes = 0;
};

struct MemoryEstimate {
    std::vector<MemoryItem> items;  // one per setting, largest first
    // The passes' private textures by ledger label (summed over cascades), a part of `items`.
    std::map<std::string, std::int64_t> privateTextures;
    std::int64_t total() const;
};

// Estimate for a configured renderer at `resolution` (the resources its
// passes create in execute(), plus what the ledger already holds).
MemoryEstimate estimateFrameMemory(const Renderer& renderer, glm::ivec2 resolution);

struct DeviceMemory {
    std::int64_t bytes = 0;
    std::string source;  // "--max-memory", "GL_NVX_gpu_memory_info", "GL_ATI_meminfo", "default"
};
// Available memory: `override` (> 0, from --max-memory) wins; otherwise what
// the driver reports (NVX_gpu_memory_info: current available video memory;
// ATI_meminfo: free texture memory); otherwise the documented default
// kDefaultMemoryBudget, capped by half of the host's MemAvailable (software
// renderers such as llvmpipe allocate in host memory). Needs a current GL context.
DeviceMemory availableDeviceMemory(std::int64_t override);
constexpr std::int64_t kDefaultMemoryBudget = std::int64_t(4) << 30;

// Throws ConfigError when the estimate exceeds `available`.
void checkMemoryBudget(const MemoryEstimate& estimate, const DeviceMemory& available);

// The hook: estimate + query + check in one call (rtgi-bench calls it before
// the first frame of every run).
void checkMemoryBudget(const Renderer& renderer, glm::ivec2 resolution, std::int64_t maxMemoryOverride);

std::string formatBytes(std::int64_t bytes);

}  // namespace rtgi
