#include "render/frame_resources.h"

#include <array>
#include <stdexcept>

namespace rtgi {
namespace {

using C = Check;
using E = Extent;
// In R:: order (checked below).
const std::array<ResourceDesc, R::count> kResources{{
    {"gbuffer.depth", GL_DEPTH_COMPONENT32F, E::view, C::none, GL_NEAREST},
    {"gbuffer.linearDepth", GL_R32F, E::view, C::nonNegative, GL_NEAREST},
    {"gbuffer.normal", GL_RGBA16F, E::view, C::signedValues, GL_NEAREST},
    {"gbuffer.albedo", GL_RGBA8, E::view, C::none, GL_NEAREST},
    {"gbuffer.material", GL_RGBA8, E::view, C::none, GL_NEAREST},
    {"gbuffer.emissive", GL_R11F_G11F_B10F, E::view, C::nonNegative, GL_NEAREST},
    {"gbuffer.velocity", GL_RG16F, E::view, C::signedValues, GL_NEAREST},
    {"shadowMap", GL_DEPTH_COMPONENT32F, E::shadow, C::none, GL_LINEAR},
    {"direct", GL_RGBA16F, E::view, C::nonNegative, GL_NEAREST},
    {"indirectDiffuse", GL_RGBA16F, E::view, C::nonNegative, GL_NEAREST},
    {"specular", GL_RGBA16F, E::view, C::nonNegative, GL_NEAREST},
    {"ao", GL_R16F, E::view, C::nonNegative, GL_NEAREST},
    // Linear: lpv.apply reads them at full resolution (bilinear from half).
    {"bentNormal", GL_RGBA16F, E::ao, C::signedValues, GL_LINEAR},
    {"s3ho", GL_RGBA16F, E::ao, C::signedValues, GL_LINEAR},
    {"specularOcclusion", GL_R16F, E::view, C::nonNegative, GL_NEAREST},
    {"brdfLut", GL_RG16F, E::brdfLut, C::nonNegative, GL_LINEAR},
    {"hdr", GL_RGBA32F, E::view, C::nonNegative, GL_NEAREST},
    {"ldr", GL_RGBA8, E::view, C::none, GL_NEAREST},
    // Linear: reprojection reads them at sub-pixel positions.
    {"history", GL_RGBA16F, E::view, C::nonNegative, GL_LINEAR},
    {"diffuseHistory", GL_RGBA16F, E::view, C::nonNegative, GL_LINEAR},
    {"localShadowMaps", GL_DEPTH_COMPONENT32F, E::localShadow, C::none, GL_LINEAR},
    // "No second surface" is FLT_MAX (finite: --check counts infinities).
    {"gbuffer.linearDepth2", GL_R32F, E::view, C::nonNegative, GL_NEAREST},
}};

}  // namespace

const ResourceDesc& resourceDesc(Resource r) {
    if (r.index < 0 || r.index >= R::count) throw std::logic_error("resourceDesc: invalid resource handle");
    return kResources[std::size_t(r.index)];
}

gl::Texture& FrameResources::operator[](Resource r) {
    return const_cast<gl::Texture&>(static_cast<const FrameResources&>(*this)[r]);
}

const gl::Texture& FrameResources::operator[](Resource r) const {
    const GBuffer& g = gbuffer;
    const gl::Texture* t[R::count] = {&g.depth,     &g.linearDepth, &g.normal,   &g.albedo, &g.material,
                                      &g.emissive,  &g.velocity,    &shadowMap,  &direct,   &indirectDiffuse,
                                      &specular,    &ao,            &bentNormal, &s3ho,     &specularOcclusion,
                                      &brdfLut,     &hdr,           &ldr,        &history,  &diffuseHistory,
                                      &localShadowMaps, &g.linearDepth2};
    resourceDesc(r);  // validates the handle
    return *t[r.index];
}

}  // namespace rtgi
