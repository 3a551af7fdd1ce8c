#pragma once
// Hosts for the renderer: a headless EGL context (benchmark, tests) and, in
// rtgi-view only, a GLFW window (window_host.cpp). Both end with a current
// OpenGL >= 4.5 core context and loaded glad function pointers.
#include <memory>
#include <string>
#include <vector>

namespace rtgi::gl {

struct ContextInfo {
    std::string vendor, renderer, version, glsl;
    std::string device;  // EGL device / platform that was chosen
    int major = 0, minor = 0;
    bool atomicFloat = false;  // GL_NV_shader_atomic_float (imageAtomicAdd on r32f)
    bool timerQuery = false;   // GL_TIMESTAMP with > 0 counter bits
    bool debugOutput = false;  // KHR_debug callback installed
};

struct ContextOptions {
    int device = -1;     // EGL device index; -1 = prefer NVIDIA, else Mesa
    bool debug = false;  // KHR_debug output (tests, debug builds)
};

class HeadlessContext {
public:
    // Throws std::runtime_error with one sentence when no usable context exists.
    static std::unique_ptr<HeadlessContext> create(const ContextOptions& opts);
    ~HeadlessContext();
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;
    const ContextInfo& info() const { return info_; }
    // Names of the EGL devices found (index = --device N).
    static std::vector<std::string> listDevices();

private:
    HeadlessContext() = default;
    void* display_ = nullptr;
    void* context_ = nullptr;
    ContextInfo info_;
};

// Fills info strings/capabilities and installs the debug callback; called by
// every host after glad has loaded the GL functions.
ContextInfo queryContextInfo(bool debug);
// GL errors and undefined-behaviour reports through KHR_debug since the last call (tests assert 0).
int takeDebugErrorCount();
// The debug groups open on this thread's context, outermost first, joined by '/' (the profiler's pass scopes;
// "" outside any): the debug callback prints it with every message so a driver warning names its pass.
std::string debugGroupPath();
// Whether the current context lists the extension (false without a loaded context).
bool hasExtension(const char* name);

}  // namespace rtgi::gl
