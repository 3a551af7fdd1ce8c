// Structs and binding indices shared by C++ and GLSL (std140 / std430).
// C++ includes this through src/render/gpu_types.h, which static_asserts the
// sizes; GLSL includes it as "lib/shared.h" (RTGI_GLSL is defined there).
#ifndef RTGI_SHARED_H
#define RTGI_SHARED_H

#ifdef RTGI_GLSL
#define RTGI_STRUCT(name) struct name
#else
#define RTGI_STRUCT(name) struct alignas(16) name
namespace rtgi::gpu {
using mat4 = glm::mat4;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;
using uint = std::uint32_t;
#endif

// ---- binding points used by every pass --------------------------------------
#define RTGI_UBO_FRAME 0        // FrameUniforms
#define RTGI_SSBO_MATERIALS 1   // GpuMaterial[]
#define RTGI_SSBO_LIGHTS 2      // GpuLight[]
#define RTGI_TEX_MATERIALS 0    // sampler2DArray of base-colour textures (raster passes)
#define RTGI_SSBO_LOCAL_SHADOW_MATRICES 10  // mat4[]: world -> clip of every local-light shadow layer
#define RTGI_SSBO_LIGHT_SHAPES 11  // GpuLightShape[], parallel to the real-time GpuLight[] (post/direct.comp)
#define RTGI_ATTR_POSITION 0
#define RTGI_ATTR_NORMAL 1
#define RTGI_ATTR_UV 2
#define RTGI_ATTR_MATERIAL 3
#define RTGI_ATTR_PREV_POSITION 4  // the position the previous frame rendered (object motion)

// Per-frame camera and lighting constants (std140).
RTGI_STRUCT(FrameUniforms) {
    mat4 view;
    mat4 proj;
    mat4 viewProj;
    mat4 invView;
    mat4 invProj;
    mat4 prevViewProj;
    mat4 prevView;
    mat4 shadowViewProj;  // world -> shadow clip (light's orthographic frustum)
    vec4 cameraPos;       // xyz world position, w = 1
    vec4 sunDirection;    // xyz: unit vector towards the sun (world), w = 1 when a sun exists
    vec4 sunIrradiance;   // rgb: E⊥ of the sun (colour × intensity), a = shadow bias (world units)
    vec4 sky;             // rgb: constant sky radiance; a = exposure
    vec4 projParams;      // near, far, tan(fovY/2), aspect
    ivec4 size;           // width, height, frame index, camera cut (1) or not (0)
    ivec4 counts;         // x: scene point/spot lights (the reference's), y: material count, z: flags,
                          // w: lights of the real-time path (x scene lights, then the emissive-region lights)
};

// Material table (std430): index stored per vertex.
RTGI_STRUCT(GpuMaterial) {
    vec4 baseColor;  // linear rgb, a = alpha
    vec4 emissive;   // rgb radiance, a: 1 = emits from both sides (glTF doubleSided), 0 = front face only
    vec4 params;     // x roughness, y metallic, z texture layer (-1 none), w unused
};

// Point / spot lights (std430). Directional lights live in FrameUniforms.
RTGI_STRUCT(GpuLight) {
    vec4 positionRange;   // xyz world position, w range (0 = infinite)
    vec4 colorIntensity;  // rgb colour × intensity (W/sr; area: Le·A)
    vec4 directionType;   // xyz direction the light travels (area: its normal), w: type (0: culled this frame)
    vec4 cone;            // cos(inner), cos(outer), first shadow layer (−1: none), shadow texel size per unit distance
};

// Extent of a real-time local light (std430), parallel to its GpuLight:
// area lights are the rectangle centre ± halfU ± halfV (docs/lights.md
// "Emissive regions as area lights"); point and spot lights a sphere of
// radius centerRadius.w (0: punctual, hard shadows).
RTGI_STRUCT(GpuLightShape) {
    vec4 centerRadius;  // xyz rectangle centre (area lights), w: source radius (point/spot; area: 0)
    vec4 halfU;         // xyz half extent along the rectangle's first axis, w: shadow far plane (near = far/1000)
    vec4 halfV;         // xyz half extent along its second axis (halfU × halfV along the emitting normal), w: soft-shadow rays per side, 4 or 2 (0: 4)
};

#define RTGI_LIGHT_POINT 1
#define RTGI_LIGHT_SPOT 2
#define RTGI_LIGHT_AREA 3  // emissive region: I0 = Le·A along the normal, max(cos, 0) lobe

#ifndef RTGI_GLSL
}  // namespace rtgi::gpu
#endif
#endif
