// glTF loader: every class of bad input must become one SceneError naming the
// file, and valid files must give the triangles, transforms, lights, cameras
// and materials computed by hand here. The test writes its own files (JSON
// with data URIs or external .bin, and GLB containers) into a per-process
// temporary directory.
#include "scene/scene.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>
#include <stb_image_write.h>

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using rtgi::loadGltf;
using rtgi::SceneError;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

struct TempDir {
    fs::path dir;
    TempDir() {
        dir = fs::temp_directory_path() / ("rtgi-gltf-tests-" + std::to_string(::getpid()));
        fs::create_directories(dir);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
};
const fs::path& tempDir() {
    static TempDir t;
    return t.dir;
}

using Bytes = std::vector<unsigned char>;

std::string base64(const Bytes& in) {
    static const char* tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        unsigned v = unsigned(in[i]) << 16 | unsigned(in[i + 1]) << 8 | in[i + 2];
        out += tbl[v >> 18];
        out += tbl[(v >> 12) & 63];
        out += tbl[(v >> 6) & 63];
        out += tbl[v & 63];
    }
    if (i + 1 == in.size()) {
        unsigned v = unsigned(in[i]) << 16;
        out += tbl[v >> 18];
        out += tbl[(v >> 12) & 63];
        out += "==";
    } else if (i + 2 == in.size()) {
        unsigned v = unsigned(in[i]) << 16 | unsigned(in[i + 1]) << 8;
        out += tbl[v >> 18];
        out += tbl[(v >> 12) & 63];
        out += tbl[(v >> 6) & 63];
        out += '=';
    }
    return out;
}

template <class T>
void put(Bytes& b, std::size_t at, T v) {
    std::memcpy(b.data() + at, &v, sizeof(T));
}
template <class T>
std::size_t append(Bytes& b, const std::vector<T>& v) {
    while (b.size() % 4) b.push_back(0);
    std::size_t off = b.size();
    b.resize(off + v.size() * sizeof(T));
    std::memcpy(b.data() + off, v.data(), v.size() * sizeof(T));
    return off;
}

// A glTF document and its one binary buffer (not yet attached).
struct Asset {
    json doc;
    Bytes bin;

    int addView(std::size_t offset, std::size_t length) {
        doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}});
        return int(doc["bufferViews"].size()) - 1;
    }
    int addAccessor(int view, int componentType, std::size_t count, const char* type) {
        doc["accessors"].push_back(
            {{"bufferView", view}, {"componentType", componentType}, {"count", count}, {"type", type}});
        return int(doc["accessors"].size()) - 1;
    }
    template <class T>
    int addData(const std::vector<T>& v, int componentType, std::size_t count, const char* type) {
        std::size_t off = append(bin, v);
        return addAccessor(addView(off, v.size() * sizeof(T)), componentType, count, type);
    }
};

constexpr int kU8 = 5121, kU16 = 5123, kU32 = 5125, kF32 = 5126;

enum class Idx { U8, U16, U32, None };

// Unit quad in the z = 0 plane facing +z: two triangles (0,1,2), (0,2,3).
Asset quad(Idx idx = Idx::U16, bool withNormals = true) {
    Asset a;
    a.doc = {{"asset", {{"version", "2.0"}}},
             {"scene", 0},
             {"scenes", json::array({{{"nodes", json::array({0})}}})},
             {"nodes", json::array({{{"mesh", 0}}})},
             {"materials",
              json::array({{{"name", "red"},
                            {"pbrMetallicRoughness",
                             {{"baseColorFactor", {1.0, 0.5, 0.25, 1.0}},
                              {"metallicFactor", 0.0},
                              {"roughnessFactor", 0.5}}}}})},
             {"accessors", json::array()},
             {"bufferViews", json::array()}};
    std::vector<float> p = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    std::vector<float> n = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    std::vector<float> uv = {0, 0, 1, 0, 1, 1, 0, 1};
    std::vector<unsigned> tri = {0, 1, 2, 0, 2, 3};
    json attrs;
    if (idx == Idx::None) {  // six vertices
        std::vector<float> p6, n6, uv6;
        for (unsigned i : tri) {
            for (unsigned k = 0; k < 3; ++k) {
                p6.push_back(p[i * 3 + k]);
                n6.push_back(n[i * 3 + k]);
            }
            for (unsigned k = 0; k < 2; ++k) uv6.push_back(uv[i * 2 + k]);
        }
        p = p6;
        n = n6;
        uv = uv6;
    }
    std::size_t nv = p.size() / 3;
    attrs["POSITION"] = a.addData(p, kF32, nv, "VEC3");
    a.doc["accessors"][0]["min"] = {0, 0, 0};
    a.doc["accessors"][0]["max"] = {1, 1, 0};
    if (withNormals) attrs["NORMAL"] = a.addData(n, kF32, nv, "VEC3");
    attrs["TEXCOORD_0"] = a.addData(uv, kF32, nv, "VEC2");
    json prim = {{"attributes", attrs}, {"material", 0}, {"mode", 4}};
    if (idx == Idx::U8) prim["indices"] = a.addData(std::vector<std::uint8_t>(tri.begin(), tri.end()), kU8, 6, "SCALAR");
    if (idx == Idx::U16)
        prim["indices"] = a.addData(std::vector<std::uint16_t>(tri.begin(), tri.end()), kU16, 6, "SCALAR");
    if (idx == Idx::U32) prim["indices"] = a.addData(tri, kU32, 6, "SCALAR");
    a.doc["meshes"] = json::array({{{"name", "quad"}, {"primitives", json::array({prim})}}});
    return a;
}

std::string writeText(const std::string& name, const std::string& text) {
    fs::path p = tempDir() / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
}
std::string writeBytes(const std::string& name, const Bytes& bytes) {
    fs::path p = tempDir() / name;
    std::ofstream f(p, std::ios::binary);
    f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    return p.string();
}

// .gltf with the buffer as a data URI.
std::string writeEmbedded(const std::string& name, Asset a) {
    a.doc["buffers"] = json::array(
        {{{"byteLength", a.bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(a.bin)}}});
    return writeText(name, a.doc.dump());
}
// .gltf with the buffer in NAME.bin next to it.
std::string writeExternal(const std::string& name, Asset a) {
    std::string binName = fs::path(name).stem().string() + ".bin";
    writeBytes(binName, a.bin);
    a.doc["buffers"] = json::array({{{"byteLength", a.bin.size()}, {"uri", binName}}});
    return writeText(name, a.doc.dump());
}

Bytes glbBytes(Asset a) {
    a.doc["buffers"] = json::array({{{"byteLength", a.bin.size()}}});
    std::string text = a.doc.dump();
    while (text.size() % 4) text += ' ';
    Bytes bin = a.bin;
    while (bin.size() % 4) bin.push_back(0);
    Bytes out(12);
    auto chunk = [&](std::uint32_t type, const unsigned char* data, std::size_t n) {
        std::size_t at = out.size();
        out.resize(at + 8 + n);
        put(out, at, std::uint32_t(n));
        put(out, at + 4, type);
        std::memcpy(out.data() + at + 8, data, n);
    };
    chunk(0x4E4F534Au, reinterpret_cast<const unsigned char*>(text.data()), text.size());
    chunk(0x004E4942u, bin.data(), bin.size());
    std::memcpy(out.data(), "glTF", 4);
    put(out, 4, std::uint32_t(2));
    put(out, 8, std::uint32_t(out.size()));
    return out;
}

