#include "gl/context.h"

#include "gl/gl.h"

#include <glad/egl.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#include <dlfcn.h>
#include <link.h>
#endif

namespace rtgi::gl {
namespace {

#if defined(__SANITIZE_ADDRESS__)
// Sanitizer builds (CI's sanitizer job, scripts/sanitize.sh): LeakSanitizer looks for leaks at exit,
// after eglTerminate has let the EGL vendor library unload the GL driver; memory the driver still
// references from its own globals then counts as leaked from an "unknown module" (Mesa 22.3.6
// llvmpipe, swrast_dri.so: 128 bytes on every context). Marking every library loaded once the context
// is current as never-unloaded keeps the driver mapped, so its allocations stay reachable, and a leak
// that LeakSanitizer does report is attributed to a named library.
void keepLoadedLibrariesMapped() {
    dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void*) -> int {
            if (info->dlpi_name && info->dlpi_name[0] != '\0')
                dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);  // reference dropped never
            return 0;
        },
        nullptr);
}
#endif

int gDebugErrors = 0;

// The open debug groups (the profiler's pass scopes, glPushDebugGroup): a message names the pass it came from.
// The driver reports every push and pop to the callback (synchronous output, one context per thread).
thread_local std::vector<std::string> tDebugGroups;

void GLAPIENTRY debugCallback(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length, const GLchar* msg,
                              const void*) {
    (void)source;
    (void)id;
    if (type == GL_DEBUG_TYPE_PUSH_GROUP) {
        tDebugGroups.emplace_back(msg, length >= 0 ? std::size_t(length) : std::strlen(msg));
        return;
    }
    if (type == GL_DEBUG_TYPE_POP_GROUP) {
        if (!tDebugGroups.empty()) tDebugGroups.pop_back();
        return;
    }
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
    // Errors, and the driver's undefined-behaviour reports (NVIDIA validates sampler and texture state): tests
    // assert none of either.
    if (type == GL_DEBUG_TYPE_ERROR || type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR) ++gDebugErrors;
    // Performance chatter from drivers is not an error; print only the rest
    // (all of it with RTGI_TRACE=1).
    static const bool all = std::getenv("RTGI_TRACE") && std::string(std::getenv("RTGI_TRACE")) != "0";
    if (!all && (type == GL_DEBUG_TYPE_PERFORMANCE || type == GL_DEBUG_TYPE_OTHER)) return;
    if (tDebugGroups.empty()) std::fprintf(stderr, "GL debug: %s\n", msg);
    else std::fprintf(stderr, "GL debug (in %s): %s\n", debugGroupPath().c_str(), msg);
}


const char* deviceName(EGLDeviceEXT dev) {
    const char* s = nullptr;
#ifdef EGL_DRM_DEVICE_FILE_EXT
    if (eglQueryDeviceStringEXT) s = eglQueryDeviceStringEXT(dev, EGL_DRM_DEVICE_FILE_EXT);
#endif
    if (!s && eglQueryDeviceStringEXT) s = eglQueryDeviceStringEXT(dev, EGL_EXTENSIONS);
    return s ? s : "(unnamed)";
}

}  // namespace

std::string debugGroupPath() {
    std::string where;
    for (const std::string& g : tDebugGroups) where += (where.empty() ? "" : "/") + g;
    return where;
}

int takeDebugErrorCount() {
    int n = gDebugErrors;
    gDebugErrors = 0;
    return n;
}

ContextInfo queryContextInfo(bool debug) {
    ContextInfo i;
    auto str = [](GLenum e) {
        const GLubyte* s = glGetString(e);
        return std::string(s ? reinterpret_cast<const char*>(s) : "");
    };
    i.vendor = str(GL_VENDOR);
    i.renderer = str(GL_RENDERER);
    i.version = str(GL_VERSION);
    i.glsl = str(GL_SHADING_LANGUAGE_VERSION);
    glGetIntegerv(GL_MAJOR_VERSION, &i.major);
    glGetIntegerv(GL_MINOR_VERSION, &i.minor);
    i.atomicFloat = hasExtension("GL_NV_shader_atomic_float");
    GLint bits = 0;
    glGetQueryiv(GL_TIMESTAMP, GL_QUERY_COUNTER_BITS, &bits);
    i.timerQuery = bits > 0;
    tDebugGroups.clear();  // a new context: no group of an earlier one is open (one left by an unwound pass)
    if (debug && glDebugMessageCallback) {
        glEnable(GL_DEBUG_OUTPUT);
        glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        glDebugMessageCallback(debugCallback, nullptr);
        i.debugOutput = true;
    }
    return i;
}

