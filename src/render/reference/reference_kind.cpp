#include "render/reference/reference_kind.h"

namespace rtgi {

ReferenceSettings::Kind referenceKindFor(const Settings& s, const FrameResources& res) {
    using K = ReferenceSettings::Kind;
    if (s.reference.kind != K::Off) return s.reference.kind;
    if (s.ao.variant != AoSettings::Variant::Off && res.ao) return K::Ao;
    if (res.indirectDiffuse) return K::Indirect;
    return K::Full;
}

const gl::Texture& comparedTexture(ReferenceSettings::Kind kind, const FrameResources& res) {
    using K = ReferenceSettings::Kind;
    return kind == K::Ao ? res.ao : kind == K::Indirect ? res.indirectDiffuse : res.hdr;
}

Settings referenceRunSettings(const Settings& run, ReferenceSettings::Kind kind) {
    Settings rs = run;
    rs.reference.kind = kind;
    rs.ao.variant = AoSettings::Variant::Off;
    rs.ao.secondLayer = false;  // vbao's input: no estimator runs here
    rs.lpv.mode = Toggle::Off;
    rs.ssr.tracer = SsrSettings::Tracer::Off;
    return rs;
}

}  // namespace rtgi
