#pragma once
// Strict JSON typing of a glTF 2.0 document, checked on the raw JSON before
// tinygltf reads it. tinygltf skips an optional member it cannot read (a
// string where a number belongs, `indices: 2.5`, `pbrMetallicRoughness: []`),
// so a file the glTF 2.0 schema calls invalid would load as a different
// scene. Here every member the loader or the schema gives a type is checked
// for it, every index for its range (including -1), and node hierarchies for
// the spec's "disjoint strict trees" rule (no duplicate children, no node
// with two parents: the instance bomb of a 4 KB file is impossible).
#include <nlohmann/json.hpp>

#include <string>

namespace rtgi {

// Throws SceneError "FILE: JSON.PATH: expected ..., found ..." on the first
// problem (e.g. `materials[0].pbrMetallicRoughness: expected an object,
// found an array`). `file` is the path named in the message.
void checkGltfSchema(const nlohmann::json& doc, const std::string& file);

}  // namespace rtgi
