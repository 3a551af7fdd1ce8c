#include "view/fly_camera.h"

#include <algorithm>
#include <cmath>

namespace rtgi::view {

namespace {
constexpr float kMaxPitch = 1.5533430f;  // 89 degrees: the view matrix degenerates at 90
}

FlyCamera FlyCamera::fromCamera(const Camera& c, float sceneDiagonal) {
    FlyCamera f;
    f.position = c.position;
    glm::vec3 d = c.target - c.position;
    float len = glm::length(d);
    d = len > 0 ? d / len : glm::vec3(0, 0, -1);
    f.pitch = std::clamp(std::asin(std::clamp(d.y, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
    f.yaw = std::atan2(d.x, -d.z);
    f.fovY = c.fovY;
    f.nearPlane = c.near;
    f.farPlane = c.far;
    f.speed = std::max(0.2f * sceneDiagonal, 1e-3f);
    return f;
}

glm::vec3 FlyCamera::forward() const {
    return {std::cos(pitch) * std::sin(yaw), std::sin(pitch), -std::cos(pitch) * std::cos(yaw)};
}

glm::vec3 FlyCamera::right() const { return {std::cos(yaw), 0.0f, std::sin(yaw)}; }

Camera FlyCamera::toCamera() const {
    Camera c;
    c.name = "fly";
    c.position = position;
    c.target = position + forward();
    c.fovY = fovY;
    c.near = nearPlane;
    c.far = farPlane;
    return c;
}

void FlyCamera::look(float dx, float dy, float radiansPerPixel) {
    yaw = std::remainder(yaw + dx * radiansPerPixel, 2.0f * 3.14159265358979f);
    pitch = std::clamp(pitch - dy * radiansPerPixel, -kMaxPitch, kMaxPitch);  // window y grows downwards
}

void FlyCamera::move(glm::vec3 axes, float dt, bool fast) {
    float step = speed * dt * (fast ? 5.0f : 1.0f);
    position += step * (axes.x * right() + axes.y * glm::vec3(0, 1, 0) + axes.z * forward());
}

}  // namespace rtgi::view
