#pragma once
// Fly camera of rtgi-view: yaw/pitch + position, WASD moves, the mouse turns.
// Pure maths (unit-tested in tests/unit/test_view_camera.cpp).
#include "scene/scene.h"

#include <glm/glm.hpp>

namespace rtgi::view {

struct FlyCamera {
    glm::vec3 position{0.0f};
    float yaw = 0.0f;    // radians around +y; 0 looks along -z, positive turns towards +x
    float pitch = 0.0f;  // radians above the horizon, kept inside +-89 degrees
    float fovY = 1.0f, nearPlane = 0.1f, farPlane = 100.0f;
    float speed = 1.0f;  // scene units per second

    // Looks where `c` looks; speed = 0.2 scene diagonals per second, so crossing
    // any scene takes about five seconds whatever its units.
    static FlyCamera fromCamera(const Camera& c, float sceneDiagonal);
    Camera toCamera() const;  // target one unit ahead

    glm::vec3 forward() const;
    glm::vec3 right() const;  // horizontal, forward x up

    // Mouse motion in pixels; radiansPerPixel sets the sensitivity. Moving the
    // mouse right turns right, moving it up looks up.
    void look(float dxPixels, float dyPixels, float radiansPerPixel);
    // Moves along (right, world up, forward) * axes for dt seconds; fast = x5.
    void move(glm::vec3 axes, float dt, bool fast);
};

}  // namespace rtgi::view
