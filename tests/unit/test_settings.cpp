// Configuration parsing: every key, ranges, unknown keys, JSON configs.
#include "render/settings.h"

#include <doctest/doctest.h>

#include <fstream>
#include <sstream>

using namespace rtgi;

TEST_CASE("every documented key parses its own printed default back to the same value") {
    Settings s;
    auto before = describe(s);
    for (auto& k : settingKeys()) {
        INFO(k.key);
        CHECK_FALSE(k.doc.empty());
        CHECK_FALSE(k.values.empty());
        Settings t;
        CHECK_NOTHROW(applySetting(t, k.key, k.show(s)));
        CHECK(describe(t) == before);
    }
    // SPEC section 12 keys exist.
    for (const char* key : {"lpv", "lpv.path", "lpv.grid", "lpv.cell", "lpv.iterations", "lpv.rsm", "lpv.format",
                            "lpv.occlusion", "lpv.bounce", "lpv.specular", "lpv.temporal", "ao", "ao.samples",
                            "ao.radius", "ao.resolution", "ao.blur", "ao.temporal", "ao.upsample", "ao.directional",
                            "ao.nearfield", "ao.radius_mode", "ao.depth_source", "ssr", "ssr.steps", "ssr.thickness",
                            "ssr.resolution", "reference", "reference.spp"}) {
        INFO(key);
        CHECK(describe(s).count(key) == 1);
    }
}

TEST_CASE("values are typed and range-checked; errors name the key") {
    Settings s;
    applyAssignment(s, "lpv.iterations=16");
    CHECK(s.lpv.iterations == 16);
    applyAssignment(s, "lpv.grid=16x8x4");
    CHECK(s.lpv.grid == glm::ivec3(16, 8, 4));
    applyAssignment(s, "lpv.grid=24");
    CHECK(s.lpv.grid == glm::ivec3(24));
    applyAssignment(s, "ao=gtao");
    CHECK((s.ao.variant == AoSettings::Variant::Gtao));
    applyAssignment(s, "ao.resolution=full");
    CHECK_FALSE(s.ao.halfResolution);
    applyAssignment(s, "camera.position=1,2.5,-3");
    CHECK(*s.camera.position == glm::vec3(1, 2.5f, -3));
    applyAssignment(s, "camera.position=auto");
    CHECK_FALSE(s.camera.position.has_value());
    // auto | a number (docs/lpv.md, "Closed scenes").
    CHECK(s.lpv.coarseIterationsAuto);
    applyAssignment(s, "lpv.coarse_iterations=24");
    CHECK((s.lpv.coarseIterations == 24 && !s.lpv.coarseIterationsAuto));
    CHECK(describe(s).at("lpv.coarse_iterations") == "24");
    applyAssignment(s, "lpv.coarse_iterations=auto");
    CHECK(describe(s).at("lpv.coarse_iterations") == "auto");
    CHECK((s.lpv.coarseIterationsAuto && s.lpv.coarseIterations == LpvSettings{}.coarseIterations));
    CHECK_THROWS_WITH_AS(applyAssignment(s, "lpv.coarse_iterations=65"), doctest::Contains("lpv.coarse_iterations"),
                         ConfigError);
    CHECK_THROWS_WITH_AS(applyAssignment(s, "lpv.closed_escape=1.5"), doctest::Contains("lpv.closed_escape"),
                         ConfigError);
    CHECK_THROWS_WITH_AS(applyAssignment(s, "lpv.iterations=0"), doctest::Contains("lpv.iterations"), ConfigError);
    CHECK_THROWS_WITH_AS(applyAssignment(s, "lpv.iterations=65"), doctest::Contains("1..64"), ConfigError);
    CHECK_THROWS_WITH_AS(applyAssignment(s, "lpv.iterations=8x"), doctest::Contains("lpv.iterations"), ConfigError);
    CHECK_THROWS_WITH_AS(applyAssignment(s, "ao=ssao"), doctest::Contains("ssao-disk"), ConfigError);
    CHECK_THROWS_WITH_AS(applyAssignment(s, "ao.radius=nan"), doctest::Contains("ao.radius"), ConfigError);
    CHECK_THROWS_WITH_AS(applyAssignment(s, "ao.radius=inf"), doctest::Contains("ao.radius"), ConfigError);
    CHECK_THROWS_WITH_AS(applyAssignment(s, "lpv.grid=0"), doctest::Contains("lpv.grid"), ConfigError);
    CHECK_THROWS_WITH_AS(applyAssignment(s, "lpv.grid=4x4"), doctest::Contains("NxMxK"), ConfigError);
    CHECK_THROWS_WITH_AS(applyAssignment(s, "lpv.itterations=3"), doctest::Contains("unknown setting 'lpv.itterations'"),
                         ConfigError);
    CHECK_THROWS_WITH_AS(applyAssignment(s, "novalue"), doctest::Contains("key=value"), ConfigError);
    CHECK_THROWS_AS(applyAssignment(s, "camera.position=1,2"), ConfigError);
}

