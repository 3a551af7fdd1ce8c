#pragma once
// The foundation's passes (one file each).
#include "render/pass.h"

#include <memory>

namespace rtgi {
std::unique_ptr<Pass> makeGBufferPass();
std::unique_ptr<Pass> makeShadowPass();
std::unique_ptr<Pass> makeDirectPass();
std::unique_ptr<Pass> makeComposePass();
// Split-sum BRDF LUT (RG16F, x = n·v, y = roughness at texel centres), made
// once when SSR or LPV specular runs.
std::unique_ptr<Pass> makeBrdfLutPass();
constexpr int kBrdfLutSize = 64;       // texels per side
constexpr int kBrdfLutSamples = 4096;  // GGX importance samples per texel

// The direct-light and composition dispatches, shared by the direct and
// post.compose passes and by ssr.diffuse_history (diffuseOnly: no specular
// lobe, no specular term, no tonemapping; target RGBA16F).
void dispatchDirect(FrameContext& ctx, const gl::Texture& target, bool diffuseOnly);
void dispatchCompose(FrameContext& ctx, const gl::Texture& direct, const gl::Texture& hdr, const gl::Texture* ldr,
                     bool diffuseOnly);

// Light-space orthographic view-projection that encloses `box` seen from a
// light travelling along -towardLight (used by the shadow map and the RSM).
glm::mat4 orthoLightViewProj(const Aabb& box, glm::vec3 towardLight);
}  // namespace rtgi
