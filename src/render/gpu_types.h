#pragma once
// C++ view of compute/lib/shared.h: the structs the GPU sees, size-checked.
#include <glm/glm.hpp>

#include <cstdint>

#include "compute/lib/shared.h"
#include "compute/lib/scene_shared.h"

namespace rtgi::gpu {
static_assert(sizeof(FrameUniforms) == 8 * 64 + 7 * 16, "FrameUniforms must match std140 layout");
static_assert(sizeof(GpuMaterial) == 48);
static_assert(sizeof(GpuLight) == 64);
static_assert(sizeof(GpuLightShape) == 48);
static_assert(sizeof(MovableVertex) == 32);
static_assert(sizeof(ObjectTransform) == 9 * 16);
}  // namespace rtgi::gpu
