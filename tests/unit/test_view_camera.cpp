// Fly camera maths of rtgi-view (no window).
#include "view/fly_camera.h"

#include <doctest/doctest.h>

#include <glm/gtc/constants.hpp>

#include <cmath>

using namespace rtgi;
using rtgi::view::FlyCamera;

namespace {
// 1e-5: float trigonometry on unit vectors.
bool near3(glm::vec3 a, glm::vec3 b, float eps = 1e-5f) { return glm::length(a - b) < eps; }
}  // namespace

TEST_CASE("view camera: looks where the scene camera looks, basis orthonormal") {
    for (glm::vec3 dir : {glm::vec3(0, 0, -1), glm::vec3(1, 0, 0), glm::vec3(0.3f, -0.5f, 0.8f), glm::vec3(-2, 1, -1)}) {
        Camera c;
        c.position = {1, 2, 3};
        c.target = c.position + 4.0f * dir;
        c.fovY = 0.7f;
        FlyCamera f = FlyCamera::fromCamera(c, 10.0f);
        CHECK(near3(f.forward(), glm::normalize(dir)));
        CHECK(std::abs(glm::length(f.forward()) - 1.0f) < 1e-5f);
        CHECK(std::abs(glm::length(f.right()) - 1.0f) < 1e-5f);
        CHECK(std::abs(glm::dot(f.forward(), f.right())) < 1e-5f);
        CHECK(std::abs(f.right().y) < 1e-6f);  // right stays horizontal (no roll)
        // right = forward x up, projected: the camera's +x in view space.
        glm::vec3 r = glm::normalize(glm::cross(f.forward(), glm::vec3(0, 1, 0)));
        CHECK(near3(f.right(), r));
        Camera back = f.toCamera();
        CHECK(near3(back.position, c.position));
        CHECK(near3(glm::normalize(back.target - back.position), glm::normalize(dir)));
        CHECK(back.fovY == c.fovY);
    }
}

TEST_CASE("view camera: mouse right turns right, mouse up looks up, pitch stops short of the pole") {
    Camera c;
    c.position = {0, 0, 0};
    c.target = {0, 0, -1};
    FlyCamera f = FlyCamera::fromCamera(c, 10.0f);
    glm::vec3 right0 = f.right();
    f.look(100.0f, 0.0f, 0.001f);  // 0.1 rad to the right
    CHECK(glm::dot(f.forward(), right0) == doctest::Approx(std::sin(0.1f)).epsilon(1e-4));
    f.look(0.0f, -200.0f, 0.001f);  // window y grows downwards: moving up looks up
    CHECK(f.forward().y == doctest::Approx(std::sin(0.2f)).epsilon(1e-4));
    f.look(0.0f, -1e6f, 0.001f);
    CHECK(f.pitch < glm::half_pi<float>());
    CHECK(f.forward().y < 1.0f);
    CHECK(f.forward().y > 0.999f);  // 89 degrees: sin = 0.99985
    // A full turn comes back to the same direction.
    FlyCamera g = FlyCamera::fromCamera(c, 10.0f);
    glm::vec3 before = g.forward();
    g.look(2.0f * glm::pi<float>() / 0.001f, 0.0f, 0.001f);
    CHECK(near3(g.forward(), before, 1e-3f));  // 1e-3: 6283 px x 0.001 rad rounds the full turn
}

TEST_CASE("view camera: movement speed follows the scene size") {
    Camera c;
    c.position = {0, 1, 0};
    c.target = {0, 1, -1};
    FlyCamera small = FlyCamera::fromCamera(c, 5.0f), big = FlyCamera::fromCamera(c, 500.0f);
    CHECK(big.speed == doctest::Approx(100.0f * small.speed));
    small.move({0, 0, 1}, 1.0f, false);  // one second forward = 0.2 scene diagonals
    CHECK(near3(small.position, {0, 1, -1.0f}));
    small.move({1, 0, 0}, 0.5f, true);  // half a second right, fast (x5)
    CHECK(near3(small.position, {2.5f, 1, -1.0f}));
    small.move({0, 1, 0}, 1.0f, false);  // world up, whatever the pitch
    CHECK(near3(small.position, {2.5f, 2, -1.0f}));
}
