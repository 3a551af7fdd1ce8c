#include "scene/scene.h"
namespace rtgi {
std::vector<std::string> builtinSceneNames() { return {}; }
Scene loadBuiltin(const std::string& name) { throw SceneError("builtin:" + name + " is not implemented yet"); }
}  // namespace rtgi
