// Binding slots are named, never literal (docs/architecture.md, "Binding slots"):
// greps compute/ and src/ so a literal unit, binding or uniform location cannot
// come back unnoticed. Each pattern is checked against a line it must catch,
// so a broken pattern fails here instead of passing silently.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Rule {
    const char* what;
    std::regex pattern;
    const char* mustCatch;  // positive control
};

// GLSL: layout(binding = 3) and every layout(location = 0): uniforms, varyings and
// colour outputs all take their location from the family header.
std::vector<Rule> shaderRules() {
    return {
        {"literal binding", std::regex(R"(binding\s*=\s*[0-9])"), "layout(rgba16f, binding = 2) uniform image2D uX;"},
        {"literal location", std::regex(R"(location\s*=\s*[0-9])"), "layout(location = 0) flat out int vLayer;"},
    };
}

// C++: the first argument of the unit/binding calls, the location of uniform setters.
std::vector<Rule> sourceRules() {
    return {
        {"literal texture/image unit", std::regex(R"(glBind(TextureUnit|ImageTexture)\(\s*[0-9])"),
         "glBindTextureUnit(0, tex.id());"},
        {"literal buffer binding", std::regex(R"(glBindBufferBase\(\s*[A-Z_]+\s*,\s*[0-9])"),
         "glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf.id());"},
        {"literal uniform location", std::regex(R"(\.set\(\s*[0-9])"), "prog.set(1, 0.5f);"},
        {"literal uniform location", std::regex(R"(glProgramUniform\w*\(\s*[^,]+,\s*[0-9])"),
         "glProgramUniform4ui(prog.id(), 0, a, b, c, d);"},
    };
}

std::vector<std::string> scan(const fs::path& root, const std::vector<std::string>& extensions,
                              const std::vector<Rule>& rules) {
    std::vector<std::string> hits;
    for (const auto& e : fs::recursive_directory_iterator(root)) {
        if (!e.is_regular_file()) continue;
        std::string ext = e.path().extension().string();
        bool wanted = false;
        for (const auto& x : extensions) wanted |= ext == x;
        if (!wanted) continue;
        std::ifstream f(e.path());
        std::string line;
        for (int n = 1; std::getline(f, line); ++n) {
            std::string code = line.substr(0, line.find("//"));  // comments may cite numbers
            for (const auto& r : rules)
                if (std::regex_search(code, r.pattern))
                    hits.push_back(e.path().lexically_relative(root.parent_path()).string() + ":" +
                                   std::to_string(n) + ": " + r.what + ": " + line);
        }
    }
    return hits;
}

}  // namespace

TEST_CASE("binding-slot patterns catch the literals they are meant for") {
    for (const auto& rules : {shaderRules(), sourceRules()})
        for (const auto& r : rules) {
            INFO(r.what << ": " << r.mustCatch);
            CHECK(std::regex_search(std::string(r.mustCatch), r.pattern));
        }
    // Named slots and named stage locations pass.
    for (const char* ok : {"layout(binding = RTGI_AO_TEX_DEPTH) uniform sampler2D uDepth;",
                           "layout(location = RTGI_VIEW_OUT_COLOR) out vec4 outColor;",
                           "layout(location = RTGI_RASTER_VARY_NORMAL) in vec3 vNormal;"})
        for (const auto& r : shaderRules()) CHECK_FALSE(std::regex_search(std::string(ok), r.pattern));
    for (const char* ok : {"glBindTextureUnit(RTGI_LPV_TEX_FLUX, rsm.flux.id());",
                           "glBindImageTexture(RTGI_SSR_IMG_HIT, hit.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG16F);",
                           "prog.set(RTGI_POST_LOC_HAVE, glm::ivec4(1));"})
        for (const auto& r : sourceRules()) CHECK_FALSE(std::regex_search(std::string(ok), r.pattern));
}

TEST_CASE("no literal binding numbers or uniform locations in compute/") {
    auto hits = scan(fs::path(RTGI_SOURCE_DIR) / "compute", {".comp", ".vert", ".frag", ".geom", ".glsl", ".h"},
                     shaderRules());
    for (const auto& h : hits) FAIL_CHECK(h);
    CHECK(hits.empty());
}

TEST_CASE("no literal texture/image units, buffer bindings or uniform locations in src/") {
    auto hits = scan(fs::path(RTGI_SOURCE_DIR) / "src", {".cpp", ".h"}, sourceRules());
    for (const auto& h : hits) FAIL_CHECK(h);
    CHECK(hits.empty());
}
