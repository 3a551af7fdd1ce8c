#pragma once
// Resources shared between passes (a typed blackboard, no string lookups).
// The pass that produces a resource allocates it in its execute() through
// Texture::ensure (so a pass that is not in the frame allocates nothing);
// consumers test it (`if (res.ao)`) or declare it in reads() so the frame
// checks the order when it is built.
#include "gl/resources.h"
#include "render/gpu_types.h"

#include <glm/glm.hpp>

#include <vector>

namespace rtgi {

struct GBuffer {
    gl::Texture depth;       // D32F, rasterizer depth
    gl::Texture linearDepth; // R32F, positive view-space distance along -z (0 = sky)
    gl::Texture normal;      // RGBA16F, view-space unit normal (xyz), a = 1 for geometry
    gl::Texture albedo;      // RGBA8, linear base colour
    gl::Texture material;    // RGBA8, r roughness, g metallic
    gl::Texture emissive;    // R11F_G11F_B10F, emitted radiance
    gl::Texture velocity;    // RG16F, previous − current projected position in UV
};

struct FrameResources {
    GBuffer gbuffer;

    // shadow (sun)
    gl::Texture shadowMap;     // D32F
    glm::mat4 shadowViewProj{1.0f};

    // local lights (render/lights.h): this frame's GpuLight list of the
    // real-time path (culled ones have type 0), the world -> clip matrix of
    // every shadow layer, and the layered depth maps (shadow.local).
    gl::Buffer localLights;          // GpuLight[] (bound at RTGI_SSBO_LIGHTS by the real-time passes)
    int localLightCount = 0;
    int localLightsCulled = 0;       // this frame: outside the view (influence sphere) or zero intensity
    gl::Buffer localShadowMatrices;  // mat4[] per layer
    struct LocalShadowView {
        glm::mat4 viewProj;
        int light, layer;
        float tanHalfFov;  // of the square perspective frustum
    };
    std::vector<LocalShadowView> localShadowViews;  // layers rendered this frame
    std::vector<gpu::GpuLight> localLightsCpu;      // the uploaded list (lpv.rsm reads the lights' data)
    std::vector<LocalShadowView> localRsmViews;     // RSM faces of the kept local lights (LPV on), lpv.rsm size
    gl::Texture localShadowMaps;     // D32F 2D array, compare mode

    // lighting
    gl::Texture direct;           // RGBA16F, direct sun/punctual + emissive radiance
    gl::Texture indirectDiffuse;  // RGBA16F, outgoing indirect diffuse radiance (LPV, near-field)
    gl::Texture specular;         // RGBA16F, indirect specular radiance (LPV specular, SSR)
    gl::Texture ao;               // R16F full resolution, final filtered AO (1 = unoccluded)
    gl::Texture bentNormal;       // RGBA16F view-space bent normal (xyz) + AO (w), or empty
    gl::Texture s3ho;             // RGBA16F SH visibility (band 0-1), or empty
    gl::Texture specularOcclusion;// R16F SSR confidence (1 = hit), or empty
    gl::Texture brdfLut;          // RG16F split-sum LUT (NdotV x roughness), made once by the brdf_lut pass
    gl::Texture blueNoise;        // RGBA8 64x64x8 2D array: 4 blue-noise channels, 8 per-frame variants (render/noise.h)
    // Frame index at which indirectDiffuse was last written by its producer
    // (lpv.apply); ao.nearfield adds into it only when it is this frame's.
    unsigned indirectDiffuseFrame = ~0u;

    // output
    gl::Texture hdr;       // RGBA16F composed radiance
    gl::Texture ldr;       // RGBA8 tonemapped, sRGB-encoded
    gl::Texture history;   // RGBA16F previous frame's hdr (only when a pass reads it)
    gl::Texture diffuseHistory;  // RGBA16F previous frame's diffuse-only radiance (ssr.diffuse_history)
    bool historyValid = false;
};

}  // namespace rtgi
