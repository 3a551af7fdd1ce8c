#include "gpu_fixture.h"

#include "gl/bindings.h"
#include "gl/embedded.h"
#include "gl/program.h"
#include "gl/profiler.h"

#include <map>

using namespace rtgi;
using namespace rtgi::test;

TEST_CASE("headless EGL context offers OpenGL 4.5 core with compute and float image atomics") {
    GpuFixture gpu;
    const auto& i = gpu.info();
    CHECK((i.major > 4 || (i.major == 4 && i.minor >= 5)));
    CHECK_FALSE(i.renderer.empty());
    CHECK(i.debugOutput);
    GLint maxInvocations = 0;
    glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &maxInvocations);
    CHECK(maxInvocations >= 256);
    // llvmpipe and NVIDIA both expose GL_NV_shader_atomic_float; the LPV
    // injection relies on it (SPEC 2).
    CHECK(i.atomicFloat);
}

TEST_CASE("an object label longer than GL_MAX_LABEL_LENGTH is cut to fit, without a GL error") {
    // A program is labelled with its file and defines; with many defines the name outgrew NVIDIA's 256
    // characters and every such program raised GL_INVALID_VALUE (the device's stress test counted 18).
    GpuFixture gpu;
    GLint maxLength = 0;
    glGetIntegerv(GL_MAX_LABEL_LENGTH, &maxLength);
    REQUIRE(maxLength >= 256);  // the GL 4.5 minimum
    GLuint id = 0;
    glCreateBuffers(1, &id);
    gl::BufferHandle b(id);
    const std::string name = "lpv/apply.comp" + std::string(std::size_t(maxLength) * 2, 'x');
    b.label(name);
    CHECK(gl::takeDebugErrorCount() == 0);
    std::string got(std::size_t(maxLength), '\0');
    GLsizei length = 0;
    glGetObjectLabel(GL_BUFFER, b.id(), maxLength, &length, got.data());
    CHECK(length == maxLength - 1);
    CHECK(got.substr(0, std::size_t(length)) == name.substr(0, std::size_t(maxLength) - 1));
}

TEST_CASE("a GL debug message names the pass it came from: the debug callback follows the profiler's groups") {
    // NVIDIA printed an undefined-behaviour warning in the GPU tier with nothing to tell which pass drew it; the
    // callback now keeps the open debug groups (the profiler's pass scopes) and prints their path with a message.
    GpuFixture gpu;
    REQUIRE(gl::debugGroupPath().empty());
    gl::Profiler prof(true);
    prof.beginFrame();
    {
        auto outer = prof.scope("outer.pass");
        CHECK(gl::debugGroupPath() == "outer.pass");
        {
            auto inner = prof.scope("inner");
            CHECK(gl::debugGroupPath() == "outer.pass/inner");
            // An error inside the group is still counted (and printed with the path).
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1u << 20, 0);
            CHECK(gl::takeDebugErrorCount() == 1);
        }
        CHECK(gl::debugGroupPath() == "outer.pass");
    }
    prof.endFrame();
    CHECK(gl::debugGroupPath().empty());
}

TEST_CASE("a pass's bindings end with no program current: the units it emptied are not validated against it") {
    // NVIDIA validates the current program at clears and copies too: post/direct.comp left current with its
    // shadow-sampler unit emptied drew "Program undefined behavior" warnings in the next pass's render-target
    // clear (lpv.rsm, lpv.inject; 141 in the device's GPU tier). ScopedBindings now ends with glUseProgram(0).
    GpuFixture gpu;
    gl::ProgramCache cache;
    const gl::Program& prog = cache.computeFromSource(
        "test/sampler.comp", "layout(local_size_x = 1) in;\nlayout(binding = 3) uniform sampler2D uTex;\n"
                             "layout(binding = 0, std430) buffer Out { vec4 v; };\nvoid main() { v = texelFetch(uTex, ivec2(0), 0); }\n");
    gl::MemoryLedger ledger;
    gl::Texture tex(ledger, "test.tex", gl::TextureDesc{GL_TEXTURE_2D, GL_RGBA8, 1, 1});
    gl::Buffer out(ledger, "test.out", 16);
    GLint current = -1;
    {
        gl::ScopedBindings b;
        b.texture(3, tex);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, out.id());
        gl::dispatch(prog, 1, 1);
        glGetIntegerv(GL_CURRENT_PROGRAM, &current);
        CHECK(current == GLint(prog.id()));
    }
    glGetIntegerv(GL_CURRENT_PROGRAM, &current);
    CHECK(current == 0);
    GLint unit = -1;
    glActiveTexture(GL_TEXTURE3);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &unit);
    glActiveTexture(GL_TEXTURE0);
    CHECK(unit == 0);
    CHECK(gl::takeDebugErrorCount() == 0);
}

