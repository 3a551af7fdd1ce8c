#pragma once
// Helpers shared by the AO GPU tests: the estimate alone (no filter chain) and
// per-frame read-backs over the 8 blue-noise variants.
#include "gpu_fixture.h"
#include "render/gpu_scene.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
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

// Slice k of `slices` of GTAO / VBAO in double, as the shader's aoSlice (lib/ao_estimators.glsl): its
// screen direction (rotated by `rotation` over 180/slices), the in-plane axis ortho (normalized), the
// length of the normal projected into the slice plane and the normal's angle from V in it; none when
// the normal lies along the slice axis.
struct AoSliceGeometry {
    glm::dvec3 dir, ortho;
    double projLen, nAngle;
};
inline std::optional<AoSliceGeometry> aoSliceGeometry(int k, int slices, double rotation, glm::dvec3 V, glm::dvec3 n) {
    double phi = std::numbers::pi * (k + rotation) / slices;
    glm::dvec3 dir(std::cos(phi), std::sin(phi), 0);
    glm::dvec3 ortho = dir - glm::dot(dir, V) * V;
    glm::dvec3 axis = glm::normalize(glm::cross(ortho, V));
    glm::dvec3 projN = n - axis * glm::dot(n, axis);
    double projLen = glm::length(projN);
    if (projLen < 1e-4) return std::nullopt;
    double nAngle = (glm::dot(ortho, projN) >= 0 ? 1.0 : -1.0) * std::acos(std::clamp(glm::dot(projN, V) / projLen, 0.0, 1.0));
    return AoSliceGeometry{dir, glm::normalize(ortho), projLen, nAngle};
}

}  // namespace rtgi::test
