// Issue 28 without GL: every file goes through one bounded reader (FIFOs,
// devices, directories and /proc files are refused by their kind before they
// are opened), radiometric products are checked in double at load time,
// accepted-but-wrong scene and configuration values are errors or warnings,
// and file names print with their control characters escaped. Each case runs
// the rtgi-bench binary (exit code, time < 5 s, the sentence on stderr).
#include "bench/sweep_spec.h"
#include "bench_runner.h"
#include "gl/input_files.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

using namespace rtgi;
using rtgi::test::runBench;
using rtgi::test::shellQuote;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

fs::path scratch(const std::string& name) {
    fs::path d = fs::temp_directory_path() / ("rtgi-inputs-unit-" + std::to_string(getpid())) / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

fs::path fifo(const fs::path& dir, const std::string& name) {
    fs::path p = dir / name;
    REQUIRE(mkfifo(p.c_str(), 0600) == 0);
    return p;
}

void writeFile(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// One triangle (corners at +-extent in x/z) in an external buffer "tri.bin"
// next to the file; callers add materials, lights, nodes before writing.
json triangleGltf(const fs::path& dir, double extent) {
    const float e = float(extent);
    const float pos[9] = {-e, 0, -e, e, 0, -e, 0, 0, e};
    std::ofstream(dir / "tri.bin", std::ios::binary).write(reinterpret_cast<const char*>(pos), sizeof pos);
    json doc = {
        {"asset", {{"version", "2.0"}}},
        {"extensionsUsed", {"KHR_materials_emissive_strength", "KHR_lights_punctual"}},
        {"buffers", {{{"uri", "tri.bin"}, {"byteLength", 36}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteLength", 36}}}},
        {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"},
                        {"min", {-e, 0, -e}}, {"max", {e, 0, e}}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
        {"nodes", {{{"mesh", 0}}}},
        {"scenes", {{{"nodes", {0}}}}},
        {"scene", 0},
    };
    return doc;
}

// An emissive material on the triangle: emissiveFactor x emissiveStrength.
void makeEmissive(json& doc, std::vector<double> factor, double strength) {
    doc["materials"] = {{{"emissiveFactor", factor},
                         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", strength}}}}}}};
    doc["meshes"][0]["primitives"][0]["material"] = 0;
}

// Adds a light with its own node; returns the node index.
std::size_t addLight(json& doc, json light, json node = json::object()) {
    auto& lights = doc["extensions"]["KHR_lights_punctual"]["lights"];
    if (lights.is_null()) lights = json::array();
    lights.push_back(light);
    node["extensions"] = {{"KHR_lights_punctual", {{"light", lights.size() - 1}}}};
    doc["nodes"].push_back(node);
    doc["scenes"][0]["nodes"].push_back(doc["nodes"].size() - 1);
    return doc["nodes"].size() - 1;
}

std::string write(const fs::path& dir, const json& doc, const std::string& name = "scene.gltf") {
    writeFile(dir / name, doc.dump());
    return (dir / name).string();
}

void writePfm1x1(const fs::path& p) {
    std::string s = "PF\n1 1\n-1.0\n";
    const float rgb[3] = {0.5f, 0.5f, 0.5f};
    s.append(reinterpret_cast<const char*>(rgb), sizeof rgb);
    writeFile(p, s);
}

// Exit code, time and the sentence: one line on stderr that contains `words`.
void expectExit(const std::string& args, int rc, const std::string& words) {
    auto r = runBench(args);
    CAPTURE(args);
    CAPTURE(r.err);
    CHECK(r.rc == rc);
    CHECK(r.seconds < 5.0);
    CHECK(r.err.find(words) != std::string::npos);
}

}  // namespace

TEST_CASE("hardening: the input reader refuses FIFOs, devices, directories and /proc files by stat, and stops at its limit") {
    fs::path d = scratch("reader");
    fs::path f = fifo(d, "pipe.json");
    CHECK(inputFileProblem(f.string(), InputKind::Config) == "is a named pipe (FIFO), not a regular file");
    CHECK(inputFileProblem("/dev/zero", InputKind::Config) == "is a character device, not a regular file");
    CHECK(inputFileProblem(d.string(), InputKind::Config) == "is a directory, not a file");
    CHECK(inputFileProblem("/proc/self/status", InputKind::Config) == "is a kernel pseudo-file (/proc, /sys), not a regular file");
    CHECK(inputFileProblem((d / "missing").string(), InputKind::Config) == "does not exist");
    // A sparse file one byte over the limit: refused from its size, nothing read.
    fs::path big = d / "big.json";
    writeFile(big, "");
    fs::resize_file(big, inputSizeLimit(InputKind::Config) + 1);
    CHECK_THROWS_WITH_AS(readInputFile(big.string(), InputKind::Config),
                         doctest::Contains("more than the 16 MiB limit for configuration files"), InputError);
    writeFile(d / "ok.json", "{}");
    CHECK(readInputFile((d / "ok.json").string(), InputKind::Config) == "{}");
    std::vector<unsigned char> bytes;
    std::string why;
    CHECK_FALSE(readInputBytes(f.string(), InputKind::SceneData, bytes, why));  // never blocks
    CHECK(why == "is a named pipe (FIFO), not a regular file");
    // Control characters are escaped, valid UTF-8 is kept, the output is stable.
    CHECK(escapeControl("a\nb\x1b[31mc\x7f\xc3\xa9\xff") == "a\\nb\\x1b[31mc\\x7f\xc3\xa9\\xff");
    CHECK(escapeControl(escapeControl("x\ty")) == escapeControl("x\ty"));
}

TEST_CASE("hardening: --config, --sweep and --compare on a FIFO, /dev/zero, a directory or /proc end at once with one sentence") {
    fs::path d = scratch("cli");
    const std::string pipe = fifo(d, "pipe.json").string(), out = (d / "out").string();
    const std::string bench = "--scene builtin:cornell --validate-only ";
    expectExit(bench + "--config " + pipe, 2, "--config " + pipe + ": is a named pipe (FIFO), not a regular file");
    expectExit("--sweep " + pipe + " --out " + out, 2, "--sweep " + pipe + ": is a named pipe (FIFO), not a regular file");
    expectExit(bench + "--config /dev/zero", 2, "--config /dev/zero: is a character device, not a regular file");
    expectExit("--sweep /dev/zero --out " + out, 2, "--sweep /dev/zero: is a character device, not a regular file");
    expectExit(bench + "--config " + d.string(), 2, "--config " + d.string() + ": is a directory, not a file");
    expectExit("--sweep " + d.string() + " --out " + out, 2, "--sweep " + d.string() + ": is a directory, not a file");
    expectExit(bench + "--config /proc/self/status", 2, "--config /proc/self/status: is a kernel pseudo-file (/proc, /sys)");
    expectExit("--scene /proc/self/status --validate-only", 3, "/proc/self/status: is a kernel pseudo-file (/proc, /sys)");
    // --compare: the image, the reference and the mask go through the same reader.
    const fs::path img = d / "img.pfm";
    writePfm1x1(img);
    const std::string pipePfm = fifo(d, "pipe.pfm").string(), cmpOut = " --out " + (d / "cmp").string();
    expectExit("--compare " + pipePfm + " " + img.string() + cmpOut, 3, pipePfm + ": is a named pipe (FIFO), not a regular file");
    expectExit("--compare " + img.string() + " " + pipePfm + cmpOut, 3, pipePfm + ": is a named pipe (FIFO)");
    expectExit("--compare " + img.string() + " " + img.string() + " --mask /dev/zero" + cmpOut, 3,
               "/dev/zero: is a character device, not a regular file");
    expectExit("--compare " + img.string() + " " + d.string() + cmpOut, 3, d.string() + ": is a directory, not a file");
}

TEST_CASE("hardening: glTF buffers and images naming a FIFO, /dev/zero or a directory say what they are, not 'missing'") {
    fs::path d = scratch("gltf-files");
    fifo(d, "pipe.bin");
    json doc = triangleGltf(d, 1.0);
    doc["buffers"][0]["uri"] = "pipe.bin";
    expectExit("--validate-only --scene " + write(d, doc), 3,
               "external buffer 'pipe.bin' (buffer 0) is a named pipe (FIFO), not a regular file");
    doc["buffers"][0]["uri"] = fs::relative("/dev/zero", d).string();
    expectExit("--validate-only --scene " + write(d, doc), 3, "(buffer 0) is a character device, not a regular file");
    doc = triangleGltf(d, 1.0);
    doc["images"] = {{{"uri", "pipe.bin"}}};
    expectExit("--validate-only --scene " + write(d, doc), 3,
               "external image 'pipe.bin' (image 0) is a named pipe (FIFO), not a regular file");
    doc["images"] = {{{"uri", "."}}};
    expectExit("--validate-only --scene " + write(d, doc), 3, "external image '.' (image 0) is a directory, not a file");
    // The scene file itself.
    const std::string pipeGltf = fifo(d, "pipe.gltf").string();
    expectExit("--validate-only --scene " + pipeGltf, 3, pipeGltf + ": is a named pipe (FIFO), not a regular file");
}

TEST_CASE("hardening: file names with a newline or an ANSI escape are printed escaped") {
    fs::path d = scratch("names");
    const std::string name = (d / "a\nb\x1b[31m.json").string();
    auto r = runBench("--scene builtin:cornell --validate-only --config " + shellQuote(name));
    CAPTURE(r.err);
    CHECK(r.rc == 2);
    CHECK(r.seconds < 5.0);
    CHECK(r.err.find("a\\nb\\x1b[31m.json: does not exist") != std::string::npos);
    CHECK(r.err.find('\x1b') == std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);  // one line
    const std::string gltf = (d / "s\x1b]0;title\a.gltf").string();
    r = runBench("--validate-only --scene " + shellQuote(gltf));
    CAPTURE(r.err);
    CHECK(r.rc == 3);
    CHECK(r.err.find("s\\x1b]0;title\\x07.gltf: does not exist") != std::string::npos);
    CHECK(r.err.find('\x1b') == std::string::npos);
}

TEST_CASE("hardening: emitters whose products overflow float are refused at load time (the three NaN cases)") {
    fs::path d = scratch("emitters");
    const std::string run = " --res 32x32 --frames 1 --warmup 0 --check --no-images --out " + (d / "out").string();
    // 1e12 m^2 (corners at +-1e6) with emissiveStrength 9.9e29: Le is fine, Le x A is not.
    json doc = triangleGltf(d, 1e6);
    makeEmissive(doc, {1, 1, 1}, 9.9e29);
    expectExit("--scene " + write(d, doc) + run, 3, "emissive region 0: emission x area = 9.9e+29 x 2e+12 m^2, an intensity of 1.98e+42 exceeds 1e+30");
    // Corners at +-1e15 with strength 1e29.
    doc = triangleGltf(d, 1e15);
    makeEmissive(doc, {1, 1, 1}, 1e29);
    expectExit("--scene " + write(d, doc) + run, 3, "emissive region 0: emission x area");
    // An emitter of 9.9e29 (0.5 m^2) is fine alone; emissive.scale=1e12 makes it 9.9e41.
    doc = triangleGltf(d, 0.5);
    makeEmissive(doc, {1, 1, 1}, 9.9e29);
    expectExit("--scene " + write(d, doc) + run + " --set emissive.scale=1e12", 2,
               "emissive.scale=1e+12: material 'material0': emission becomes 9.9e+41, more than 1e+30");
    // sun.scale on a sun of 1e20 likewise.
    doc = triangleGltf(d, 1.0);
    addLight(doc, {{"type", "directional"}, {"intensity", 1e20}});
    expectExit("--scene " + write(d, doc) + " --validate-only --set sun.scale=1e12", 2,
               "sun.scale=1e+12: the sun's irradiance becomes 1e+32, more than 1e+30");
}

TEST_CASE("hardening: accepted-but-wrong lights and materials are warnings or errors in their own words") {
    fs::path d = scratch("lights");
    json doc = triangleGltf(d, 1.0);
    for (int i = 0; i < 1000; ++i) addLight(doc, {{"type", "directional"}, {"intensity", 1}});
    auto r = runBench("--validate-only --scene " + write(d, doc));
    CAPTURE(r.err);
    CHECK(r.rc == 0);
    CHECK(r.seconds < 5.0);
    CHECK(r.err.find("1000 directional lights; only 'light 0' is used (the frame has one sun), the other 999 are ignored") !=
          std::string::npos);

    struct Case {
        const char* name;
        json light, node;
        const char* warning;
    };
    const Case cases[] = {
        {"range 0", {{"type", "point"}, {"range", 0}}, json::object(),
         "lights[0].range is 0, which glTF does not allow (range must be > 0)"},
        {"negative colour", {{"type", "point"}, {"color", {-9e29, 1, 1}}}, json::object(),
         "lights[0].color [-9e+29, 1, 1] has a negative component (glTF colours are 0..1); clamped to 0"},
        {"range -5", {{"type", "spot"}, {"range", -5}, {"spot", json::object()}}, json::object(),
         "lights[0].range is -5, which glTF does not allow (range must be > 0); the light has no range (infinite)"},
        {"intensity -2", {{"type", "point"}, {"intensity", -2}}, json::object(),
         "lights[0].intensity is -2, which glTF does not allow (intensity must be >= 0); using 1"},
        {"point with spot", {{"type", "point"}, {"spot", {{"outerConeAngle", 0.5}}}}, json::object(),
         "lights[0] is a point light but has a \"spot\" object, which is ignored"},
        {"scaled spot", {{"type", "spot"}, {"spot", json::object()}}, {{"scale", {1e39, 1e39, 1e39}}},
         "scales light 0 by 1e+39 (outside 1e-6..1e6); lights are not scaled in glTF, so the scale is ignored"},
    };
    for (auto& c : cases) {
        const std::string name = c.name;
        CAPTURE(name);
        doc = triangleGltf(d, 1.0);
        addLight(doc, c.light, c.node);
        r = runBench("--validate-only --scene " + write(d, doc));
        CAPTURE(r.err);
        CHECK(r.rc == 0);
        CHECK(r.seconds < 5.0);
        CHECK(r.err.find(std::string("warning: ") + (d / "scene.gltf").string()) != std::string::npos);
        CHECK(r.err.find(c.warning) != std::string::npos);
    }
    // A spot light without its "spot" object: the loader's sentence, not the parser's text.
    doc = triangleGltf(d, 1.0);
    addLight(doc, {{"type", "spot"}});
    expectExit("--validate-only --scene " + write(d, doc), 3,
               "lights[0] is a spot light without its \"spot\" object (glTF requires it, with the cone angles)");
    // emissiveFactor outside 0..1.
    for (auto f : {std::vector<double>{-1, -1, -1}, std::vector<double>{5, 5, 5}}) {
        doc = triangleGltf(d, 1.0);
        makeEmissive(doc, f, 1.0);
        r = runBench("--validate-only --scene " + write(d, doc));
        CAPTURE(r.err);
        CHECK(r.rc == 0);
        CHECK(r.err.find("materials[0].emissiveFactor [") != std::string::npos);
        CHECK(r.err.find("is outside 0..1 (glTF; brighter emission goes in KHR_materials_emissive_strength)") != std::string::npos);
    }
}

TEST_CASE("hardening: sweep and config mistakes that were accepted silently are errors naming the key") {
    fs::path d = scratch("sweeps");
    const std::string out = " --out " + (d / "out").string();
    writeFile(d / "res.json", R"({"scenes": ["builtin:cornell"], "resolutions": "32x32"})");
    expectExit("--sweep " + (d / "res.json").string() + out, 2,
               "res.json: 'resolutions': expected a list of \"WxH\" strings (e.g. [\"1920x1080\"]), found a string");
    writeFile(d / "scenes.json", R"({"scenes": [5]})");
    expectExit("--sweep " + (d / "scenes.json").string() + out, 2,
               "scenes.json: 'scenes[0]': expected a scene (builtin:NAME or a glTF path), a list of scenes or an object "
               "with \"scene\", found a number");
    writeFile(d / "ok.json", R"({"scenes": ["builtin:cornell"]})");
    expectExit("--sweep " + (d / "ok.json").string() + out + " --set ao=gtao", 2, "--sweep: --set/--config do not apply to sweeps");
    expectExit("--sweep " + (d / "ok.json").string() + out + " --set lpv.cascades=2", 2,  // the default value too
               "--sweep: --set/--config do not apply to sweeps");
    writeFile(d / "twice.json", R"({"lpv": {"cascades": 6}, "lpv.cascades": 1})");
    expectExit("--scene builtin:cornell --validate-only --config " + (d / "twice.json").string(), 2,
               "twice.json: 'lpv.cascades' is given twice (nested and dotted); give it once");
}

TEST_CASE("hardening: --validate-only refuses an unknown named view with the run's sentence") {
    // The view is resolved without GL; before, only a rendering run reported it.
    const std::string sentence = "setting 'view': no view named 'nope' for scene builtin:cornell in benchmarks/views/";
    expectExit("--scene builtin:cornell --validate-only --set view=nope", 2, sentence);
    fs::path d = scratch("views");
    expectExit("--scene builtin:cornell --res 32x32 --frames 1 --warmup 0 --no-images --set view=nope --out " +
                   (d / "out").string(), 2, sentence);
    auto ok = runBench("--scene builtin:gallery --validate-only --set view=red-wall");  // a view of benchmarks/views/
    CAPTURE(ok.err);
    CHECK(ok.rc == 0);
    expectExit("--scene builtin:gallery --validate-only --set view=Red-Wall", 2, "no view named 'Red-Wall'");
}
