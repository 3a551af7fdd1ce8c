#pragma once
// Shader programs built from the embedded sources (compute/...), with
// `#include "lib/x.glsl"` resolved here and `#line` directives so that a
// compile error names the original file and line. Programs are cached by
// their source files + #define set (variants by #define on one source).
#include "gl/handles.h"

#include <glm/glm.hpp>

#include <functional>
#include <map>
#include <optional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rtgi::gl {

struct Define {
    std::string name;
    std::string value;
};
using Defines = std::vector<Define>;
// A float-valued define: the value printed with enough digits to read back the same float.
Define floatDefine(std::string name, double value);

class ShaderError : public std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Source after #include expansion plus the table that maps the source-string
// numbers used in `#line L N` back to file names.
struct ExpandedSource {
    std::string text;
    std::vector<std::string> files;
};
// `load` returns the text of a path relative to compute/ or nullopt.
ExpandedSource expandIncludes(const std::string& path, const Defines& defines,
                              const std::function<std::optional<std::string>(const std::string&)>& load);
// Rewrites "0:12(3): error" (Mesa) or "0(12) : error" (NVIDIA) into "file:line: error".
std::string mapErrorLog(const std::string& log, const std::vector<std::string>& files);

class Program {
public:
    Program() = default;
    GLuint id() const { return handle_.id(); }
    // Workgroup size read back after linking (compute programs only).
    glm::ivec3 localSize() const { return localSize_; }
    const std::string& name() const { return name_; }

    // Typed uniform setters by location (locations are layout(location=...)
    // constants from the shared headers, never strings built at run time).
    void set(GLint loc, int v) const { glProgramUniform1i(id(), loc, v); }
    void set(GLint loc, unsigned v) const { glProgramUniform1ui(id(), loc, v); }
    void set(GLint loc, float v) const { glProgramUniform1f(id(), loc, v); }
    void set(GLint loc, glm::vec2 v) const { glProgramUniform2f(id(), loc, v.x, v.y); }
    void set(GLint loc, glm::vec3 v) const { glProgramUniform3f(id(), loc, v.x, v.y, v.z); }
    void set(GLint loc, glm::vec4 v) const { glProgramUniform4f(id(), loc, v.x, v.y, v.z, v.w); }
    void set(GLint loc, glm::ivec2 v) const { glProgramUniform2i(id(), loc, v.x, v.y); }
    void set(GLint loc, glm::ivec3 v) const { glProgramUniform3i(id(), loc, v.x, v.y, v.z); }
    void set(GLint loc, glm::ivec4 v) const { glProgramUniform4i(id(), loc, v.x, v.y, v.z, v.w); }
    void set(GLint loc, const glm::mat4& m) const;

private:
    friend class ProgramCache;
    ProgramHandle handle_;
    glm::ivec3 localSize_{0};
    std::string name_;
};

class ProgramCache {
public:
    // Compute program from compute/<path> (e.g. "lpv/inject.comp").
    const Program& compute(const std::string& path, const Defines& defines = {});
    // Raster program; geometry may be empty.
    const Program& raster(const std::string& vertex, const std::string& fragment, const Defines& defines = {},
                          const std::string& geometry = {});
    // Compiles a program from in-memory sources (tests of the include and
    // error-line machinery); `extraFiles` are visible to #include.
    const Program& computeFromSource(const std::string& name, const std::string& source,
                                     const std::map<std::string, std::string>& extraFiles = {},
                                     const Defines& defines = {});
    std::size_t size() const { return cache_.size(); }
    void clear() { cache_.clear(); }

private:
    std::optional<std::string> load(const std::string& path) const;
    ShaderHandle compileStage(GLenum stage, const std::string& path, const Defines& defines);
    std::map<std::string, std::unique_ptr<Program>> cache_;
    std::map<std::string, std::string> extra_;
};

// Dispatches a compute program over an n-dimensional domain, computing group
// counts from the program's own workgroup size.
void dispatch(const Program& p, int x, int y = 1, int z = 1);

}  // namespace rtgi::gl
