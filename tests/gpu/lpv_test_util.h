// Set-ups shared by the LPV kernel tests that drive the injection dispatches directly.
#pragma once
#include "gpu_fixture.h"

#include "render/lpv/lpv_math.h"

namespace rtgi::test {

// A grey wall at z = 0 facing +z (16 x 16 m, roughness 1) filling the view of a 60-degree camera at
// (0, 1, 3) looking along -z: the linear depth is 3 at every pixel, and the visible part of the wall is
// (2 * 3 * tan 30 deg)^2 * aspect.
inline Scene headOnWallScene(float albedo) {
    Scene scene;
    scene.name = "test:wall";
    Material m;
    m.baseColor = glm::vec4(albedo, albedo, albedo, 1.0f);
    m.roughness = 1.0f;
    scene.materials.push_back(m);
    addQuad(scene, {-8, -7, 0}, {8, -7, 0}, {8, 9, 0}, {-8, 9, 0}, 0);
    Camera cam;
    cam.position = {0, 1, 3};
    cam.target = {0, 1, 0};
    cam.fovY = glm::radians(60.0f);
    cam.near = 0.1f;
    cam.far = 50.0f;
    scene.cameras.push_back(cam);
    return scene;
}

// The uniform block of a hand-placed volume (grid cells of size `cell` from `origin`).
inline gpu::LpvUniforms placedUniforms(const LpvSettings& s, glm::ivec3 grid, float cell, glm::vec3 origin) {
    lpv::Placement pl;
    pl.grid = grid;
    pl.cell = cell;
    pl.origin = origin;
    lpv::UniformInputs in;
    in.placement = pl;
    return lpv::makeUniforms(s, in);
}

}  // namespace rtgi::test
