#include "gl/program.h"

#include "gl/embedded.h"
#include "gl/input_files.h"
#include "gl/profiler.h"
#include "gl/resources.h"

#include <glm/gtc/type_ptr.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <regex>
#include <utility>
#include <set>
#include <sstream>

namespace rtgi {

std::optional<std::string> readEmbeddedFile(std::string_view path) {
    if (const char* dir = std::getenv("RTGI_DATA_DIR")) {
        const std::string file = std::string(dir) + "/" + std::string(path);
        if (inputFileProblem(file, InputKind::Config).empty()) return readInputFile(file, InputKind::Config);
    }
    for (int i = 0; i < kEmbeddedFileCount; ++i)
        if (path == kEmbeddedFiles[i].path) return std::string(kEmbeddedFiles[i].text);
    return std::nullopt;
}

}  // namespace rtgi

namespace rtgi::gl {

Define floatDefine(std::string name, double value) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", value);
    return {std::move(name), buf};
}

namespace {

void expandInto(const std::string& path, const std::function<std::optional<std::string>(const std::string&)>& load,
                ExpandedSource& out, std::set<std::string>& onceGuard, int depth) {
    if (depth > 16) throw ShaderError(path + ": #include nesting deeper than 16 (cycle?)");
    auto text = load(path);
    if (!text) throw ShaderError("shader file '" + path + "' not found");
    int fileIndex = int(out.files.size());
    out.files.push_back(path);
    std::istringstream in(*text);
    std::string line;
    int lineNo = 0;
    // The #version line must stay first: it is written by the caller.
    out.text += "#line 1 " + std::to_string(fileIndex) + "\n";
    while (std::getline(in, line)) {
        ++lineNo;
        std::string trimmed = line.substr(std::min(line.find_first_not_of(" \t"), line.size()));
        if (trimmed.rfind("#version", 0) == 0) {
            out.text += "\n";
            continue;
        }
        if (trimmed.rfind("#pragma once", 0) == 0) {
            out.text += "\n";
            continue;
        }
        if (trimmed.rfind("#include", 0) == 0) {
            auto a = trimmed.find('"'), b = trimmed.rfind('"');
            if (a == std::string::npos || b == a)
                throw ShaderError(path + ":" + std::to_string(lineNo) + ": malformed #include");
            std::string inc = trimmed.substr(a + 1, b - a - 1);
            if (onceGuard.insert(inc).second) expandInto(inc, load, out, onceGuard, depth + 1);
            out.text += "#line " + std::to_string(lineNo + 1) + " " + std::to_string(fileIndex) + "\n";
            continue;
        }
        out.text += line + "\n";
    }
}

}  // namespace

ExpandedSource expandIncludes(const std::string& path, const Defines& defines,
                              const std::function<std::optional<std::string>(const std::string&)>& load) {
    ExpandedSource out;
    out.text = "#version 450 core\n";
    // Shared C++/GLSL headers test for this macro instead of __cplusplus.
    out.text += "#define RTGI_GLSL 1\n";
    for (auto& d : defines) out.text += "#define " + d.name + " " + (d.value.empty() ? "1" : d.value) + "\n";
    std::set<std::string> once;
    expandInto(path, load, out, once, 0);
    return out;
}

std::string mapErrorLog(const std::string& log, const std::vector<std::string>& files) {
    // Mesa: "0:12(3): error: ..."; NVIDIA: "0(12) : error C0000: ..."
    static const std::regex mesa(R"((\d+):(\d+)\((\d+)\))");
    static const std::regex nv(R"(^(\d+)\((\d+)\))");
    std::istringstream in(log);
    std::string line, out;
    while (std::getline(in, line)) {
        std::smatch m;
        if (std::regex_search(line, m, mesa) && m.position(0) == 0) {
            std::size_t f = std::stoul(m[1]);
            std::string name = f < files.size() ? files[f] : "?";
            line = name + ":" + m[2].str() + ":" + m[3].str() + line.substr(std::size_t(m.length(0)));
        } else if (std::regex_search(line, m, nv)) {
            std::size_t f = std::stoul(m[1]);
            std::string name = f < files.size() ? files[f] : "?";
            line = name + ":" + m[2].str() + line.substr(std::size_t(m.length(0)));
        }
        out += line + "\n";
    }
    return out;
}

void Program::set(GLint loc, const glm::mat4& m) const {
    glProgramUniformMatrix4fv(id(), loc, 1, GL_FALSE, glm::value_ptr(m));
}

std::optional<std::string> ProgramCache::load(const std::string& path) const {
    if (auto it = extra_.find(path); it != extra_.end()) return it->second;
    return readEmbeddedFile("compute/" + path);
}

