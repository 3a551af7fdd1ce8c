#pragma once
// Camera state of one frame, with the previous frame's matrices for
// reprojection (velocity buffer, temporal filters).
#include "scene/scene.h"

#include <glm/glm.hpp>

namespace rtgi {

struct View {
    glm::ivec2 size{0};
    glm::mat4 view{1.0f}, proj{1.0f};
    glm::mat4 prevView{1.0f}, prevProj{1.0f};
    glm::vec3 position{0.0f};
    float fovY = 1.0f, nearPlane = 0.1f, farPlane = 100.0f;
    unsigned frame = 0;
    bool cut = true;  // history invalid (first frame, camera jump)

    glm::mat4 viewProj() const { return proj * view; }
    glm::mat4 prevViewProj() const { return prevProj * prevView; }
    glm::vec3 forward() const { return -glm::vec3(glm::inverse(view)[2]); }
};

// Builds the view for a camera; the previous matrices are those of `prev`
// (or the same ones on a cut).
View makeView(const Camera& cam, glm::ivec2 size, const View* prev, unsigned frame);

}  // namespace rtgi
