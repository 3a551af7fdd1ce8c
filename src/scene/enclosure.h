#pragma once
// How closed a scene is for its lights (docs/lpv.md, "Closed scenes"): the share of the light that its
// lit surfaces scatter which leaves the scene without meeting another surface. Points are spread over
// the surfaces by area and weighted by the direct irradiance they receive (every light and emissive
// triangle, shadowed, luminance of its colour); from each, one cosine-distributed ray on the side its
// shading normal faces (the first bounce of a Lambertian surface) counts as escaped when it hits no
// triangle. A closed room gives 0, a lone plane under a sun 1, the floor of a box open on one side about
// the cosine-weighted view factor of the opening. Without any light the points weigh by area alone.
// Points are drawn until `rays` of them were lit, or 16 x `rays` were drawn.
#include <cstdint>

namespace rtgi {

struct Scene;

struct Enclosure {
    double escaped = 1.0;  // weighted fraction of the rays that hit nothing
    int rays = 0;          // scattered rays that carry weight: from lit points, or all when none was lit
                           // (0: the scene has no surface area)
    bool lit = false;      // some point received light (else the weights were the area alone)
};

Enclosure measureEnclosure(const Scene& scene, int rays = 8192, std::uint32_t seed = 1);

}  // namespace rtgi
