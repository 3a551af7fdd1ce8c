#pragma once
// Move-only RAII owners of GL object names. Each type has an explicit empty
// state (id() == 0); copying is a compile error (tests/unit/test_handles.cpp).
#include "gl/gl.h"

#include <string_view>
#include <utility>

namespace rtgi::gl {

template <class Traits>
class Handle {
public:
    Handle() = default;
    explicit Handle(GLuint id) : id_(id) {}
    ~Handle() { reset(); }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            reset();
            id_ = std::exchange(o.id_, 0);
        }
        return *this;
    }
    GLuint id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    void reset() {
        if (id_) Traits::destroy(id_);
        id_ = 0;
    }
    // Debuggers and KHR_debug messages then speak the pass's language. A label must be shorter than
    // GL_MAX_LABEL_LENGTH (GL_INVALID_VALUE otherwise: a program named by its many defines exceeded
    // NVIDIA's 256), so a longer name is cut.
    void label(std::string_view name) const {
        if (!id_ || !glObjectLabel) return;
        static const GLint maxLength = [] {
            GLint m = 0;
            glGetIntegerv(GL_MAX_LABEL_LENGTH, &m);
            return m;
        }();
        if (maxLength > 0 && name.size() >= std::size_t(maxLength)) name = name.substr(0, std::size_t(maxLength) - 1);
        glObjectLabel(Traits::kLabelKind, id_, GLsizei(name.size()), name.data());
    }

private:
    GLuint id_ = 0;
};

struct BufferTraits {
    static constexpr GLenum kLabelKind = GL_BUFFER;
    static void destroy(GLuint id) { glDeleteBuffers(1, &id); }
};
struct TextureTraits {
    static constexpr GLenum kLabelKind = GL_TEXTURE;
    static void destroy(GLuint id) { glDeleteTextures(1, &id); }
};
struct FramebufferTraits {
    static constexpr GLenum kLabelKind = GL_FRAMEBUFFER;
    static void destroy(GLuint id) { glDeleteFramebuffers(1, &id); }
};
struct VertexArrayTraits {
    static constexpr GLenum kLabelKind = GL_VERTEX_ARRAY;
    static void destroy(GLuint id) { glDeleteVertexArrays(1, &id); }
};
struct QueryTraits {
    static constexpr GLenum kLabelKind = GL_QUERY;
    static void destroy(GLuint id) { glDeleteQueries(1, &id); }
};
struct ProgramTraits {
    static constexpr GLenum kLabelKind = GL_PROGRAM;
    static void destroy(GLuint id) { glDeleteProgram(id); }
};
struct ShaderTraits {
    static constexpr GLenum kLabelKind = GL_SHADER;
    static void destroy(GLuint id) { glDeleteShader(id); }
};
struct SamplerTraits {
    static constexpr GLenum kLabelKind = GL_SAMPLER;
    static void destroy(GLuint id) { glDeleteSamplers(1, &id); }
};

using BufferHandle = Handle<BufferTraits>;
using TextureHandle = Handle<TextureTraits>;
using FramebufferHandle = Handle<FramebufferTraits>;
using VertexArrayHandle = Handle<VertexArrayTraits>;
using QueryHandle = Handle<QueryTraits>;
using ProgramHandle = Handle<ProgramTraits>;
using ShaderHandle = Handle<ShaderTraits>;
using SamplerHandle = Handle<SamplerTraits>;

}  // namespace rtgi::gl