ShaderHandle ProgramCache::compileStage(GLenum stage, const std::string& path, const Defines& defines) {
    ExpandedSource src = expandIncludes(path, defines, [this](const std::string& p) { return load(p); });
    ShaderHandle sh(glCreateShader(stage));
    const char* text = src.text.c_str();
    glShaderSource(sh.id(), 1, &text, nullptr);
    glCompileShader(sh.id());
    GLint ok = 0;
    glGetShaderiv(sh.id(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetShaderiv(sh.id(), GL_INFO_LOG_LENGTH, &len);
        std::string log(std::size_t(std::max(len, 1)), '\0');
        glGetShaderInfoLog(sh.id(), len, nullptr, log.data());
        throw ShaderError("shader compile failed:\n" + mapErrorLog(log.c_str(), src.files));
    }
    return sh;
}

static std::string cacheKey(const std::vector<std::string>& stages, const Defines& defines) {
    std::string k;
    for (auto& s : stages) k += s + "|";
    for (auto& d : defines) k += d.name + "=" + d.value + ";";
    return k;
}

static std::string displayName(const std::string& path, const Defines& defines) {
    std::string n = path;
    for (auto& d : defines) n += " " + d.name + (d.value.empty() ? "" : "=" + d.value);
    return n;
}

static void linkOrThrow(Program& p, GLuint id, const std::string& name) {
    glLinkProgram(id);
    GLint ok = 0;
    glGetProgramiv(id, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetProgramiv(id, GL_INFO_LOG_LENGTH, &len);
        std::string log(std::size_t(std::max(len, 1)), '\0');
        glGetProgramInfoLog(id, len, nullptr, log.data());
        throw ShaderError("program '" + name + "' failed to link: " + std::string(log.c_str()));
    }
    (void)p;
}

const Program& ProgramCache::compute(const std::string& path, const Defines& defines) {
    std::string key = cacheKey({path}, defines);
    if (auto it = cache_.find(key); it != cache_.end()) return *it->second;
    auto p = std::make_unique<Program>();
    ShaderHandle cs = compileStage(GL_COMPUTE_SHADER, path, defines);
    p->handle_ = ProgramHandle(glCreateProgram());
    p->name_ = displayName(path, defines);
    glAttachShader(p->id(), cs.id());
    linkOrThrow(*p, p->id(), p->name_);
    glDetachShader(p->id(), cs.id());
    GLint ls[3] = {0, 0, 0};
    glGetProgramiv(p->id(), GL_COMPUTE_WORK_GROUP_SIZE, ls);
    p->localSize_ = {ls[0], ls[1], ls[2]};
    p->handle_.label(p->name_);
    return *(cache_[key] = std::move(p));
}

const Program& ProgramCache::raster(const std::string& vertex, const std::string& fragment, const Defines& defines,
                                    const std::string& geometry) {
    std::string key = cacheKey({vertex, fragment, geometry}, defines);
    if (auto it = cache_.find(key); it != cache_.end()) return *it->second;
    auto p = std::make_unique<Program>();
    std::vector<ShaderHandle> stages;
    stages.push_back(compileStage(GL_VERTEX_SHADER, vertex, defines));
    stages.push_back(compileStage(GL_FRAGMENT_SHADER, fragment, defines));
    if (!geometry.empty()) stages.push_back(compileStage(GL_GEOMETRY_SHADER, geometry, defines));
    p->handle_ = ProgramHandle(glCreateProgram());
    p->name_ = displayName(vertex + "+" + fragment + (geometry.empty() ? "" : "+" + geometry), defines);
    for (auto& s : stages) glAttachShader(p->id(), s.id());
    linkOrThrow(*p, p->id(), p->name_);
    for (auto& s : stages) glDetachShader(p->id(), s.id());
    p->handle_.label(p->name_);
    return *(cache_[key] = std::move(p));
}

const Program& ProgramCache::computeFromSource(const std::string& name, const std::string& source,
                                               const std::map<std::string, std::string>& extraFiles,
                                               const Defines& defines) {
    extra_ = extraFiles;
    extra_[name] = source;
    cache_.erase(cacheKey({name}, defines));
    const Program& p = compute(name, defines);
    extra_.clear();
    return p;
}

void dispatch(const Program& p, int x, int y, int z) {
    Profiler::noteDispatch();
    if (x <= 0 || y <= 0 || z <= 0) return;
    glm::ivec3 l = p.localSize();
    auto scope = Profiler::dispatchScope(p.name());
    glUseProgram(p.id());
    glDispatchCompute(groupCount(x, l.x), groupCount(y, l.y), groupCount(z, l.z));
}

}  // namespace rtgi::gl
