// The key codes view/controls.h names must be GLFW's (checked here, in view/,
// so that gl/window_host.cpp knows nothing of the viewer's key bindings).
#include "view/controls.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace rtgi::view {
static_assert(key::Escape == GLFW_KEY_ESCAPE && key::Tab == GLFW_KEY_TAB && key::PageUp == GLFW_KEY_PAGE_UP &&
              key::PageDown == GLFW_KEY_PAGE_DOWN && key::Left == GLFW_KEY_LEFT &&
              key::Right == GLFW_KEY_RIGHT && key::Home == GLFW_KEY_HOME && key::Space == GLFW_KEY_SPACE && key::F1 == GLFW_KEY_F1 && key::F12 == GLFW_KEY_F12 &&
              key::Comma == GLFW_KEY_COMMA && key::Period == GLFW_KEY_PERIOD &&
              key::LeftBracket == GLFW_KEY_LEFT_BRACKET && key::RightBracket == GLFW_KEY_RIGHT_BRACKET &&
              key::ModShift == GLFW_MOD_SHIFT && GLFW_KEY_A == 'A' && GLFW_KEY_1 == '1');
}  // namespace rtgi::view
