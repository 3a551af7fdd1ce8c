#pragma once
// The foundation's passes (one file each).
#include "gl/program.h"
#include "render/pass.h"

#include <memory>

namespace rtgi {
std::unique_ptr<Pass> makeGBufferPass();
std::unique_ptr<Pass> makeShadowPass();
std::unique_ptr<Pass> makeLocalShadowPass();  // shadow.local: spot / point / area-light depth maps
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

// The one way the scene is rasterized (G-buffer, shadow map, RSM): binds
// `fbo`, sets the full raster state (depth test, no blending, no culling —
// scenes may be open and normals are flipped for back faces — optional
// slope-scaled depth bias), clears `colorTargets` colour attachments to 0 and
// depth to 1, draws the whole scene with `prog`, and unbinds.
void rasterizeScene(FrameContext& ctx, const gl::Program& prog, GLuint fbo, glm::ivec2 size, int colorTargets,
                    bool depthBias = false);

// Depth of the scene seen through viewProj into the depth attachment of
// `fbo` (size²), with the slope-scaled bias of shadow maps: the one call the
// sun's and the local lights' shadow maps go through.
void renderShadowDepth(FrameContext& ctx, const glm::mat4& viewProj, GLuint fbo, glm::ivec2 size);

// shadow.cache: true when the sun's shadow map already holds this frame's
// view of the scene (same light frustum, size, GpuScene::geometryVersion,
// allocation and writer), so the pass may skip drawing; otherwise records the
// new key and returns false. Always false with shadow.cache=off.
bool shadowMapCurrent(FrameContext& ctx, int writer);

// Light-space orthographic view-projection that encloses `box` seen from a
// light travelling along -towardLight (used by the shadow map and the RSM).
glm::mat4 orthoLightViewProj(const Aabb& box, glm::vec3 towardLight);
}  // namespace rtgi