TEST_CASE("an invalid --device index is a clear error, not a crash") {
    CHECK_THROWS_WITH_AS(gl::HeadlessContext::create({63, false}), doctest::Contains("--device 63"),
                         std::runtime_error);
}

TEST_CASE("compute programs: #include expansion, #define variants, workgroup size read back") {
    GpuFixture gpu;
    gl::ProgramCache cache;
    std::map<std::string, std::string> files = {{"lib/twice.glsl", "float twice(float x) { return 2.0 * x; }\n"}};
    const char* src = R"(#include "lib/twice.glsl"
layout(local_size_x = 4, local_size_y = 2) in;
layout(std430, binding = 0) buffer B { float v[]; };
void main() { uint i = gl_GlobalInvocationID.y * 8u + gl_GlobalInvocationID.x; v[i] = twice(float(i)) + float(FACTOR); }
)";
    const gl::Program& p = cache.computeFromSource("test/twice.comp", src, files, {{"FACTOR", "3"}});
    CHECK(p.localSize() == glm::ivec3(4, 2, 1));
    gl::MemoryLedger ledger;
    gl::Buffer buf(ledger, "test.buffer", 8 * 4 * 4);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf.id());
    gl::dispatch(p, 8, 4);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> out(32);
    buf.download(out.data(), 128);
    for (int i = 0; i < 32; ++i) CHECK(out[std::size_t(i)] == doctest::Approx(2.0 * i + 3));
    CHECK(ledger.total() == 128);
}

TEST_CASE("shader compile errors name the original file and line after #include expansion") {
    GpuFixture gpu;
    gl::ProgramCache cache;
    std::map<std::string, std::string> files = {
        {"lib/good.glsl", "float good() { return 1.0; }\n"},
        {"lib/bad.glsl", "// line 1\n// line 2\nfloat bad() { return undefined_symbol; }\n"}};
    const char* src = "#include \"lib/good.glsl\"\n#include \"lib/bad.glsl\"\nlayout(local_size_x = 1) in;\nvoid main() {}\n";
    std::string msg;
    try {
        cache.computeFromSource("test/uses_bad.comp", src, files);
    } catch (const gl::ShaderError& e) {
        msg = e.what();
    }
    INFO(msg);
    CHECK(msg.find("lib/bad.glsl:3") != std::string::npos);
    // An error in the main file after the includes keeps its own line number.
    const char* src2 = "#include \"lib/good.glsl\"\nlayout(local_size_x = 1) in;\nvoid main() { int x = ; }\n";
    msg.clear();
    try {
        cache.computeFromSource("test/main_error.comp", src2, files);
    } catch (const gl::ShaderError& e) {
        msg = e.what();
    }
    INFO(msg);
    CHECK(msg.find("test/main_error.comp:3") != std::string::npos);
    gl::takeDebugErrorCount();  // the failed compiles are expected errors
}

TEST_CASE("every embedded shader of the project compiles") {
    GpuFixture gpu;
    gl::ProgramCache cache;
    int compiled = 0;
    for (int i = 0; i < kEmbeddedFileCount; ++i) {
        std::string path = kEmbeddedFiles[i].path;
        if (path.rfind("compute/", 0) != 0 || path.size() < 5 || path.substr(path.size() - 5) != ".comp") continue;
        std::string rel = path.substr(8);
        INFO(rel);
        // Variants that need defines declare "// rtgi-variants: A,B" on the first line; compile the default.
        CHECK_NOTHROW(cache.compute(rel));
        ++compiled;
    }
    CHECK(compiled >= 3);
}

