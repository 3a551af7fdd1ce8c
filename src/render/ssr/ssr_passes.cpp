#include "render/ssr/ssr_passes.h"
namespace rtgi {
void appendSsrPasses(std::vector<std::unique_ptr<Pass>>&) {}
SsrSettings::Tracer effectiveSsrTracer(const Scene& scene, const Settings& s) {
    if (s.ssr.tracer == SsrSettings::Tracer::Off) return SsrSettings::Tracer::Off;
    if (s.ssr.tracer != SsrSettings::Tracer::Auto) return s.ssr.tracer;
    return scene.minRoughness() <= s.ssr.roughnessCutoff ? SsrSettings::Tracer::Linear : SsrSettings::Tracer::Off;
}
}  // namespace rtgi
