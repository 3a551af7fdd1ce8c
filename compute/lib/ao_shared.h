// AO family: binding points and the AoParams block shared by C++ and GLSL
// (std140). C++ includes it through src/render/ao/ao_params.h, which
// static_asserts the size; GLSL includes it as "lib/ao_shared.h".
#ifndef RTGI_AO_SHARED_H
#define RTGI_AO_SHARED_H
#ifdef RTGI_GLSL
#include "lib/shared.h"
#else
namespace rtgi::gpu {  // C++: included after compute/lib/shared.h (render/gpu_types.h)
#endif

#define RTGI_UBO_AO 3            // AoParams
#define RTGI_AO_MAX_KERNEL 64    // sphere / hemisphere kernel size (ao.samples <= 64)
#define RTGI_AO_MAX_VO_PAIRS 32  // VO line-sample pairs (2 x 32 = 64 line samples)
#define RTGI_AO_MAX_PROBE 328    // dynamic radius probe (seed 003 4.2.2, K = 328)

// Variant codes (AO_VARIANT define and AoParams.counts.w).
#define RTGI_AO_SSAO_DISK 1
#define RTGI_AO_SSAO_SPHERE 2
#define RTGI_AO_SSAO_HEMISPHERE 3
#define RTGI_AO_VO 4
#define RTGI_AO_HBAO 5
#define RTGI_AO_GTAO 6
#define RTGI_AO_VBAO 7  // visibility bitmask (GTAO slices, 32 sectors, thickness)
#define RTGI_AO_RTAO 8  // rays through the scene's BVH (compute/ao/rtao.comp)

RTGI_STRUCT(AoParams) {
    vec4 radius;   // x R (view units), y second radius (dual), z max occlusion distance (VO: 2R), w tan(angle bias)
    vec4 focal;    // x cot(fovY/2)/aspect, y cot(fovY/2) (eq. 5.3 focal length), z tan(fovY/2), w aspect
    ivec4 counts;  // x samples, y directions (hbao/gtao), z steps per direction, w variant
    ivec4 flags;   // x edge-highlight removal, y hbao uses normals, z gtao multi-bounce, w radius mode (0 fixed, 1 dual, 2..7 dynamic1..6)
    ivec4 size;    // AO resolution (w, h), full resolution (w, h)
    vec4 misc;     // x dual combine (0 product, 1 min), y near-field strength, z VO pair count, w dynamic probe K
    vec4 bitmask;  // vbao: x thickness (< 0 infinite), y 1 = depth-scaled (x * sample depth); rtao: z rays per pixel
    vec4 kernel[RTGI_AO_MAX_KERNEL];    // unit-ball offsets, radial density d(x) = 3/2 (1 - x^2) (seed 003 5.5)
    vec4 voSamples[RTGI_AO_MAX_VO_PAIRS]; // xy disk position, z half-length z_s, w volume weight / sum
    vec4 probe[RTGI_AO_MAX_PROBE];      // xy Poisson-disk offsets in the unit disk (dynamic radius probe)
};

#ifndef RTGI_GLSL
}  // namespace rtgi::gpu
#endif

// ---- slots of compute/ao/ (docs/architecture.md, "Binding slots") ----
// RTGI_<FAMILY>[_<PASS>]_<TEX|IMG|LOC|SSBO>_<ROLE>; the pass appears only where the
// family's passes give the same role different slots.
// texture units (sampler bindings)
#define RTGI_AO_TEX_DEPTH            0  // ao/ao.comp ao/downsample.comp ao/nearfield.comp ao/radius.comp
#define RTGI_AO_TEX_NORMAL           1  // ao/ao.comp ao/downsample.comp ao/nearfield.comp ao/radius.comp
#define RTGI_AO_ESTIMATE_TEX_NOISE   2  // ao/ao.comp
#define RTGI_AO_TEX_RADIUS_SCALE     3  // ao/ao.comp
#define RTGI_AO_TEX_SHADOW_MAP       4  // ao/ao.comp
#define RTGI_AO_ESTIMATE_TEX_ALBEDO  5  // ao/ao.comp
#define RTGI_AO_ESTIMATE_TEX_DEPTH2  6  // ao/ao.comp (gbuffer.linearDepth2, AO_SECOND_LAYER)
#define RTGI_AO_NEARFIELD_TEX_ALBEDO 2  // ao/nearfield.comp
#define RTGI_AO_RTAO_TEX_FULL_DEPTH  2  // ao/rtao.comp (the G-buffer's, at half resolution)
#define RTGI_AO_RTAO_TEX_FULL_NORMAL 3  // ao/rtao.comp
#define RTGI_AO_TEX_MATERIAL         3  // ao/nearfield.comp
#define RTGI_AO_TEX_HISTORY          4  // ao/nearfield.comp
#define RTGI_AO_TEX_VELOCITY         5  // ao/nearfield.comp
#define RTGI_AO_NEARFIELD_TEX_NOISE  6  // ao/nearfield.comp
// image units
#define RTGI_AO_IMG_AO          0  // ao/ao.comp
#define RTGI_AO_IMG_DIRECTIONAL 1  // ao/ao.comp
#define RTGI_AO_IMG_HALF_DEPTH  0  // ao/downsample.comp
#define RTGI_AO_IMG_HALF_NORMAL 1  // ao/downsample.comp
#define RTGI_AO_IMG_NEAR_FIELD  0  // ao/nearfield.comp
#define RTGI_AO_IMG_INDIRECT    1  // ao/nearfield.comp
#define RTGI_AO_IMG_SCALE       0  // ao/radius.comp
#define RTGI_AO_IMG_SCALE_COLOR 1  // ao/radius.comp
// uniform locations
#define RTGI_AO_LOC_VIEW_TO_SHADOW 0  // ao/ao.comp
#define RTGI_AO_LOC_SHADOW_TO_VIEW 1  // ao/ao.comp
#define RTGI_AO_LOC_ACCUMULATE     0  // ao/nearfield.comp
#define RTGI_AO_LOC_HISTORY_VALID  1  // ao/nearfield.comp
// ao.rtao: AO pixels per invocation (a block) in x and y at ao.ray_rate r: 1x1, 2x1, 2x2 (docs/ao.md "Sparse rays")
#define RTGI_AO_RTAO_BLOCK_X(r) ((r) == 1 ? 1 : 2)
#define RTGI_AO_RTAO_BLOCK_Y(r) ((r) == 4 ? 2 : 1)
#define RTGI_AO_RTAO_LOC_FILL_DEPTH  0  // ao/rtao.comp (ao.ray_rate > 1): float, relative depth difference
#define RTGI_AO_RTAO_LOC_FILL_NORMAL 1  // ao/rtao.comp (ao.ray_rate > 1): float, minimum normal cosine
#endif
