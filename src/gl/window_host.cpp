#include "gl/window_host.h"

#include "gl/gl.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <stdexcept>

namespace rtgi::gl {

namespace {

std::string lastGlfwError() {
    const char* msg = nullptr;
    int code = glfwGetError(&msg);
    return code == GLFW_NO_ERROR ? std::string("unknown reason") : std::string(msg ? msg : "no message");
}

GLFWwindow* win(void* w) { return static_cast<GLFWwindow*>(w); }

}  // namespace

std::unique_ptr<WindowHost> WindowHost::create(glm::ivec2 size, const std::string& title, bool debug, bool vsync) {
    if (!glfwInit())
        throw std::runtime_error("cannot open a window: GLFW could not start (" + lastGlfwError() +
                                 "); is DISPLAY set? Headless machines use rtgi-bench, or run under xvfb-run");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, debug ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_FALSE);  // images are encoded by the shaders
    GLFWwindow* w = glfwCreateWindow(size.x, size.y, title.c_str(), nullptr, nullptr);
    if (!w) {
        std::string why = lastGlfwError();
        glfwTerminate();
        throw std::runtime_error("cannot open a window with an OpenGL 4.5 core context (" + why + ")");
    }
    glfwMakeContextCurrent(w);
    if (!gladLoadGL(reinterpret_cast<GLADloadfunc>(glfwGetProcAddress))) {
        glfwDestroyWindow(w);
        glfwTerminate();
        throw std::runtime_error("cannot load the OpenGL functions of the window's context");
    }
    std::unique_ptr<WindowHost> h(new WindowHost());
    h->window_ = w;
    h->info_ = queryContextInfo(debug);
    h->info_.device = "GLFW window";
    glfwSetWindowUserPointer(w, h.get());
    glfwSetKeyCallback(w, [](GLFWwindow* gw, int key, int, int action, int mods) {
        auto* self = static_cast<WindowHost*>(glfwGetWindowUserPointer(gw));
        if ((action == GLFW_PRESS || action == GLFW_REPEAT) && self->onKey) self->onKey(key, mods);
    });
    h->setVsync(vsync);
    return h;
}

WindowHost::~WindowHost() {
    if (window_) glfwDestroyWindow(win(window_));
    glfwTerminate();
}

bool WindowHost::shouldClose() const { return glfwWindowShouldClose(win(window_)); }
void WindowHost::requestClose() { glfwSetWindowShouldClose(win(window_), GLFW_TRUE); }
void WindowHost::pollEvents() { glfwPollEvents(); }
void WindowHost::swapBuffers() { glfwSwapBuffers(win(window_)); }
void WindowHost::setVsync(bool on) { glfwSwapInterval(on ? 1 : 0); }
void WindowHost::setTitle(const std::string& t) { glfwSetWindowTitle(win(window_), t.c_str()); }

glm::ivec2 WindowHost::framebufferSize() const {
    glm::ivec2 s;
    glfwGetFramebufferSize(win(window_), &s.x, &s.y);
    return s;
}

glm::ivec2 WindowHost::windowSize() const {
    glm::ivec2 s;
    glfwGetWindowSize(win(window_), &s.x, &s.y);
    return s;
}

bool WindowHost::keyDown(int key) const { return glfwGetKey(win(window_), key) == GLFW_PRESS; }
bool WindowHost::mouseButtonDown(int b) const { return glfwGetMouseButton(win(window_), b) == GLFW_PRESS; }

glm::dvec2 WindowHost::cursor() const {
    glm::dvec2 c;
    glfwGetCursorPos(win(window_), &c.x, &c.y);
    return c;
}

}  // namespace rtgi::gl
