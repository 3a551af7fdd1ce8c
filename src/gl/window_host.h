#pragma once
// The GLFW window host of rtgi-view (window_host.cpp is compiled into
// rtgi-view only; the headless binaries never link GLFW). Ends with a current
// OpenGL >= 4.5 core context and loaded glad pointers, like HeadlessContext.
#include "gl/context.h"

#include <glm/glm.hpp>

#include <functional>
#include <memory>
#include <string>

namespace rtgi::gl {

class WindowHost {
public:
    // Throws std::runtime_error with one sentence saying why no window could
    // be opened (no display, no GL 4.5 core, ...).
    static std::unique_ptr<WindowHost> create(glm::ivec2 size, const std::string& title, bool debug, bool vsync);
    ~WindowHost();
    WindowHost(const WindowHost&) = delete;
    WindowHost& operator=(const WindowHost&) = delete;

    const ContextInfo& info() const { return info_; }
    bool shouldClose() const;
    void requestClose();
    void pollEvents();
    void swapBuffers();
    void setVsync(bool on);
    glm::ivec2 framebufferSize() const;
    glm::ivec2 windowSize() const;
    bool keyDown(int key) const;
    bool mouseButtonDown(int button) const;  // 0 left, 1 right
    glm::dvec2 cursor() const;
    void setTitle(const std::string& title);
    // The GLFWwindow, for UI toolkits that bind to it (rtgi-view's ImGui).
    void* nativeHandle() const { return window_; }

    // Key presses (and repeats) with GLFW key codes and modifier bits.
    std::function<void(int key, int mods)> onKey;

private:
    WindowHost() = default;
    void* window_ = nullptr;  // GLFWwindow
    ContextInfo info_;
};

}  // namespace rtgi::gl
