#pragma once
// Helpers shared by the AO GPU tests: the estimate alone (no filter chain) and
// per-frame read-backs over the 8 blue-noise variants.
#include "gpu_fixture.h"
#include "render/gpu_scene.h"

#include <functional>
#include <vector>

namespace rtgi::test {

// One AO variant at full resolution, no blur / temporal filter; LPV and SSR off.
inline Settings rawAoSettings(AoSettings::Variant v, int samples, float radius) {
    Settings st;
    st.lpv.mode = Toggle::Off;
    st.ssr.tracer = SsrSettings::Tracer::Off;
    st.ao.variant = v;
    st.ao.samples = samples;
    st.ao.radius = radius;
    st.ao.halfResolution = false;
    st.ao.blur = false;
    st.ao.temporal = false;
    return st;
}

// Renders `frames` frames (frame f uses noise variant f) and reads `tex` back after each.
inline std::vector<FloatImage> frameReadbacks(const Scene& s, const Settings& st, glm::ivec2 size, gl::Profiler& prof,
                                              const std::function<const gl::Texture&(const FrameResources&)>& tex,
                                              int frames) {
    Renderer r(s, st, prof);
    Camera cam = resolveCamera(s, st);
    std::vector<FloatImage> out;
    View prev;
    for (int f = 0; f < frames; ++f) {
        View view = makeView(cam, size, f == 0 ? nullptr : &prev, unsigned(f));
        r.render(view);
        prev = view;
        out.push_back(readTexture(tex(r.resources())));
    }
    return out;
}

}  // namespace rtgi::test