TEST_CASE("profiler: every pass is timed once per measured frame, in frame order, without stalls") {
    GpuFixture gpu;
    gl::Profiler prof(gpu.info().timerQuery);
    Scene s = floorScene(5, glm::vec3(0.5f), true);
    Settings st;
    st.light.shadowCache = false;  // a reused shadow map is timed but draws nothing
    st.lpv.sunCache = false;       // so is a kept sun RSM and its injection (docs/lpv.md, "Sun injection cache")
    auto r = renderFrames(s, st, {32, 24}, prof, 3);
    prof.reset();
    prof.setMeasuring(true);
    Camera cam = resolveCamera(s, st);
    for (int f = 0; f < 12; ++f) r->render(makeView(cam, {32, 24}, nullptr, unsigned(f)));
    prof.flush();
    auto res = prof.results();
    REQUIRE(res.size() == r->passes().size() + 1);
    for (std::size_t i = 0; i < r->passes().size(); ++i) {
        CHECK(res[i].name == r->passes()[i]->name());
        CHECK(res[i].ms.samples == 12);
        CHECK(res[i].ms.min >= 0.0);
        CHECK(res[i].ms.min <= res[i].ms.median);
        CHECK(res[i].ms.median <= res[i].ms.max);
        // lpv.visibility traces only when a cascade is placed anew (docs/lpv.md, "Visibility
        // moments"): the camera is static here, so it must not dispatch in the measured frames.
        if (res[i].name == "lpv.visibility") CHECK(res[i].dispatchesPerFrame == 0.0);
        else CHECK(res[i].dispatchesPerFrame >= 1.0);
    }
    CHECK(res.back().name == "frame");
    CHECK(res.back().ms.samples == 12);
    // The frame contains its passes: its median is at least the largest pass median.
    double largest = 0;
    for (std::size_t i = 0; i + 1 < res.size(); ++i) largest = std::max(largest, res[i].ms.median);
    CHECK(res.back().ms.median >= largest);
    CHECK((std::string(prof.timer()) == "gpu" || std::string(prof.timer()) == "cpu"));
}


TEST_CASE("profiler: profile.dispatches times every dispatch inside its pass, and only then") {
    GpuFixture gpu;
    Scene s = floorScene(5, glm::vec3(0.5f), true);
    for (bool on : {true, false}) {
        gl::Profiler prof(gpu.info().timerQuery);
        Settings st;
        st.light.shadowCache = false;
        st.post.profileDispatches = on;
        auto r = renderFrames(s, st, {32, 24}, prof, 2);
        prof.reset();
        prof.setMeasuring(true);
        Camera cam = resolveCamera(s, st);
        for (int f = 0; f < 4; ++f) r->render(makeView(cam, {32, 24}, nullptr, unsigned(f)));
        prof.flush();
        std::map<std::string, double> passDispatches, subDispatches;
        int subScopes = 0;
        for (auto& t : prof.results()) {
            auto slash = t.name.find('/');
            if (slash == std::string::npos) {
                passDispatches[t.name] = t.dispatchesPerFrame;
                continue;
            }
            ++subScopes;
            CHECK(t.ms.samples == 4);
            subDispatches[t.name.substr(0, slash)] += t.dispatchesPerFrame;
        }
        if (!on) {
            CHECK(subScopes == 0);
            continue;
        }
        // A compute dispatch is counted once in exactly one sub-step of its pass
        // (draws of the hardware rasterizer count in the pass only).
        for (auto& [pass, n] : subDispatches) {
            INFO(pass);
            REQUIRE(passDispatches.count(pass) == 1);
            CHECK(n > 0.0);
            CHECK(n <= passDispatches[pass]);
        }
        for (const char* compute : {"direct", "post.compose"}) {
            INFO(compute);
            CHECK(subDispatches[compute] == passDispatches[compute]);
            CHECK(subDispatches[compute] >= 1.0);
        }
    }
}
