#pragma once
// Resources shared between passes. Each one is a named field of
// FrameResources and has a typed handle (R::normal, R::ao, ...) that passes
// use to declare what they read, write and accumulate into (render/pass.h).
// The renderer allocates every shared resource that a pass of the frame
// writes, from the resource's descriptor (resourceDesc) and by handle, never
// by label; passes only fill them.
#include "gl/resources.h"
#include "render/gpu_types.h"

#include <cstdint>
#include <glm/glm.hpp>

#include <vector>

namespace rtgi {

// What --check counts on a texture (NaN/Inf always; negatives unless signed).
enum class Check {
    none,         // depth / unorm formats: cannot hold non-finite values
    nonNegative,  // radiance, AO, distances: a negative value is a bug
    signedValues  // normals, velocities, SH coefficients
};

// How big a shared texture is (the renderer derives the size each frame).
enum class Extent {
    view,    // the view's size
    ao,      // the AO chain's resolution (half the view with ao.resolution=half)
    shadow,  // shadow.size squared
    brdfLut,     // kBrdfLutSize squared
    localShadow  // light.local_shadow_size squared, FrameResources::localShadowLayers layers (2D array)
};

// Typed handle of one shared resource: an index into the resource table.
struct Resource {
    int index = -1;
    constexpr bool operator==(const Resource& o) const { return index == o.index; }
    constexpr bool operator<(const Resource& o) const { return index < o.index; }
};

// Every shared resource, in table order (resourceDesc).
namespace R {
inline constexpr Resource depth{0};             // D32F rasterizer depth
inline constexpr Resource linearDepth{1};       // R32F positive view-space distance along -z (0 = sky)
inline constexpr Resource normal{2};            // RGBA16F view-space unit normal (xyz), a = 1 for geometry
inline constexpr Resource albedo{3};            // RGBA8 linear base colour
inline constexpr Resource material{4};          // RGBA8 r roughness, g metallic
inline constexpr Resource emissive{5};          // R11F_G11F_B10F emitted radiance
inline constexpr Resource velocity{6};          // RG16F previous − current projected position in UV
inline constexpr Resource shadowMap{7};         // D32F sun depth map (compare mode on)
inline constexpr Resource direct{8};            // RGBA16F direct sun/punctual + emissive radiance
inline constexpr Resource indirectDiffuse{9};   // RGBA16F outgoing indirect diffuse radiance (LPV, near-field)
inline constexpr Resource specular{10};         // RGBA16F indirect specular radiance (LPV specular, SSR)
inline constexpr Resource ao{11};               // R16F full resolution, final filtered AO (1 = unoccluded)
inline constexpr Resource bentNormal{12};       // RGBA16F view-space bent normal (xyz) + AO (w), AO resolution
inline constexpr Resource s3ho{13};             // RGBA16F SH visibility (bands 0-1), AO resolution
inline constexpr Resource specularOcclusion{14};// R16F SSR confidence (1 = hit)
inline constexpr Resource brdfLut{15};          // RG16F split-sum LUT (NdotV x roughness)
inline constexpr Resource hdr{16};              // RGBA32F composed radiance
inline constexpr Resource ldr{17};              // RGBA8 tonemapped, sRGB-encoded
inline constexpr Resource history{18};          // RGBA16F previous frame's hdr
inline constexpr Resource diffuseHistory{19};   // RGBA16F previous frame's diffuse-only radiance
inline constexpr Resource localShadowMaps{20};  // D32F 2D array, one layer per local-light shadow face (compare mode on)
inline constexpr Resource linearDepth2{21};     // R32F second depth layer (visibility.layer2, ao.second_layer); FLT_MAX = none
inline constexpr int count = 22;
}  // namespace R

// How the renderer allocates a shared resource and how --check reads it.
struct ResourceDesc {
    const char* name;  // label, results, --check, debug images, --print-frame
    GLenum format;
    Extent extent;
    Check check;
    GLenum filter;  // min/mag filter (GL_NEAREST unless a reader interpolates)
};
const ResourceDesc& resourceDesc(Resource r);

struct GBuffer {
    gl::Texture depth, linearDepth, normal, albedo, material, emissive, velocity;
    gl::Texture linearDepth2;  // only with ao.second_layer=on on the compute raster path
};

struct FrameResources {
    GBuffer gbuffer;
    gl::Texture shadowMap;
    glm::mat4 shadowViewProj{1.0f};
    // What the sun's shadow map holds (shadow.cache): the map is redrawn only
    // when the key of this frame differs (render/passes/core_passes.h).
    struct ShadowKey {
        glm::mat4 viewProj{0.0f};
        int size = 0;
        std::uint64_t geometryVersion = ~std::uint64_t(0);
        unsigned allocationEpoch = ~0u;
        int writer = -1;  // which pass drew it (hardware or compute rasterizer)
        bool operator==(const ShadowKey&) const = default;
    } shadowKey;
    gl::Texture direct, indirectDiffuse, specular, ao, bentNormal, s3ho, specularOcclusion, brdfLut;
    gl::Texture hdr, ldr, history, diffuseHistory;
    gl::Texture localShadowMaps;
    // Constant input, not a frame product: made once on first use (render/noise.h).
    gl::Texture blueNoise;  // RGBA8 64x64x8 2D array: 4 blue-noise channels, 8 per-frame variants
    // Incremented whenever the renderer (re)allocates a shared texture: a
    // pass that attaches shared textures to a framebuffer rebuilds it then.
    unsigned allocationEpoch = 0;

