#include "render/view.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace rtgi {

View makeView(const Camera& cam, glm::ivec2 size, const View* prev, unsigned frame) {
    View v;
    v.size = size;
    v.position = cam.position;
    v.fovY = cam.fovY;
    v.nearPlane = cam.near;
    v.farPlane = cam.far;
    glm::vec3 fwd = glm::normalize(cam.target - cam.position);
    glm::vec3 up = cam.up;
    if (std::abs(glm::dot(fwd, glm::normalize(up))) > 0.999f) up = glm::vec3(0, 0, 1);  // looking straight up/down
    v.view = glm::lookAt(cam.position, cam.target, up);
    float aspect = float(size.x) / float(std::max(size.y, 1));
    v.proj = glm::perspective(cam.fovY, aspect, cam.near, cam.far);
    v.frame = frame;
    // History is valid only when the previous view had the same size.
    v.cut = !prev || prev->size != size;
    v.prevView = v.cut ? v.view : prev->view;
    v.prevProj = v.cut ? v.proj : prev->proj;
    return v;
}

}  // namespace rtgi
