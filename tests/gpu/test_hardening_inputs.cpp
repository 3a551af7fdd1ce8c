// Issue 28 on the GPU tier: the warnings of accepted-but-wrong scenes reach
// results.json ("warnings") as well as stderr, and a scene with several suns
// renders with the first one (rtgi-bench end to end at 32x32, one frame).
#include "bench_runner.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>

using namespace rtgi;
namespace fs = std::filesystem;
using json = nlohmann::json;

TEST_CASE("hardening: warnings of accepted-but-wrong lights and materials are listed in results.json") {
    fs::path d = fs::temp_directory_path() / ("rtgi-inputs-gpu-" + std::to_string(getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    // A floor quad (two triangles) with a slightly emissive, out-of-range
    // emissiveFactor, two suns, a point light with range 0, a negative colour
    // and a "spot" object.
    const float pos[18] = {-2, 0, -2, 2, 0, -2, 2, 0, 2, -2, 0, -2, 2, 0, 2, -2, 0, 2};
    std::ofstream(d / "quad.bin", std::ios::binary).write(reinterpret_cast<const char*>(pos), sizeof pos);
    json doc = {
        {"asset", {{"version", "2.0"}}},
        {"extensionsUsed", {"KHR_lights_punctual"}},
        {"buffers", {{{"uri", "quad.bin"}, {"byteLength", 72}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteLength", 72}}}},
        {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 6}, {"type", "VEC3"},
                        {"min", {-2, 0, -2}}, {"max", {2, 0, 2}}}}},
        {"materials", {{{"emissiveFactor", {5, -1, 0}}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"material", 0}}}}}}},
        {"extensions", {{"KHR_lights_punctual", {{"lights", {
            {{"type", "directional"}, {"name", "sun a"}, {"intensity", 2}},
            {{"type", "directional"}, {"name", "sun b"}, {"intensity", 3}},
            {{"type", "point"}, {"range", 0}, {"color", {-1, 1, 1}}, {"spot", {{"outerConeAngle", 0.5}}}},
        }}}}}},
        {"nodes", {{{"mesh", 0}},
                   {{"rotation", {-0.7071068, 0, 0, 0.7071068}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
                   {{"rotation", {-0.7071068, 0, 0, 0.7071068}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}},
                   {{"translation", {0, 1, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}}}},
        {"scenes", {{{"nodes", {0, 1, 2, 3}}}}},
        {"scene", 0},
    };
    std::ofstream(d / "scene.gltf") << doc.dump();
    const fs::path out = d / "out";
    auto r = test::runBench("--scene " + (d / "scene.gltf").string() + " --res 32x32 --frames 1 --warmup 0 --check --no-images --out " +
                            out.string(), 120);
    CAPTURE(r.err);
    MESSAGE("render with warnings: " << r.seconds << " s");
    REQUIRE(r.rc == 0);
    std::ifstream in(out / "results.json");
    json results = json::parse(in);
    REQUIRE(results.contains("warnings"));
    std::string all;
    for (auto& w : results["warnings"]) all += w.get<std::string>() + "\n";
    CAPTURE(all);
    for (const char* words : {"2 directional lights; only 'sun a' is used", "lights[2].range is 0",
                              "lights[2].color [-1, 1, 1] has a negative component",
                              "lights[2] is a point light but has a \"spot\" object",
                              "materials[0].emissiveFactor [5, -1, 0] is outside 0..1"}) {
        CHECK(all.find(words) != std::string::npos);
        CHECK(r.err.find(words) != std::string::npos);  // and on stderr
    }
    CHECK(results["check"]["non_finite"].get<std::uint64_t>() == 0);
    fs::remove_all(d);
}

TEST_CASE("hardening: 400 point lights with 16^2 local shadows render on both raster paths within the 2048-layer array") {
    // Issue 28: 342+ point lights on the compute rasterizer failed with exit 4
    // ("depth copy framebuffer incomplete": a 2052-layer array). The array holds
    // GL 4.5's minimum GL_MAX_ARRAY_TEXTURE_LAYERS = 2048 layers: floor(2048 / 6)
    // = 341 point lights get their six faces, the other 59 are unshadowed, with a warning.
    fs::path d = fs::temp_directory_path() / ("rtgi-many-lights-gpu-" + std::to_string(getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    const float pos[18] = {-20, 0, -20, 20, 0, 20, 20, 0, -20, -20, 0, -20, -20, 0, 20, 20, 0, 20};
    std::ofstream(d / "floor.bin", std::ios::binary).write(reinterpret_cast<const char*>(pos), sizeof pos);
    json lights = json::array(), nodes = {{{"mesh", 0}}}, roots = {0};
    for (int i = 0; i < 400; ++i) {
        lights.push_back({{"type", "point"}, {"intensity", 1}});
        nodes.push_back({{"translation", {(i % 20) - 10, 1, (i / 20) - 10}},
                         {"extensions", {{"KHR_lights_punctual", {{"light", i}}}}}});
        roots.push_back(i + 1);
    }
    json doc = {
        {"asset", {{"version", "2.0"}}},
        {"extensionsUsed", {"KHR_lights_punctual"}},
        {"buffers", {{{"uri", "floor.bin"}, {"byteLength", 72}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteLength", 72}}}},
        {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 6}, {"type", "VEC3"},
                        {"min", {-20, 0, -20}}, {"max", {20, 0, 20}}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
        {"extensions", {{"KHR_lights_punctual", {{"lights", lights}}}}},
        {"nodes", nodes},
        {"scenes", {{{"nodes", roots}}}},
        {"scene", 0},
    };
    std::ofstream(d / "lights.gltf") << doc.dump();
    for (const std::string path : {"compute", "hardware"}) {
        CAPTURE(path);
        const fs::path out = d / path;
        auto r = test::runBench("--scene " + (d / "lights.gltf").string() + " --res 32x32 --frames 1 --warmup 0 --check --no-images" +
                                    " --set shadow.local_size=16 --set raster.path=" + path + " --out " + out.string(), 120);
        CAPTURE(r.err);
        MESSAGE(path << ": 400 point lights in " << r.seconds << " s");
        REQUIRE(r.rc == 0);
        json results = json::parse(std::ifstream(out / "results.json"));
        std::string all;
        for (auto& w : results["warnings"]) all += w.get<std::string>() + "\n";
        CHECK(all.find("59 local lights get no shadow map: the shadow array holds 2048 layers") != std::string::npos);
        // The layers of the 341 shadowed lights (2046 <= 2048), 16^2 D32F each.
        CHECK(results["memory_bytes"]["resources"]["localShadowMaps"].get<std::int64_t>() == std::int64_t(2048 / 6) * 6 * 16 * 16 * 4);
        CHECK(results["check"]["non_finite"].get<std::uint64_t>() == 0);
    }
    fs::remove_all(d);
}