TEST_CASE("JSON configuration: nested objects are dotted keys, unknown keys are errors naming the file") {
    Settings s;
    applyJsonConfig(s, R"({"lpv": {"grid": 16, "occlusion": false, "format": "rgba32f"}, "ao": "hbao",
                          "ao.samples": 24, "camera": {"position": [1, 2, 3]}})",
                    "my.json");
    CHECK(s.lpv.grid == glm::ivec3(16));
    CHECK_FALSE(s.lpv.occlusion);
    CHECK(s.lpv.format == LpvSettings::Format::Rgba32f);
    CHECK((s.ao.variant == AoSettings::Variant::Hbao));
    CHECK(s.ao.samples == 24);
    CHECK(*s.camera.position == glm::vec3(1, 2, 3));
    CHECK_THROWS_WITH_AS(applyJsonConfig(s, R"({"lpv": {"gird": 4}})", "my.json"),
                         doctest::Contains("my.json: unknown setting 'lpv.gird'"), ConfigError);
    CHECK_THROWS_WITH_AS(applyJsonConfig(s, "{not json", "broken.json"), doctest::Contains("broken.json"), ConfigError);
    CHECK_THROWS_WITH_AS(applyJsonConfig(s, "[1,2]", "arr.json"), doctest::Contains("arr.json"), ConfigError);
}

TEST_CASE("docs/configuration.md documents every key") {
    std::ifstream f(std::string(RTGI_SOURCE_DIR) + "/docs/configuration.md");
    REQUIRE(f.good());
    std::stringstream ss;
    ss << f.rdbuf();
    // Every key has a row "| `key` | `values` | `default` | meaning |" with the code's default
    // (regenerate with scripts/gen_config_doc.py after changing a default).
    const std::string doc = ss.str();
    for (auto& k : settingKeys()) {
        INFO(k.key);
        std::size_t row = doc.find("| `" + k.key + "` |");
        REQUIRE(row != std::string::npos);
        std::string line = doc.substr(row, doc.find('\n', row) - row);
        std::string def = settingDefault(k);
        std::string escaped;
        for (char c : def) escaped += c == '|' ? std::string("\\|") : std::string(1, c);
        CHECK(line.find("| `" + escaped + "` |") != std::string::npos);
    }
}

TEST_CASE("scene-suggested settings: applied first, explicit assignments win, bad keys name the scene") {
    Assignments scene = {{"lpv.grid", "16"}, {"post.exposure", "2.5"}};
    Settings s = effectiveSettings(scene, {}, "builtin:test");
    CHECK(s.lpv.grid == glm::ivec3(16));
    CHECK(s.post.exposure == doctest::Approx(2.5));
    Settings t = effectiveSettings(scene, {{"lpv.grid", "32"}}, "builtin:test");
    CHECK(t.lpv.grid == glm::ivec3(32));
    CHECK(t.post.exposure == doctest::Approx(2.5));
    // The raster baseline blocks as oriented whatever lpv.blocking=visibility says, and reports that.
    CHECK(effectiveSettings({}, {}, "builtin:test").lpv.blocking == LpvSettings::Blocking::Visibility);
    CHECK(effectiveSettings({}, {{"lpv.path", "raster"}}, "builtin:test").lpv.blocking == LpvSettings::Blocking::Oriented);
    CHECK(effectiveSettings({}, {{"lpv.path", "raster"}, {"lpv.blocking", "two-sided"}}, "builtin:test").lpv.blocking ==
          LpvSettings::Blocking::TwoSided);
    // ao.bent_normals=slices holds only for GTAO's bent normals from one radius; otherwise rays are reported.
    CHECK(effectiveSettings({}, {}, "builtin:test").ao.sliceBentNormals);
    CHECK_FALSE(effectiveSettings({}, {{"ao", "hbao"}}, "builtin:test").ao.sliceBentNormals);
    CHECK_FALSE(effectiveSettings({}, {{"ao.directional", "s3ho"}}, "builtin:test").ao.sliceBentNormals);
    CHECK_FALSE(effectiveSettings({}, {{"ao.radius_mode", "dual"}}, "builtin:test").ao.sliceBentNormals);
    CHECK_THROWS_WITH_AS(effectiveSettings({{"lpv.gird", "4"}}, {}, "builtin:test"),
                         doctest::Contains("builtin:test: suggested settings"), ConfigError);
    Assignments flat = flattenJsonConfig(R"({"ao": {"samples": 8}, "lpv": "on"})", "x.json");
    REQUIRE(flat.size() == 2);
    CHECK(flat[0] == std::pair<std::string, std::string>("ao.samples", "8"));
    CHECK(flat[1] == std::pair<std::string, std::string>("lpv", "on"));
}