    gl::Texture& operator[](Resource r);
    const gl::Texture& operator[](Resource r) const;

    // Local lights (render/lights.h): this frame's GpuLight list of the
    // real-time path (culled and waiting ones have type 0), the world -> clip
    // matrix of every shadow layer (the one its map was drawn with); the
    // layered depth maps are R::localShadowMaps. The light budget
    // (LightSchedule) picks the faces drawn this frame; the others keep their maps.
    gl::Buffer localLights;          // GpuLight[] (bound at RTGI_SSBO_LIGHTS by the real-time passes)
    gl::Buffer localLightShapes;     // GpuLightShape[] parallel to it (RTGI_SSBO_LIGHT_SHAPES, the direct pass)
    gl::SamplerHandle localShadowDepthSampler;  // compare off, nearest: raw depth of localShadowMaps (soft shadows)
    int localLightCount = 0;
    int localLightsCulled = 0;       // this frame: outside the view (influence sphere) or zero intensity
    int localLightsWaiting = 0;      // this frame: kept but a face it needs has no map yet (light budget)
    int localFacesCached = 0;        // this frame: needed faces reused from earlier frames
    int localShadowLayers = 1;       // layers of localShadowMaps (every light at once, so culling never reallocates)
    int localRsmSize = 0;            // side of each local-light RSM face (localRsmSize(), lights.h)
    int localRsmFaces = 0;           // RSM faces of every local light (LocalLights::faces): the layers lpv.rsm allocates
    gl::Buffer localShadowMatrices;  // mat4[] per layer
    struct LocalShadowView {
        glm::mat4 viewProj;
        int light, layer;
        float tanHalfFov;  // of the square perspective frustum
        int face;          // fixed face index (LocalLight::firstFace + k)
        bool valid = false;  // localRsmInject: the map is up to date (ShadowView::valid)
    };
    std::vector<LocalShadowView> localShadowViews;  // shadow layers drawn this frame
    std::vector<gpu::GpuLight> localLightsCpu;      // the uploaded list (lpv.rsm reads the lights' data)
    std::vector<LocalShadowView> localRsmViews;     // RSM faces drawn this frame (localRsmSize)
    std::vector<LocalShadowView> localRsmInject;    // RSM faces injected this frame (every face of the lit lights)
};

}  // namespace rtgi
