#include "render/ssr/ssr_constants.h"

#include <algorithm>
#include <stdexcept>

namespace rtgi {

glm::ivec2 ssrTraceSize(glm::ivec2 full, bool half) {
    if (!half) return glm::max(full, glm::ivec2(1));
    return glm::max((full + 1) / 2, glm::ivec2(1));
}

int hizLevelCount(glm::ivec2 full) {
    int m = std::max(std::max(full.x, full.y), 1), levels = 1;
    while (m > 1) {
        m /= 2;
        ++levels;
    }
    return levels;
}

glm::ivec2 hizLevelSize(glm::ivec2 full, int level) {
    glm::ivec2 s = glm::max(full, glm::ivec2(1));
    for (int i = 0; i < level; ++i) s = glm::max(s / 2, glm::ivec2(1));
    return s;
}

int ssrTracerId(SsrSettings::Tracer t) {
    switch (t) {
        case SsrSettings::Tracer::Linear: return RTGI_SSR_LINEAR;
        case SsrSettings::Tracer::Dda: return RTGI_SSR_DDA;
        case SsrSettings::Tracer::Hiz: return RTGI_SSR_HIZ;
        default: throw std::logic_error("ssrTracerId: auto/off tracers are resolved before the GPU");
    }
}

gpu::SsrUniforms makeSsrUniforms(const SsrSettings& s, SsrSettings::Tracer tracer, glm::ivec2 full) {
    gpu::SsrUniforms u{};
    glm::ivec2 t = ssrTraceSize(full, s.halfResolution);
    u.sizes = glm::ivec4(t, full);
    u.params = glm::ivec4(s.steps, ssrTracerId(tracer), hizLevelCount(full), s.halfResolution ? 2 : 1);
    u.trace = glm::vec4(s.thickness, s.roughnessCutoff, SsrFilterConstants::kEdgeFade, 0.0f);
    return u;
}

}  // namespace rtgi
