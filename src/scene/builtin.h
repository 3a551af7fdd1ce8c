#pragma once
// Built-in scenes: small JSON descriptions under scenes/ (embedded at build
// time) turned into a Scene by a primitive-based builder. The schema is
// documented in docs/scenes.md; loadBuiltin() / builtinSceneNames() are
// declared in scene.h.
#include "scene/scene.h"

#include <string>

namespace rtgi {

// Builds a scene from the text of a scene description. sourceName (e.g.
// "scenes/atrium.json") starts every error message and names the scene.
// Throws SceneError for malformed JSON, unknown keys, primitives or
// materials and out-of-range values.
Scene buildSceneFromJson(const std::string& text, const std::string& sourceName);

// Height of the ground plane of builtin:plane, box-on-plane and
// sphere-on-plane. A scanned model merged onto builtin:plane (Scene::merge)
// is first moved by the caller so that its lowest point sits on it.
inline constexpr float kBuiltinFloorY = 0.0f;

// Translates a scene vertically (vertices, point/spot light positions,
// cameras) so that its lowest vertex lies at floorY.
void placeOnFloor(Scene& model, float floorY = kBuiltinFloorY);

}  // namespace rtgi
