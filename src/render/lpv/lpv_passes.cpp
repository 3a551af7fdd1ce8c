#include "render/lpv/lpv_passes.h"

#include "render/gpu_scene.h"
namespace rtgi {
void appendLpvPasses(std::vector<std::unique_ptr<Pass>>&) {}
bool lpvActive(const Scene& scene, const Settings& s) {
    if (s.lpv.mode == Toggle::Off) return false;
    return resolveSun(scene, s).has_value();
}
bool lpvSpecularActive(const Scene& scene, const Settings& s) {
    if (!lpvActive(scene, s) || s.lpv.specular == Toggle::Off) return false;
    if (s.lpv.specular == Toggle::On) return true;
    return resolveMaterials(scene, s).size() && scene.minRoughness() <= s.ssr.roughnessCutoff;
}
}  // namespace rtgi