std::vector<std::string> HeadlessContext::listDevices() {
    std::vector<std::string> out;
    if (!gladLoaderLoadEGL(EGL_NO_DISPLAY) || !eglQueryDevicesEXT) return out;
    EGLDeviceEXT devs[16];
    EGLint n = 0;
    if (!eglQueryDevicesEXT(16, devs, &n)) return out;
    for (EGLint k = 0; k < n; ++k) out.emplace_back(deviceName(devs[k]));
    return out;
}

std::unique_ptr<HeadlessContext> HeadlessContext::create(const ContextOptions& opts) {
    if (!gladLoaderLoadEGL(EGL_NO_DISPLAY))
        throw std::runtime_error("could not load libEGL (install libegl1 and libegl-mesa0)");
    std::unique_ptr<HeadlessContext> ctx(new HeadlessContext());

    // Candidate displays: the EGL devices (EGL_EXT_platform_device), NVIDIA
    // first unless --device picks one, then Mesa's surfaceless platform.
    struct Candidate {
        EGLDisplay display;
        std::string name;
    };
    std::vector<Candidate> candidates;
    if (eglQueryDevicesEXT && eglGetPlatformDisplayEXT) {
        EGLDeviceEXT devs[16];
        EGLint n = 0;
        eglQueryDevicesEXT(16, devs, &n);
        if (opts.device >= 0 && opts.device >= n)
            throw std::runtime_error("--device " + std::to_string(opts.device) + " does not exist: " +
                                     std::to_string(n) + " EGL device(s) found");
        std::vector<Candidate> nvidia, other;
        for (EGLint k = 0; k < n; ++k) {
            if (opts.device >= 0 && k != opts.device) continue;
            EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devs[k], nullptr);
            if (d == EGL_NO_DISPLAY) continue;
            std::string name = "egl-device " + std::to_string(k) + " (" + deviceName(devs[k]) + ")";
            const char* exts = eglQueryDeviceStringEXT ? eglQueryDeviceStringEXT(devs[k], EGL_EXTENSIONS) : nullptr;
            bool isNv = exts && std::strstr(exts, "EGL_NV_");
            (isNv ? nvidia : other).push_back({d, name});
        }
        candidates.insert(candidates.end(), nvidia.begin(), nvidia.end());
        candidates.insert(candidates.end(), other.begin(), other.end());
    }
    if (opts.device < 0 && eglGetPlatformDisplayEXT) {
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (d != EGL_NO_DISPLAY) candidates.push_back({d, "mesa-surfaceless"});
    }

    std::string tried;
    for (auto& c : candidates) {
        EGLint major = 0, minor = 0;
        if (!eglInitialize(c.display, &major, &minor)) {
            tried += " " + c.name + ": eglInitialize failed;";
            continue;
        }
        gladLoaderLoadEGL(c.display);
        if (!eglBindAPI(EGL_OPENGL_API)) {
            tried += " " + c.name + ": no desktop OpenGL;";
            continue;
        }
        EGLContext context = EGL_NO_CONTEXT;
        for (int minorGl : {6, 5}) {
            const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4,
                                      EGL_CONTEXT_MINOR_VERSION, minorGl,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_CONTEXT_OPENGL_DEBUG, opts.debug ? EGL_TRUE : EGL_FALSE,
                                      EGL_NONE};
            context = eglCreateContext(c.display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
            if (context != EGL_NO_CONTEXT) break;
        }
        if (context == EGL_NO_CONTEXT) {
            tried += " " + c.name + ": no OpenGL 4.5 core context;";
            eglTerminate(c.display);
            continue;
        }
        if (!eglMakeCurrent(c.display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
            tried += " " + c.name + ": eglMakeCurrent failed;";
            eglDestroyContext(c.display, context);
            eglTerminate(c.display);
            continue;
        }
        if (!gladLoaderLoadGL()) {
            tried += " " + c.name + ": GL functions could not be loaded;";
            continue;
        }
#if defined(__SANITIZE_ADDRESS__)
        keepLoadedLibrariesMapped();
#endif
        ctx->display_ = c.display;
        ctx->context_ = context;
        ctx->info_ = queryContextInfo(opts.debug);
        ctx->info_.device = c.name;
        return ctx;
    }
    throw std::runtime_error("no usable OpenGL 4.5 core context through EGL" +
                             (tried.empty() ? std::string(" (no EGL device or Mesa surfaceless platform found)")
                                            : std::string(":") + tried));
}

HeadlessContext::~HeadlessContext() {
    if (display_) {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (context_) eglDestroyContext(display_, context_);
        eglTerminate(display_);
    }
}

bool hasExtension(const char* name) {
    if (!glGetIntegerv || !glGetStringi) return false;  // no loaded context
    GLint n = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &n);
    for (GLint i = 0; i < n; ++i) {
        const char* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
        if (e && std::strcmp(e, name) == 0) return true;
    }
    return false;
}

}  // namespace rtgi::gl
