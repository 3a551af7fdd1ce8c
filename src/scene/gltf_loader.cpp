#include "scene/scene.h"
namespace rtgi {
Scene loadGltf(const std::string& path) { throw SceneError(path + ": glTF loading is not implemented yet"); }
}  // namespace rtgi