Bytes pngBytes(int w, int h, const std::vector<unsigned char>& rgba) {
    Bytes out;
    stbi_write_png_to_func(
        [](void* ctx, void* data, int size) {
            auto* o = static_cast<Bytes*>(ctx);
            auto* d = static_cast<unsigned char*>(data);
            o->insert(o->end(), d, d + size);
        },
        &out, w, h, 4, rgba.data(), w * 4);
    return out;
}

// Loads and expects a SceneError whose message names the file and contains `word`.
void expectError(const std::string& path, const std::string& word) {
    CAPTURE(path);
    CAPTURE(word);
    try {
        (void)loadGltf(path);
        FAIL("no SceneError was thrown");
    } catch (const SceneError& e) {
        std::string msg = e.what();
        CAPTURE(msg);
        CHECK(msg.find(path) != std::string::npos);
        CHECK(msg.find(word) != std::string::npos);
        CHECK(msg.find('\n') == std::string::npos);
    }
}

bool near3(glm::vec3 a, glm::vec3 b, float eps = 1e-5f) { return glm::length(a - b) <= eps; }

bool hasWarning(const rtgi::Scene& s, const std::string& word) {
    for (const auto& w : s.warnings)
        if (w.find(word) != std::string::npos) return true;
    return false;
}

// World-space triangles as position triplets.
std::vector<std::array<glm::vec3, 3>> triangles(const rtgi::Scene& s) {
    std::vector<std::array<glm::vec3, 3>> out;
    for (std::size_t t = 0; t + 2 < s.indices.size(); t += 3)
        out.push_back({s.vertices[s.indices[t]].position, s.vertices[s.indices[t + 1]].position,
                       s.vertices[s.indices[t + 2]].position});
    return out;
}

// The shared scenes directory: RTGI_SHARED_SCENES from the environment if set
// (worktrees outside the main checkout), else the compile-time default.
std::string sharedScenes() {
    const char* env = std::getenv("RTGI_SHARED_SCENES");
    return env && *env ? std::string(env) : std::string(RTGI_SHARED_SCENES);
}

bool sharedScenesPresent() {
    if (fs::is_directory(sharedScenes())) return true;
    MESSAGE("skipped: " << sharedScenes() << " is absent (set RTGI_SHARED_SCENES to override)");
    return false;
}

}  // namespace

// ---------------------------------------------------------------------------
// Bad input, one class per test case.

TEST_CASE("gltf: a missing file is a SceneError") {
    std::string p = (tempDir() / "does-not-exist.gltf").string();
    expectError(p, "does not exist");
    expectError(tempDir().string(), "directory");
}

TEST_CASE("gltf: files that are not glTF are SceneErrors") {
    Bytes noise(1000);
    std::uint32_t x = 12345;
    for (auto& b : noise) b = static_cast<unsigned char>((x = x * 1664525u + 1013904223u) >> 24);
    noise[0] = 0x89;  // not '{', not "glTF"
    expectError(writeBytes("noise.gltf", noise), "not a glTF file");
    expectError(writeBytes("noise.glb", noise), "not a glTF file");
    expectError(writeText("empty.gltf", ""), "empty");
    expectError(writeText("broken.gltf", "{\"asset\": {\"version\": \"2.0\""), "not valid JSON");
    expectError(writeText("other.gltf", R"({"name": "a JSON file", "values": [1, 2, 3]})"), "not a glTF asset");
    expectError(writeText("v1.gltf", R"({"asset": {"version": "1.0"}})"), "version");
    expectError(writeText("deep.gltf", "{\"asset\":{\"version\":\"2.0\"},\"extras\":" + std::string(100000, '[') +
                                           std::string(100000, ']') + "}"),
                "deeper");
    Bytes glb = glbBytes(quad());
    put(glb, 4, std::uint32_t(1));
    expectError(writeBytes("v1.glb", glb), "version");
}

