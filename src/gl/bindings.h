#pragma once
// Bind-and-restore for texture and image units: a pass binds its inputs and
// outputs through one ScopedBindings, and every unit bound through it is reset
// to 0 when it goes out of scope. That keeps a texture a pass sampled (the
// compare-mode shadow map, a target written as an image by a later pass) from
// staying attached to a unit the next pass does not rebind. Slots are the named
// constants of compute/lib/*_shared.h (docs/architecture.md, "Binding slots").
#include "gl/gl.h"
#include "gl/resources.h"

#include <vector>

namespace rtgi::gl {

class ScopedBindings {
public:
    ScopedBindings() = default;
    ScopedBindings(const ScopedBindings&) = delete;
    ScopedBindings& operator=(const ScopedBindings&) = delete;
    ~ScopedBindings() {
        for (GLuint u : textures_) glBindTextureUnit(u, 0);
        for (GLuint u : images_) glBindImageTexture(u, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R8);
        // The program that used these units stops being current with them: NVIDIA validates the current program
        // at later clears and copies too, and warned of post/direct.comp's shadow sampler on its emptied unit in
        // the next pass's render-target clear (docs/STABILITY.md).
        if (!textures_.empty() || !images_.empty()) glUseProgram(0);
    }

    // Samples `t` at texture unit `unit`; null leaves the unit empty (an input the variant does not read).
    ScopedBindings& texture(GLuint unit, const Texture* t) {
        glBindTextureUnit(unit, t ? t->id() : 0);
        textures_.push_back(unit);
        return *this;
    }
    ScopedBindings& texture(GLuint unit, const Texture& t) { return texture(unit, &t); }

    // Level 0 of a 2D texture at image unit `unit`; `layered` for whole 3D volumes.
    ScopedBindings& image(GLuint unit, const Texture& t, GLenum access, GLenum format, bool layered = false) {
        glBindImageTexture(unit, t.id(), 0, layered ? GL_TRUE : GL_FALSE, 0, access, format);
        images_.push_back(unit);
        return *this;
    }

private:
    std::vector<GLuint> textures_, images_;
};

}  // namespace rtgi::gl
