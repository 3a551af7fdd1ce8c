#pragma once
// Analytic scenes for the enclosure measure (scene/enclosure.h), shared by the unit and GPU tiers.
#include "test_scenes.h"

namespace rtgi::test {

// A w x w x h box of inward-facing quads, floor at y = 0; `top`: with its lid.
inline Scene enclosureBox(float w, float h, bool top) {
    Scene s;
    s.materials.push_back(Material{});
    const glm::vec3 p000(0, 0, 0), p100(w, 0, 0), p101(w, 0, w), p001(0, 0, w);
    const glm::vec3 p010(0, h, 0), p110(w, h, 0), p111(w, h, w), p011(0, h, w);
    addQuad(s, p000, p001, p101, p100, 0);  // floor, normal +y
    addQuad(s, p000, p100, p110, p010, 0);  // z = 0 wall, normal +z
    addQuad(s, p001, p011, p111, p101, 0);  // z = w wall, normal -z
    addQuad(s, p000, p010, p011, p001, 0);  // x = 0 wall, normal +x
    addQuad(s, p100, p101, p111, p110, 0);  // x = w wall, normal -x
    if (top) addQuad(s, p010, p110, p111, p011, 0);  // lid, normal -y
    return s;
}

inline Light enclosureSun() {
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = {0, -1, 0};
    sun.intensity = 3.0f;
    return sun;
}

// The 2 x 2 x 1.5 closed box lit by a point light inside it.
inline Scene enclosureRoom() {
    Scene s = enclosureBox(2.0f, 1.5f, true);
    Light point;
    point.type = LightType::Point;
    point.position = {1.0f, 1.0f, 1.0f};
    point.intensity = 5.0f;
    s.lights.push_back(point);
    return s;
}

}  // namespace rtgi::test