TEST_CASE("gltf: missing external buffers and images are SceneErrors") {
    Asset a = quad();
    a.doc["buffers"] = json::array({{{"byteLength", a.bin.size()}, {"uri", "nowhere.bin"}}});
    expectError(writeText("missing-buffer.gltf", a.doc.dump()), "buffer 'nowhere.bin'");
    expectError(writeText("missing-buffer2.gltf", a.doc.dump()), "missing");

    Asset b = quad();
    b.doc["images"] = json::array({{{"uri", "nowhere.png"}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    b.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    std::string p = writeEmbedded("missing-image.gltf", b);
    expectError(p, "image 'nowhere.png'");
    expectError(p, "missing");
}

TEST_CASE("gltf: truncated external buffers and images are SceneErrors") {
    Asset a = quad();
    std::string p = writeExternal("short-buffer.gltf", a);
    Bytes cut(a.bin.begin(), a.bin.begin() + 40);
    writeBytes("short-buffer.bin", cut);
    expectError(p, "truncated");
    Bytes longer = a.bin;
    longer.resize(a.bin.size() + 64);
    writeBytes("short-buffer.bin", longer);
    expectError(p, "byteLength");

    Asset b = quad();
    Bytes png = pngBytes(8, 8, std::vector<unsigned char>(8 * 8 * 4, 200));
    png.resize(png.size() / 2);
    writeBytes("half.png", png);
    b.doc["images"] = json::array({{{"uri", "half.png"}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    b.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    expectError(writeEmbedded("half-image.gltf", b), "image 0 ('half.png')");
}

TEST_CASE("gltf: declared sizes beyond the data are SceneErrors") {
    SUBCASE("embedded buffer shorter than its byteLength") {
        Asset a = quad();
        a.doc["buffers"] = json::array({{{"byteLength", a.bin.size() + 100},
                                         {"uri", "data:application/octet-stream;base64," + base64(a.bin)}}});
        expectError(writeText("short-embedded.gltf", a.doc.dump()), "byteLength");
    }
    SUBCASE("bufferView beyond its buffer") {
        Asset a = quad();
        a.doc["bufferViews"][0]["byteLength"] = 4096;
        expectError(writeEmbedded("long-view.gltf", a), "bufferView 0");
        a.doc["bufferViews"][0]["byteLength"] = 48;
        a.doc["bufferViews"][0]["byteOffset"] = std::uint64_t(1) << 40;
        expectError(writeEmbedded("far-view.gltf", a), "extends beyond buffer 0");
    }
    SUBCASE("accessor beyond its bufferView") {
        Asset a = quad();
        a.doc["accessors"][0]["count"] = 5;
        expectError(writeEmbedded("long-accessor.gltf", a), "accessor 0");
        a.doc["accessors"][0]["count"] = std::uint64_t(1) << 62;
        expectError(writeEmbedded("huge-accessor.gltf", a), "reads beyond the end of bufferView");
        a.doc["accessors"][0]["count"] = 4;
        a.doc["accessors"][0]["byteOffset"] = 4;
        expectError(writeEmbedded("offset-accessor.gltf", a), "accessor 0");
    }
    SUBCASE("byteStride smaller than the element") {
        Asset a = quad();
        a.doc["bufferViews"][0]["byteStride"] = 4;
        expectError(writeEmbedded("stride.gltf", a), "byteStride");
    }
    SUBCASE("truncated GLB") {
        Bytes glb = glbBytes(quad());
        Bytes cut(glb.begin(), glb.end() - 16);
        expectError(writeBytes("cut.glb", cut), "truncated");
        Bytes lying = glb;
        put(lying, 8, std::uint32_t(glb.size() * 4));
        expectError(writeBytes("lying.glb", lying), "truncated");
        // BIN chunk header claiming more than the file has.
        Bytes bin = glb;
        std::uint32_t jsonLen;
        std::memcpy(&jsonLen, bin.data() + 12, 4);
        put(bin, 20 + jsonLen, std::uint32_t(1 << 20));
        expectError(writeBytes("bin-chunk.glb", bin), "BIN chunk");
    }
}

TEST_CASE("gltf: indices out of range are SceneErrors") {
    for (Idx idx : {Idx::U8, Idx::U16, Idx::U32}) {
        Asset a = quad(idx);
        std::size_t off = a.doc["bufferViews"][3]["byteOffset"].get<std::size_t>() + 0;
        if (idx == Idx::U8) a.bin[off + 4] = 7;
        if (idx == Idx::U16) put(a.bin, off + 8, std::uint16_t(60000));
        if (idx == Idx::U32) put(a.bin, off + 8, std::uint32_t(0xFFFFFFFFu));
        expectError(writeEmbedded("bad-index.gltf", a), "out of range");
    }
    Asset a = quad();
    a.doc["meshes"][0]["primitives"][0]["indices"] = 17;
    expectError(writeEmbedded("bad-index-accessor.gltf", a), "accessor");
}

TEST_CASE("gltf: NaN and infinite positions are SceneErrors") {
    Asset a = quad();
    put(a.bin, 12, std::numeric_limits<float>::quiet_NaN());
    expectError(writeEmbedded("nan.gltf", a), "NaN");
    Asset b = quad();
    put(b.bin, 20, std::numeric_limits<float>::infinity());
    expectError(writeEmbedded("inf.gltf", b), "infinite");
}

TEST_CASE("gltf: wrong accessor types are SceneErrors") {
    Asset a = quad();
    a.doc["accessors"][0]["type"] = "VEC2";
    expectError(writeEmbedded("pos-vec2.gltf", a), "POSITION must be a float VEC3");
    Asset b = quad();
    b.doc["accessors"][0]["componentType"] = kU8;
    expectError(writeEmbedded("pos-u8.gltf", b), "POSITION must be a float VEC3 accessor, but accessor 0 is u8 VEC3");
    Asset c = quad();
    c.doc["accessors"][3]["componentType"] = kF32;
    c.doc["accessors"][3]["count"] = 3;
    expectError(writeEmbedded("idx-float.gltf", c), "indices must be");
    Asset d = quad();
    d.doc["accessors"][1]["type"] = "VEC4";
    d.doc["accessors"][1]["count"] = 3;
    expectError(writeEmbedded("normal-vec4.gltf", d), "NORMAL");
    Asset e = quad();
    e.doc["meshes"][0]["primitives"][0]["attributes"].erase("POSITION");
    expectError(writeEmbedded("no-position.gltf", e), "POSITION");
}

TEST_CASE("gltf: node hierarchies with cycles or bad indices are SceneErrors") {
    Asset a = quad();
    a.doc["nodes"] = json::array({{{"children", {1}}}, {{"children", {2}}, {"mesh", 0}}, {{"children", {1}}}});
    expectError(writeEmbedded("cycle.gltf", a), "cycle");
    a.doc["nodes"] = json::array({{{"children", {0}}, {"mesh", 0}}});
    expectError(writeEmbedded("self-cycle.gltf", a), "cycle");
    a.doc["nodes"] = json::array({{{"children", {5}}, {"mesh", 0}}});
    expectError(writeEmbedded("bad-child.gltf", a), "nodes[0].children[0]: expected an index into nodes");
    a.doc["nodes"] = json::array({{{"mesh", 3}}});
    expectError(writeEmbedded("bad-mesh.gltf", a), "nodes[0].mesh: expected an index into meshes (0..0), found 3");
    a.doc["nodes"] = json::array({{{"mesh", 0}}});
    a.doc["scenes"][0]["nodes"] = {4};
    expectError(writeEmbedded("bad-root.gltf", a), "scenes[0].nodes[0]: expected an index into nodes");
    a.doc["scenes"][0]["nodes"] = {0};
    a.doc["scene"] = 2;
    expectError(writeEmbedded("bad-scene.gltf", a), "scene: expected an index into scenes (0..0), found 2");
    Asset b = quad();
    b.doc["meshes"][0]["primitives"][0]["material"] = 9;
    expectError(writeEmbedded("bad-material.gltf", b), "meshes[0].primitives[0].material: expected an index into materials (0..0), found 9");
    Asset c = quad();
    c.doc["nodes"][0]["matrix"] = {1, 0, 0};
    expectError(writeEmbedded("bad-matrix.gltf", c), "matrix");
}

TEST_CASE("gltf: absurd instancing is a SceneError, not a hang") {
    // Every node lists the next one twice: 2^k instances of the leaf.
    auto chain = [](int levels) {
        Asset a = quad();
        json nodes = json::array();
        for (int i = 0; i < levels; ++i) nodes.push_back({{"children", {i + 1, i + 1}}});
        nodes.push_back({{"mesh", 0}});
        a.doc["nodes"] = nodes;
        return a;
    };
    auto t0 = std::chrono::steady_clock::now();
    // glTF 2.0 requires unique children and strict trees (gltf_schema.cpp),
    // so the doubling chains are refused at once; the instance, triangle and
    // vertex bounds of walkNodes remain as a second line.
    expectError(writeEmbedded("instances.gltf", chain(60)), "lists 1 a second time");
    // Fewer instances, but a 300-triangle mesh: 2^19 · 300 > 1e8 triangles.
    Asset b = chain(19);
    std::vector<float> p;
    for (int t = 0; t < 300; ++t)
        for (float v : {0.f, 0.f, float(t), 1.f, 0.f, float(t), 0.f, 1.f, float(t)}) p.push_back(v);
    json attrs = {{"POSITION", b.addData(p, kF32, p.size() / 3, "VEC3")}};
    b.doc["meshes"][0]["primitives"] = json::array({{{"attributes", attrs}}});
    expectError(writeEmbedded("triangles.gltf", b), "a second time");
    // One triangle, but 1000 vertices per instance: 2^19 · 1000 > 3e8 vertices.
    Asset c = chain(19);
    std::vector<float> many(3000, 0.0f);
    many[3] = 1.0f;
    many[7] = 1.0f;
    json attrs2 = {{"POSITION", c.addData(many, kF32, 1000, "VEC3")},
                   {"NORMAL", c.addData(std::vector<float>(3000, 1.0f), kF32, 1000, "VEC3")}};
    int tri = c.addData(std::vector<std::uint16_t>{0, 1, 2}, kU16, 3, "SCALAR");
    c.doc["meshes"][0]["primitives"] = json::array({{{"attributes", attrs2}, {"indices", tri}}});
    expectError(writeEmbedded("vertices.gltf", c), "a second time");
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    CHECK(seconds < 2.0);
    // Many (valid) instances: 2^15 nodes sharing one mesh stay fast
    // (flattening is linear).
    Asset m = quad();
    json nodesMany = json::array(), roots = json::array();
    for (int i = 0; i < (1 << 15); ++i) {
        nodesMany.push_back({{"mesh", 0}, {"translation", {double(i % 256), double(i / 256), 0.0}}});
        roots.push_back(i);
    }
    m.doc["nodes"] = nodesMany;
    m.doc["scenes"][0]["nodes"] = roots;
    t0 = std::chrono::steady_clock::now();
    rtgi::Scene s = loadGltf(writeEmbedded("many.gltf", m));
    CHECK(s.triangleCount() == 2u << 15);
    CHECK(s.draws.size() == 1u << 15);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    MESSAGE("2^15 instances of a quad: " << seconds << " s");
    CHECK(seconds < 5.0);
}

TEST_CASE("gltf: unsupported extensionsRequired is a SceneError naming the extension") {
    Asset a = quad();
    a.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    a.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    expectError(writeEmbedded("draco.gltf", a), "KHR_draco_mesh_compression");
    a.doc["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_texture_transform"};
    a.doc["extensionsRequired"] = a.doc["extensionsUsed"];
    CHECK(loadGltf(writeEmbedded("supported-required.gltf", a)).triangleCount() == 2);
}

TEST_CASE("gltf: scenes without triangles are SceneErrors") {
    Asset a = quad();
    a.doc["nodes"] = json::array({{{"name", "empty"}}});
    expectError(writeEmbedded("no-mesh.gltf", a), "no triangles");
    Asset b = quad();
    b.doc["meshes"][0]["primitives"][0]["mode"] = 1;  // lines only
    expectError(writeEmbedded("lines-only.gltf", b), "no triangles");
    Asset c = quad();
    put(c.bin, 12, 0.0f);  // vertex 1 = vertex 0, vertex 2 on the same line: both triangles degenerate
    put(c.bin, 24, 0.0f);
    put(c.bin, 28, 0.0f);
    put(c.bin, 36, 0.0f);
    put(c.bin, 40, 0.0f);
    expectError(writeEmbedded("degenerate.gltf", c), "no triangles");
    json bare = {{"asset", {{"version", "2.0"}}}};
    expectError(writeText("bare.gltf", bare.dump()), "no triangles");
}

// ---------------------------------------------------------------------------
// Valid input.

TEST_CASE("gltf: u8, u16, u32 and non-indexed primitives give the same triangles") {
    rtgi::Scene ref = loadGltf(writeEmbedded("idx-u16.gltf", quad(Idx::U16)));
    REQUIRE(ref.triangleCount() == 2);
    auto expected = triangles(ref);
    CHECK(near3(expected[0][0], {0, 0, 0}));
    CHECK(near3(expected[0][1], {1, 0, 0}));
    CHECK(near3(expected[0][2], {1, 1, 0}));
    CHECK(near3(expected[1][2], {0, 1, 0}));
    CHECK(ref.name == (tempDir() / "idx-u16.gltf").string());
    CHECK(ref.warnings.empty());
    for (Idx idx : {Idx::U8, Idx::U32, Idx::None}) {
        rtgi::Scene s = loadGltf(writeEmbedded("idx.gltf", quad(idx)));
        auto got = triangles(s);
        REQUIRE(got.size() == expected.size());
        for (std::size_t t = 0; t < got.size(); ++t)
            for (int k = 0; k < 3; ++k) CHECK(near3(got[t][std::size_t(k)], expected[t][std::size_t(k)]));
        for (const auto& v : s.vertices) CHECK(near3(v.normal, {0, 0, 1}));
        REQUIRE(s.draws.size() == 1);
        CHECK(s.draws[0].indexCount == 6);
    }
    // The same quad from an external .bin.
    CHECK(triangles(loadGltf(writeExternal("external.gltf", quad()))).size() == 2);
}

TEST_CASE("gltf: node transforms compose to world space") {
    Asset a = quad();
    const float h = std::sqrt(0.5f);
    // Parent: translate (10,0,0) and rotate 90 degrees about +z; child: scale 2.
    a.doc["nodes"] = json::array(
        {{{"translation", {10, 0, 0}}, {"rotation", {0, 0, h, h}}, {"children", {1}}},
         {{"scale", {2, 2, 2}}, {"mesh", 0}},
         // Mirrored instance given as a matrix: scale x by -1, translate (0,0,5).
         {{"matrix", {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1}}, {"mesh", 0}}});
    a.doc["scenes"][0]["nodes"] = {0, 2};
    rtgi::Scene s = loadGltf(writeEmbedded("hierarchy.gltf", a));
    REQUIRE(s.triangleCount() == 4);
    REQUIRE(s.draws.size() == 2);
    auto t = triangles(s);
    // (x,y,0) -> scale -> (2x,2y,0) -> rotate -> (-2y,2x,0) -> translate -> (10-2y, 2x, 0)
    CHECK(near3(t[0][0], {10, 0, 0}));
    CHECK(near3(t[0][1], {10, 2, 0}));
    CHECK(near3(t[0][2], {8, 2, 0}));
    CHECK(near3(t[1][2], {8, 0, 0}));
    for (std::size_t v = 0; v < 4; ++v) CHECK(near3(s.vertices[v].normal, {0, 0, 1}));
    // Mirrored instance: positions (-x, y, 5), normal still +z, winding flipped
    // so that the geometric normal agrees with the vertex normal.
    bool found = false;
    for (const auto& tri : t) {
        glm::vec3 gn = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
        CHECK(gn.z > 0.0f);
        if (near3(tri[0], {0, 0, 5}) && (near3(tri[1], {-1, 1, 5}) || near3(tri[2], {-1, 1, 5}))) found = true;
    }
    CHECK(found);
    for (std::size_t v = 4; v < s.vertices.size(); ++v) CHECK(near3(s.vertices[v].normal, {0, 0, 1}));
}

TEST_CASE("gltf: KHR_lights_punctual lights are placed by their nodes") {
    Asset a = quad();
    const float h = std::sqrt(0.5f);
    a.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    a.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array(
        {{{"type", "directional"}, {"color", {1.0, 0.9, 0.8}}, {"intensity", 3.0}, {"name", "sun"}},
         {{"type", "point"}, {"intensity", 20.0}, {"range", 7.0}},
         {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}}});
    a.doc["nodes"].push_back(  // -90 degrees about x: -z turns into -y
        {{"rotation", {-h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    a.doc["nodes"].push_back({{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    a.doc["nodes"].push_back({{"translation", {0, 4, 0}},
                              {"rotation", {0, h, 0, h}},  // +90 degrees about y: -z turns into -x
                              {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
    a.doc["scenes"][0]["nodes"] = {0, 1, 2, 3};
    rtgi::Scene s = loadGltf(writeEmbedded("lights.gltf", a));
    REQUIRE(s.lights.size() == 3);
    REQUIRE(s.sun() != nullptr);
    CHECK(s.sun()->name == "sun");
    CHECK(near3(s.sun()->direction, {0, -1, 0}));
    CHECK(near3(s.sun()->color, {1.0f, 0.9f, 0.8f}));
    CHECK(s.sun()->intensity == doctest::Approx(3.0));
    CHECK(s.lights[1].type == rtgi::LightType::Point);
    CHECK(near3(s.lights[1].position, {1, 2, 3}));
    CHECK(s.lights[1].range == doctest::Approx(7.0));
    CHECK(s.lights[2].type == rtgi::LightType::Spot);
    CHECK(near3(s.lights[2].position, {0, 4, 0}));
    CHECK(near3(s.lights[2].direction, {-1, 0, 0}));
    CHECK(s.lights[2].innerCone == doctest::Approx(0.2));
    CHECK(s.lights[2].outerCone == doctest::Approx(0.5));

    a.doc["nodes"][1]["extensions"]["KHR_lights_punctual"]["light"] = 8;
    expectError(writeEmbedded("bad-light.gltf", a), "KHR_lights_punctual.light: expected an index");
}

TEST_CASE("gltf: perspective cameras are placed by their nodes") {
    Asset a = quad();
    a.doc["cameras"] = json::array(
        {{{"type", "perspective"}, {"name", "cam"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}},
         {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.5}, {"zfar", 50.0}}}}});
    const float h = std::sqrt(0.5f);
    a.doc["nodes"].push_back({{"translation", {0, 1, 5}}, {"camera", 0}});
    a.doc["nodes"].push_back({{"translation", {3, 0, 0}}, {"rotation", {0, h, 0, h}}, {"camera", 1}});
    a.doc["scenes"][0]["nodes"] = {0, 1, 2};
    rtgi::Scene s = loadGltf(writeEmbedded("camera.gltf", a));
    REQUIRE(s.cameras.size() == 2);
    const rtgi::Camera& c = s.cameras[0];
    CHECK(c.name == "cam");
    CHECK(near3(c.position, {0, 1, 5}));
    CHECK(near3(glm::normalize(c.target - c.position), {0, 0, -1}));
    CHECK(near3(c.up, {0, 1, 0}));
    CHECK(c.fovY == doctest::Approx(0.8));
    CHECK(c.near == doctest::Approx(0.1));
    CHECK(c.far == doctest::Approx(1000.0 * std::sqrt(2.0)).epsilon(1e-3));  // no zfar: 1000x the diagonal
    const rtgi::Camera& d = s.cameras[1];
    CHECK(near3(d.position, {3, 0, 0}));
    CHECK(near3(glm::normalize(d.target - d.position), {-1, 0, 0}));
    CHECK(d.far == doctest::Approx(50.0));
}

TEST_CASE("gltf: a GLB container gives the same scene as the .gltf") {
    rtgi::Scene ref = loadGltf(writeEmbedded("ref.gltf", quad(Idx::U32)));
    rtgi::Scene s = loadGltf(writeBytes("quad.glb", glbBytes(quad(Idx::U32))));
    CHECK(s.warnings.empty());
    auto a = triangles(ref), b = triangles(s);
    REQUIRE(a.size() == b.size());
    for (std::size_t t = 0; t < a.size(); ++t)
        for (int k = 0; k < 3; ++k) CHECK(near3(a[t][std::size_t(k)], b[t][std::size_t(k)]));
    REQUIRE(s.materials.size() == 1);
    CHECK(s.materials[0].name == "red");
    CHECK(near3(glm::vec3(s.materials[0].baseColor), {1.0f, 0.5f, 0.25f}));
    CHECK(s.materials[0].roughness == doctest::Approx(0.5));
    CHECK(s.materials[0].metallic == doctest::Approx(0.0));
}

TEST_CASE("gltf: zero-length normals are repaired with a warning") {
    Asset a = quad();
    std::size_t normals = a.doc["bufferViews"][1]["byteOffset"].get<std::size_t>();
    put(a.bin, normals + 8, 0.0f);  // normal of vertex 0 = (0,0,0)
    rtgi::Scene s = loadGltf(writeEmbedded("zero-normal.gltf", a));
    CHECK(s.triangleCount() == 2);
    CHECK(hasWarning(s, "normals"));
    for (const auto& v : s.vertices) CHECK(near3(v.normal, {0, 0, 1}));
}

TEST_CASE("gltf: missing normals become flat normals; degenerate triangles are dropped") {
    Asset a = quad(Idx::U16, /*withNormals=*/false);
    rtgi::Scene s = loadGltf(writeEmbedded("flat.gltf", a));
    CHECK(s.triangleCount() == 2);
    CHECK(s.vertices.size() == 6);
    for (const auto& v : s.vertices) CHECK(near3(v.normal, {0, 0, 1}));

    Asset b = quad(Idx::U8);
    std::size_t idx = b.doc["bufferViews"][3]["byteOffset"].get<std::size_t>();
    b.bin[idx + 4] = 0;  // second triangle becomes (0,0,3)
    rtgi::Scene t = loadGltf(writeEmbedded("degenerate-one.gltf", b));
    CHECK(t.triangleCount() == 1);
    CHECK(hasWarning(t, "degenerate"));
}

TEST_CASE("gltf: materials, base colour textures and the default material") {
    Asset a = quad();
    std::vector<unsigned char> rgba = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128};
    Bytes png = pngBytes(2, 2, rgba);
    writeBytes("tex.png", png);
    a.doc["images"] = json::array({{{"uri", "tex.png"}}, {{"uri", "data:image/png;base64," + base64(png)}}});
    a.doc["textures"] = json::array({{{"source", 0}}, {{"source", 1}}});
    a.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    a.doc["materials"][0]["emissiveFactor"] = {1.0, 0.5, 0.0};
    a.doc["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = 4.0;
    a.doc["materials"].push_back({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}, {"doubleSided", true}});
    // Second mesh: the same quad with the second material, third: without material.
    json prim = a.doc["meshes"][0]["primitives"][0];
    prim["material"] = 1;
    json noMat = prim;
    noMat.erase("material");
    json lines = prim;
    lines["mode"] = 1;
    a.doc["meshes"][0]["primitives"].push_back(prim);
    a.doc["meshes"][0]["primitives"].push_back(noMat);
    a.doc["meshes"][0]["primitives"].push_back(lines);
    rtgi::Scene s = loadGltf(writeEmbedded("materials.gltf", a));
    CHECK(s.triangleCount() == 6);
    REQUIRE(s.draws.size() == 3);
    REQUIRE(s.materials.size() == 3);
    CHECK(s.draws[0].material == 0);
    CHECK(s.draws[1].material == 1);
    CHECK(s.draws[2].material == 2);
    CHECK(s.materials[2].name == "default");
    CHECK(s.materials[2].baseColorTexture == -1);
    CHECK(near3(s.materials[0].emissive, {4.0f, 2.0f, 0.0f}));
    CHECK(s.materials[1].metallic == doctest::Approx(1.0));  // glTF default
    CHECK_FALSE(s.materials[0].doubleSided);  // glTF default: single-sided (emits from the front face only)
    CHECK(s.materials[1].doubleSided);
    REQUIRE(s.images.size() == 2);
    CHECK(s.materials[0].baseColorTexture == 0);
    CHECK(s.materials[1].baseColorTexture == 1);
    for (const auto& img : s.images) {
        CHECK(img.width == 2);
        CHECK(img.height == 2);
        CHECK(img.rgba == rgba);
    }
    CHECK(hasWarning(s, "lines"));

    a.doc["textures"][1]["source"] = 7;
    expectError(writeEmbedded("bad-texture.gltf", a), "textures[1].source: expected an index into images (0..1), found 7");
    a.doc["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 5;
    expectError(writeEmbedded("bad-texture2.gltf", a), "baseColorTexture.index: expected an index into textures (0..1), found 5");
}

TEST_CASE("gltf: images in bufferViews are bounds-checked and decoded") {
    Asset a = quad();
    std::vector<unsigned char> rgba(4 * 4 * 4, 77);
    Bytes png = pngBytes(4, 4, rgba);
    std::size_t off = append(a.bin, png);
    int view = a.addView(off, png.size());
    a.doc["images"] = json::array({{{"bufferView", view}, {"mimeType", "image/png"}}});
    a.doc["textures"] = json::array({{{"source", 0}}});
    a.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    rtgi::Scene s = loadGltf(writeBytes("image-view.glb", glbBytes(a)));
    REQUIRE(s.images.size() == 1);
    CHECK(s.images[0].rgba == rgba);
    a.doc["bufferViews"][std::size_t(view)]["byteLength"] = png.size() + 100000;
    expectError(writeBytes("image-view-long.glb", glbBytes(a)), "bufferView");
}

TEST_CASE("gltf: the real scenes load with their triangle counts") {
    if (!sharedScenesPresent()) return;
    const std::string dir = sharedScenes();
    struct Case {
        std::string file;
        std::size_t triangles;
    };
    for (const Case& c : {Case{dir + "/stanford-bunny/bunny.gltf", 69451},
                          Case{dir + "/stanford-dragon/dragon.gltf", 100000},
                          Case{dir + "/cornell-box/cornell-box.gltf", 36}}) {
        CAPTURE(c.file);
        auto t0 = std::chrono::steady_clock::now();
        rtgi::Scene s = loadGltf(c.file);
        double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        MESSAGE(c.file << ": " << s.triangleCount() << " triangles in " << ms << " ms");
        CHECK(s.triangleCount() == c.triangles);
        CHECK(s.name == c.file);
        CHECK(ms < 1000.0);
        for (const auto& w : s.warnings) MESSAGE(w);
    }
    rtgi::Scene cb = loadGltf(dir + "/cornell-box/cornell-box.gltf");
    CHECK(cb.materials.size() == 8);
    CHECK(cb.draws.size() == 8);
    bool light = false;
    for (const auto& m : cb.materials)
        if (m.name == "light") {
            light = true;
            CHECK(near3(m.emissive, glm::vec3(1.0f, 0.706f, 0.235f) * 17.0f, 0.02f));
        }
    CHECK(light);
    CHECK(cb.lights.empty());
    CHECK(cb.cameras.empty());
}

// ---------------------------------------------------------------------------
// End to end: rtgi-bench itself on every broken class (issue 2 acceptance):
// an exit code 1..125 (not a signal), within 5 s, one line naming the file.

namespace {

struct BenchOutcome {
    int exitCode = -1;
    bool signalled = false;
    double seconds = 0;
    std::string stderrText;
};

BenchOutcome runBenchOn(const std::string& scenePath) {
    fs::path err = tempDir() / "bench-stderr.txt";
    std::string cmd = std::string("timeout -s KILL 20 ") + RTGI_BENCH_EXE + " --scene '" + scenePath +
                      "' --res 8x8 --frames 1 --warmup 0 --no-images --out '" + (tempDir() / "bench-out").string() +
                      "' >/dev/null 2>'" + err.string() + "'";
    auto t0 = std::chrono::steady_clock::now();
    int status = std::system(cmd.c_str());
    BenchOutcome o;
    o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (WIFEXITED(status)) {
        o.exitCode = WEXITSTATUS(status);
        o.signalled = o.exitCode > 125;  // shell reports 128+N for a signal, timeout's KILL as 137
    } else {
        o.signalled = true;
    }
    std::ifstream f(err);
    std::stringstream ss;
    ss << f.rdbuf();
    o.stderrText = ss.str();
    return o;
}

}  // namespace

TEST_CASE("rtgi-bench: every broken glTF class exits 1..125 within 5 s with one line naming the file") {
    std::vector<std::pair<std::string, std::string>> cases;  // path, what the test broke
    cases.push_back({(tempDir() / "does-not-exist.gltf").string(), "missing file"});
    cases.push_back({writeBytes("e2e-random.gltf", Bytes{0x13, 0x37, 0xff, 0x00, 0x42, 0x10}), "not glTF"});
    cases.push_back({writeText("e2e-notgltf.gltf", R"({"hello": "world"})"), "JSON that is not glTF"});
    {
        Asset a = quad();
        std::string p = writeExternal("e2e-missing-bin.gltf", a);
        fs::remove(tempDir() / "e2e-missing-bin.bin");
        cases.push_back({p, "missing buffer"});
    }
    {
        Asset a = quad();
        std::string p = writeExternal("e2e-truncated.gltf", a);
        fs::resize_file(tempDir() / "e2e-truncated.bin", 10);
        cases.push_back({p, "truncated buffer"});
    }
    {
        Asset a = quad();
        a.doc["accessors"][0]["count"] = 4000;
        cases.push_back({writeEmbedded("e2e-size.gltf", a), "declared size beyond the data"});
    }
    {
        Asset a = quad(Idx::U32);
        put(a.bin, a.doc["bufferViews"][3]["byteOffset"].get<std::size_t>() + 8, std::uint32_t(99999));
        cases.push_back({writeEmbedded("e2e-index.gltf", a), "index out of range"});
    }
    {
        Asset a = quad();
        put(a.bin, 12, std::numeric_limits<float>::quiet_NaN());
        cases.push_back({writeEmbedded("e2e-nan.gltf", a), "NaN position"});
    }
    {
        Asset a = quad();
        a.doc["accessors"][0]["type"] = "VEC2";
        cases.push_back({writeEmbedded("e2e-type.gltf", a), "wrong accessor type"});
    }
    {
        Asset a = quad();
        a.doc["nodes"] = json::array({{{"children", {1}}, {"mesh", 0}}, {{"children", {0}}}});
        cases.push_back({writeEmbedded("e2e-cycle.gltf", a), "cycle"});
    }
    {
        Asset a = quad();
        a.doc["extensionsUsed"] = {"EXT_unknown_magic"};
        a.doc["extensionsRequired"] = {"EXT_unknown_magic"};
        cases.push_back({writeEmbedded("e2e-ext.gltf", a), "unsupported required extension"});
    }
    {
        Asset a = quad();
        a.doc["nodes"] = json::array({{{"name", "empty"}}});
        cases.push_back({writeEmbedded("e2e-empty.gltf", a), "empty scene"});
    }
    for (auto& [path, what] : cases) {
        BenchOutcome o = runBenchOn(path);
        INFO(what << ": exit " << o.exitCode << " in " << o.seconds << " s, stderr: " << o.stderrText);
        CHECK_FALSE(o.signalled);
        CHECK(o.exitCode >= 1);
        CHECK(o.exitCode <= 125);
        CHECK(o.seconds < 5.0);
        // One line, naming the file.
        std::string text = o.stderrText;
        while (!text.empty() && text.back() == '\n') text.pop_back();
        CHECK(text.find('\n') == std::string::npos);
        CHECK(text.find(path) != std::string::npos);
    }
    // And a valid file still renders.
    BenchOutcome ok = runBenchOn(writeEmbedded("e2e-valid.gltf", quad()));
    INFO(ok.stderrText);
    CHECK(ok.exitCode == 0);
}

// ---- issue 16: strict typing, float ranges, double-precision degeneracy ----

namespace {
// The quad with a sun (light 0 on node 1) and a camera (camera 0 on node 2).
Asset litQuad() {
    Asset a = quad();
    a.doc["scenes"][0]["nodes"] = {0, 1, 2};
    a.doc["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    a.doc["nodes"].push_back({{"camera", 0}, {"translation", {0.5, 0.5, 3.0}}});
    a.doc["extensions"]["KHR_lights_punctual"]["lights"] =
        json::array({{{"type", "directional"}, {"color", {1.0, 1.0, 1.0}}, {"intensity", 3.0}}});
    a.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.05}, {"zfar", 100.0}}}}});
    return a;
}
// Sets the member at a JSON pointer and expects a SceneError containing `word`.
void expectMutationError(const std::string& name, const std::string& pointer, const json& value, const std::string& word) {
    Asset a = litQuad();
    a.doc[json::json_pointer(pointer)] = value;
    expectError(writeEmbedded(name, a), word);
}
}  // namespace

TEST_CASE("gltf: hardening: the valid lit quad loads (the base of the mutations below)") {
    rtgi::Scene s = loadGltf(writeEmbedded("lit-quad.gltf", litQuad()));
    CHECK(s.triangleCount() == 2);
    CHECK(s.lights.size() == 1);
    CHECK(s.cameras.size() == 1);
}

TEST_CASE("gltf: hardening: a member of the wrong JSON type is an error naming the JSON path") {
    // Every example of issue 16; tinygltf skipped each of them silently.
    expectMutationError("t-mode.gltf", "/meshes/0/primitives/0/mode", "TRIANGLES",
                        "meshes[0].primitives[0].mode: expected an integer, found the string \"TRIANGLES\"");
    expectMutationError("t-children.gltf", "/nodes/0/children", 1, "nodes[0].children: expected an array, found a number");
    expectMutationError("t-scene.gltf", "/scene", "0", "scene: expected an index into scenes (0..0), found the string \"0\"");
    expectMutationError("t-matrix.gltf", "/nodes/0/matrix", "1 0 0 0", "nodes[0].matrix: expected an array, found a string");
    expectMutationError("t-translation.gltf", "/nodes/2/translation", "0 0 3", "nodes[2].translation: expected an array");
    expectMutationError("t-translation2.gltf", "/nodes/2/translation", json::array({0, "0", 3}),
                        "nodes[2].translation[1]: expected a number, found the string \"0\"");
    expectMutationError("t-ext-number.gltf", "/nodes/1/extensions/KHR_lights_punctual", 0,
                        "nodes[1].extensions.KHR_lights_punctual: expected an object, found a number");
    expectMutationError("t-ext-string.gltf", "/materials/0/extensions", "KHR_materials_emissive_strength",
                        "materials[0].extensions: expected an object, found a string");
    expectMutationError("t-color.gltf", "/materials/0/pbrMetallicRoughness/baseColorFactor", "red",
                        "materials[0].pbrMetallicRoughness.baseColorFactor: expected an array, found a string");
    expectMutationError("t-pbr.gltf", "/materials/0/pbrMetallicRoughness", json::array(),
                        "materials[0].pbrMetallicRoughness: expected an object, found an array");
    expectMutationError("t-colorlen.gltf", "/materials/0/pbrMetallicRoughness/baseColorFactor", json::array({1, 0, 0}),
                        "baseColorFactor: expected 4 numbers, found 3");
}

TEST_CASE("gltf: hardening: indices out of range, -1 and non-integers are errors naming the JSON path") {
    expectMutationError("i-tex.gltf", "/materials/0/pbrMetallicRoughness/baseColorTexture", json{{"index", -1}},
                        "materials[0].pbrMetallicRoughness.baseColorTexture.index: expected an index into textures "
                        "(the file has no textures), found -1");
    expectMutationError("i-indices.gltf", "/meshes/0/primitives/0/indices", 2.5,
                        "meshes[0].primitives[0].indices: expected an index into accessors (0..3), found 2.5");
    expectMutationError("i-mesh.gltf", "/nodes/0/mesh", -1, "nodes[0].mesh: expected an index into meshes (0..0), found -1");
    expectMutationError("i-material.gltf", "/meshes/0/primitives/0/material", 1, "found 1");
    expectMutationError("i-light.gltf", "/nodes/1/extensions/KHR_lights_punctual/light", 1,
                        "nodes[1].extensions.KHR_lights_punctual.light: expected an index");
    expectMutationError("i-view.gltf", "/accessors/0/bufferView", 4294967296.0, "accessors[0].bufferView");
}

TEST_CASE("gltf: hardening: duplicate children and nodes with two parents are errors (no instance bomb)") {
    // The 4 KB file of issue 16: every node lists the next one twice.
    Asset a = litQuad();
    json nodes = json::array();
    for (int i = 0; i < 22; ++i) nodes.push_back({{"children", {i + 1, i + 1}}});
    nodes.push_back({{"mesh", 0}});
    a.doc["nodes"] = nodes;
    a.doc["scenes"][0]["nodes"] = {0};
    a.doc.erase("cameras");
    auto t0 = std::chrono::steady_clock::now();
    expectError(writeEmbedded("bomb-twice.gltf", a), "nodes[0].children[1]: lists 1 a second time");
    // The same doubling without duplicates: node i+1 and i+2 shared by every level.
    for (int i = 0; i < 21; ++i) a.doc["nodes"][std::size_t(i)]["children"] = {i + 1, i + 2};
    a.doc["nodes"][21]["children"] = {22};
    expectError(writeEmbedded("bomb-dag.gltf", a), "no node has two parents");
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 1.0);
}

TEST_CASE("gltf: hardening: light values beyond float are errors naming the JSON path") {
    expectMutationError("l-intensity.gltf", "/extensions/KHR_lights_punctual/lights/0/intensity", 1e300,
                        "extensions.KHR_lights_punctual.lights[0].intensity: 1e+300 is not representable as a float");
    expectMutationError("l-color.gltf", "/extensions/KHR_lights_punctual/lights/0/color/1", 1e300,
                        "extensions.KHR_lights_punctual.lights[0].color[1]: 1e+300 is not representable as a float");
    // Each factor a float, the product not: 1e20 x 1e20.
    Asset a = litQuad();
    a.doc["extensions"]["KHR_lights_punctual"]["lights"][0]["color"] = {1e20, 1.0, 1.0};
    a.doc["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = 1e20;
    expectError(writeEmbedded("l-product.gltf", a), "color x intensity");
    expectMutationError("m-emissive.gltf", "/materials/0/emissiveFactor", json::array({0.0, 1e300, 0.0}),
                        "materials[0].emissiveFactor[1]: 1e+300 is not representable as a float");
    // Large but representable values load and stay finite.
    Asset b = litQuad();
    b.doc["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = 1e20;
    rtgi::Scene s = loadGltf(writeEmbedded("l-large.gltf", b));
    CHECK(s.sun()->intensity == doctest::Approx(1e20));
}

TEST_CASE("gltf: hardening: camera yfov / znear / zfar outside the --set ranges are errors naming the JSON path") {
    expectMutationError("c-fov1.gltf", "/cameras/0/perspective/yfov", 1e-45, "cameras[0].perspective.yfov: 1e-45 radians");
    expectMutationError("c-fov2.gltf", "/cameras/0/perspective/yfov", 1e-300, "cameras[0].perspective.yfov");
    expectMutationError("c-fov3.gltf", "/cameras/0/perspective/yfov", 3.2, "outside the supported 0.5..175 degrees");
    expectMutationError("c-near.gltf", "/cameras/0/perspective/znear", 1e-300, "cameras[0].perspective.znear: 1e-300");
    expectMutationError("c-far.gltf", "/cameras/0/perspective/zfar", 1e300, "cameras[0].perspective.zfar: 1e+300");
    // Near and far distinct in double, equal in float.
    Asset a = litQuad();
    a.doc["cameras"][0]["perspective"]["znear"] = 1.0;
    a.doc["cameras"][0]["perspective"]["zfar"] = 1.00000001;
    expectError(writeEmbedded("c-equal.gltf", a), "does not lie beyond znear 1 in float precision");
    // The ends of the ranges load.
    Asset b = litQuad();
    b.doc["cameras"][0]["perspective"] = {{"yfov", 3.05}, {"znear", 1e-6}, {"zfar", 1e9}};
    rtgi::Scene s = loadGltf(writeEmbedded("c-edges.gltf", b));
    REQUIRE(s.cameras.size() == 1);
    CHECK(s.cameras[0].fovY == doctest::Approx(3.05f));
    CHECK(s.cameras[0].near == doctest::Approx(1e-6f));
}

TEST_CASE("gltf: hardening: vertices beyond 1e15 are an error naming the file; huge valid triangles load") {
    // A vertex at 1e38 (a float) used to end in "camera: far plane must lie
    // beyond the near plane" without a file name.
    Asset a = litQuad();
    std::vector<float> p = {0, 0, 0, 1e38f, 0, 0, 1, 1, 0, 0, 1, 0};
    std::memcpy(a.bin.data(), p.data(), p.size() * 4);
    expectError(writeEmbedded("v-1e38.gltf", a), "places a vertex at (9.99999968e+37, 0, 0), beyond the supported +-1e15");
    // Edges of 5e9: the float cross product (2.5e19^2 per component) overflowed
    // and the triangles were dropped as degenerate ("no triangles").
    Asset b = litQuad();
    std::vector<float> q = {0, 0, 0, 5e9f, 0, 0, 5e9f, 5e9f, 0, 0, 5e9f, 0};
    std::memcpy(b.bin.data(), q.data(), q.size() * 4);
    b.doc["accessors"][0]["max"] = {5e9, 5e9, 0};
    b.doc.erase("cameras");
    b.doc["nodes"][2].erase("camera");
    rtgi::Scene s = loadGltf(writeEmbedded("v-huge.gltf", b));
    CHECK(s.triangleCount() == 2);
    CHECK(s.warnings.empty());
    // The same without normals (flat normals computed while decoding).
    Asset c = b;
    c.doc["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
    rtgi::Scene sc = loadGltf(writeEmbedded("v-huge-flat.gltf", c));
    CHECK(sc.triangleCount() == 2);
    CHECK(sc.vertices[0].normal.z == doctest::Approx(1.0f));
}

// Issue 23: node animations. An animated glTF written here: the parent node
// translates (LINEAR), the mesh node rotates (LINEAR slerp), a light node
// steps (STEP); the scene at t is compared with positions computed by hand.
TEST_CASE("gltf: node animations move meshes and lights; skins and morph targets are refused") {
    Asset a = quad();
    const float h = std::sqrt(0.5f);
    a.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    a.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({{{"type", "point"}, {"intensity", 5.0}}});
    a.doc["nodes"] = json::array({{{"translation", {5, 0, 0}}, {"children", {1, 2}}},
                                  {{"mesh", 0}},
                                  {{"translation", {0, 1, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}});
    const int t0 = a.addData(std::vector<float>{0, 2}, kF32, 2, "SCALAR");
    const int v0 = a.addData(std::vector<float>{5, 0, 0, 5, 4, 0}, kF32, 2, "VEC3");
    const int t1 = a.addData(std::vector<float>{0, 1}, kF32, 2, "SCALAR");
    const int v1 = a.addData(std::vector<float>{0, 0, 0, 1, 0, 0, h, h}, kF32, 2, "VEC4");
    const int t2 = a.addData(std::vector<float>{0, 1.5f}, kF32, 2, "SCALAR");
    const int v2 = a.addData(std::vector<float>{0, 1, 0, 0, 2, 0}, kF32, 2, "VEC3");
    a.doc["animations"] = json::array({{{"samplers", json::array({{{"input", t0}, {"output", v0}, {"interpolation", "LINEAR"}},
                                                                  {{"input", t1}, {"output", v1}},
                                                                  {{"input", t2}, {"output", v2}, {"interpolation", "STEP"}}})},
                                        {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}},
                                                                  {{"sampler", 1}, {"target", {{"node", 1}, {"path", "rotation"}}}},
                                                                  {{"sampler", 2}, {"target", {{"node", 2}, {"path", "translation"}}}}})}}});
    const rtgi::Scene rest = loadGltf(writeEmbedded("animated.gltf", a));
    REQUIRE(rest.vertices.size() == 4);
    REQUIRE(rest.lights.size() == 1);
    CHECK(rest.animation.tracks.size() == 3);
    CHECK(rest.animation.duration() == 2.0);
    CHECK(near3(rest.vertices[1].position, {6, 0, 0}));  // the rest pose: the nodes' own TRS
    CHECK(near3(rest.lights[0].position, {5, 1, 0}));
    auto at = [&](double t) {
        rtgi::Scene s = rest;
        CHECK(rtgi::applySceneAnimation(s, rest, t));
        return s;
    };
    // t = 0.5: parent at (5, 1, 0), quad turned 45 degrees about z: (1,0,0) -> (0.70711, 0.70711, 0).
    rtgi::Scene s = at(0.5);
    CHECK(near3(s.vertices[1].position, {5.70710678f, 1.70710678f, 0}));
    CHECK(near3(s.vertices[1].normal, {0, 0, 1}));
    CHECK(near3(s.lights[0].position, {5, 2, 0}));  // STEP: still the first key
    // t = 1: parent at (5, 2, 0), quad turned 90 degrees: (1,0,0) -> (5,3,0), (1,1,0) -> (4,3,0).
    s = at(1.0);
    CHECK(near3(s.vertices[1].position, {5, 3, 0}));
    CHECK(near3(s.vertices[2].position, {4, 3, 0}));
    CHECK(near3(s.lights[0].position, {5, 3, 0}));
    // t = 2 and beyond: the last keys hold; the light has stepped to (0, 2, 0).
    s = at(3.0);
    CHECK(near3(s.vertices[1].position, {5, 5, 0}));
    CHECK(near3(s.lights[0].position, {5, 6, 0}));

    Asset morph = a;
    morph.doc["animations"][0]["channels"][1]["target"]["path"] = "weights";
    expectError(writeEmbedded("morph.gltf", morph), "morph target");
    Asset skin = a;
    skin.doc["skins"] = json::array({{{"joints", {0}}}});
    skin.doc["nodes"][1]["skin"] = 0;
    expectError(writeEmbedded("skin.gltf", skin), "skinning");
    Asset badTimes = a;
    const int tb = badTimes.addData(std::vector<float>{1, 0}, kF32, 2, "SCALAR");
    badTimes.doc["animations"][0]["samplers"][0]["input"] = tb;
    expectError(writeEmbedded("badtimes.gltf", badTimes), "increase strictly");
}
