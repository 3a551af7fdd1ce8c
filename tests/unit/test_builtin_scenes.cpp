// Built-in scenes and the JSON scene builder (no GL). The analytic scenes are
// checked for exactness because the AO tests integrate against them.
#include "render/gpu_scene.h"
#include "scene/builtin.h"
#include "scene/scene.h"

#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <set>
#include <string>

using namespace rtgi;

namespace {

int materialIndex(const Scene& s, const std::string& name) {
    for (std::size_t m = 0; m < s.materials.size(); ++m)
        if (s.materials[m].name == name) return int(m);
    return -1;
}

// Indices of the vertices referenced by the draws of one material.
std::set<std::uint32_t> verticesOf(const Scene& s, const std::string& material) {
    std::set<std::uint32_t> out;
    int m = materialIndex(s, material);
    for (auto& d : s.draws)
        if (d.material == m)
            for (std::uint32_t k = 0; k < d.indexCount; ++k) out.insert(s.indices[d.firstIndex + k]);
    return out;
}

// Geometric (winding) normal, not normalized.
glm::dvec3 windingNormal(const Scene& s, std::size_t t) {
    glm::dvec3 a = s.vertices[s.indices[3 * t]].position, b = s.vertices[s.indices[3 * t + 1]].position,
               c = s.vertices[s.indices[3 * t + 2]].position;
    return glm::cross(b - a, c - a);
}

// Divergence theorem: the volume enclosed by a closed, outward-wound mesh
// is positive (and equals the solid's volume).
double signedVolume(const Scene& s) {
    double v = 0.0;
    for (std::size_t t = 0; t < s.triangleCount(); ++t) {
        glm::dvec3 a = s.vertices[s.indices[3 * t]].position, b = s.vertices[s.indices[3 * t + 1]].position,
                   c = s.vertices[s.indices[3 * t + 2]].position;
        v += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return v;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const SceneError& e) {
        return e.what();
    }
    return "(no SceneError)";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::string oneMaterial(const std::string& objects) {
    return R"({"materials": {"m": {"baseColor": [0.5, 0.5, 0.5]}}, "objects": )" + objects + "}";
}

}  // namespace

TEST_CASE("the built-in scenes are the documented set") {
    auto names = builtinSceneNames();
    std::set<std::string> got(names.begin(), names.end());
    std::set<std::string> expected{"atrium", "box-on-plane", "corner", "cornell", "gallery", "leak", "leak-door", "plane",
                                   "restaurant", "sphere-on-plane"};
    CHECK(got == expected);
}

TEST_CASE("every built-in scene loads and is well formed") {
    for (const auto& name : builtinSceneNames()) {
        CAPTURE(name);
        Scene s = loadBuiltin(name);
        MESSAGE("builtin:" << name << ": " << s.triangleCount() << " triangles, " << s.vertices.size() << " vertices, "
                           << s.draws.size() << " draws");
        CHECK(s.name == "builtin:" + name);
        CHECK(s.triangleCount() > 0);
        CHECK(s.warnings.empty());  // the builder needs no repairs
        REQUIRE_FALSE(s.cameras.empty());
        for (auto& c : s.cameras) {
            CHECK(c.fovY > 0.1f);
            CHECK(c.fovY < 3.0f);
            CHECK(c.far > c.near);
            CHECK(glm::length(c.target - c.position) > 0.0f);
        }
        // Every built-in scene but the gallery (local lights only) is lit by a sun coming from above.
        const Light* sun = s.sun();
        if (name == "gallery") {
            CHECK(sun == nullptr);
        } else {
            REQUIRE(sun != nullptr);
            CHECK(sun->intensity > 0.0f);
            CHECK(std::abs(glm::length(sun->direction) - 1.0f) < 1e-5f);
            CHECK(sun->direction.y < 0.0f);
        }

        std::size_t badPos = 0, badNormal = 0, badWinding = 0;
        for (auto& v : s.vertices) {
            if (!std::isfinite(v.position.x) || !std::isfinite(v.position.y) || !std::isfinite(v.position.z)) ++badPos;
            if (std::abs(glm::length(v.normal) - 1.0f) > 1e-4f) ++badNormal;
        }
        // Consistent orientation: each triangle is wound CCW seen from the
        // side its vertex normals point to.
        for (std::size_t t = 0; t < s.triangleCount(); ++t) {
            glm::dvec3 g = glm::normalize(windingNormal(s, t));
            for (int k = 0; k < 3; ++k)
                if (glm::dot(g, glm::dvec3(s.vertices[s.indices[3 * t + std::size_t(k)]].normal)) <= 0.0) {
                    ++badWinding;
                    break;
                }
        }
        CHECK(badPos == 0);
        CHECK(badNormal == 0);
        CHECK(badWinding == 0);

        std::uint32_t covered = 0;
        for (auto& d : s.draws) {
            CHECK(d.firstIndex == covered);
            covered += d.indexCount;
            CHECK(d.material >= 0);
            CHECK(std::size_t(d.material) < s.materials.size());
        }
        CHECK(covered == s.indices.size());
    }
}

TEST_CASE("cornell: Lambertian only, closed box open at the front") {
    Scene s = loadBuiltin("cornell");
    CHECK(s.minRoughness() >= 0.5f);
    for (auto& m : s.materials) {
        CHECK(m.roughness >= 0.5f);
        CHECK(m.metallic == 0.0f);
    }
    CHECK(s.sky == glm::vec3(0.0f));
    Aabb b = s.bounds();
    CHECK(b.extent().x == doctest::Approx(5.7).epsilon(1e-5));
    CHECK(b.extent().y == doctest::Approx(5.7).epsilon(1e-5));
    // The camera looks in through the open front (+z).
    CHECK(s.cameras[0].position.z > b.hi.z);
    // Boxes are closed and outward-wound: the enclosed volume is the sum of
    // the solids (floor, walls, 3 ceiling slabs around the opening, 2 boxes).
    double walls = 5.5 * 0.1 * 5.6 + 5.5 * 5.5 * 0.1 + 2.0 * 0.1 * 5.7 * 5.6;
    double ceiling = 5.5 * 0.1 * 5.6 - 3.15 * 0.1 * 2.0;  // opening x in [-2.75, 0.4], z in [-1.5, 0.5]
    double boxes = 1.65 * 1.65 * 1.65 + 1.65 * 3.3 * 1.65;
    CHECK(signedVolume(s) == doctest::Approx(walls + ceiling + boxes).epsilon(1e-4));
}

TEST_CASE("atrium: glossy floor, budget, sun and sky") {
    Scene s = loadBuiltin("atrium");
    int floor = materialIndex(s, "floor");
    REQUIRE(floor >= 0);
    CHECK(s.materials[std::size_t(floor)].roughness <= 0.3f);
    CHECK(s.minRoughness() <= 0.3f);  // SSR has something to do
    CHECK(s.triangleCount() <= 60000);
    CHECK(s.sky.z > s.sky.x);  // bluish
    Aabb b = s.bounds();
    CHECK(b.extent().x == doctest::Approx(30.8).epsilon(1e-4));
    CHECK(b.hi.y == doctest::Approx(14.0).epsilon(1e-5));
    // The camera is inside the courtyard.
    glm::vec3 c = s.cameras[0].position;
    CHECK((c.x > b.lo.x && c.x < b.hi.x && c.y > 0.0f && c.y < b.hi.y && c.z > b.lo.z && c.z < b.hi.z));
    // Banners in three colours.
    for (auto name : {"clothRed", "clothBlue", "clothGreen"}) CHECK_FALSE(verticesOf(s, name).empty());
}

TEST_CASE("restaurant: thin legs, rough materials") {
    Scene s = loadBuiltin("restaurant");
    for (auto& m : s.materials) CHECK(m.roughness == doctest::Approx(0.8f));
    CHECK(s.triangleCount() > 5000);
    Aabb b = s.bounds();
    CHECK(b.extent().x == doctest::Approx(12.4).epsilon(1e-4));
    CHECK(b.hi.y == doctest::Approx(4.2).epsilon(1e-5));
}

TEST_CASE("plane: exactly planar at y = 0") {
    Scene s = loadBuiltin("plane");
    CHECK(s.triangleCount() == 2);
    for (auto& v : s.vertices) {
        CHECK(v.position.y == 0.0f);
        CHECK(v.normal == glm::vec3(0, 1, 0));
    }
    Aabb b = s.bounds();
    CHECK(b.lo.x == -100.0f);
    CHECK(b.hi.x == 100.0f);
    CHECK(b.lo.z == -100.0f);
    CHECK(b.hi.z == 100.0f);
    CHECK(kBuiltinFloorY == 0.0f);
}

TEST_CASE("corner: floor at y = 0 and wall exactly at x = 0") {
    Scene s = loadBuiltin("corner");
    auto floor = verticesOf(s, "floor"), wall = verticesOf(s, "wall");
    REQUIRE(floor.size() == 4);
    REQUIRE(wall.size() == 4);
    for (auto i : floor) {
        CHECK(s.vertices[i].position.y == 0.0f);
        CHECK(s.vertices[i].position.x >= 0.0f);
        CHECK(s.vertices[i].normal == glm::vec3(0, 1, 0));
    }
    for (auto i : wall) {
        CHECK(s.vertices[i].position.x == 0.0f);
        CHECK(s.vertices[i].position.y >= 0.0f);
        CHECK(s.vertices[i].normal == glm::vec3(1, 0, 0));
    }
    Aabb b = s.bounds();
    CHECK(b.lo == glm::vec3(0.0f, 0.0f, -50.0f));
    CHECK(b.hi == glm::vec3(100.0f, 100.0f, 50.0f));
}

TEST_CASE("box-on-plane: a unit cube standing on the plane") {
    Scene s = loadBuiltin("box-on-plane");
    for (auto i : verticesOf(s, "floor")) CHECK(s.vertices[i].position.y == 0.0f);
    auto cube = verticesOf(s, "cube");
    CHECK(cube.size() == 24);
    for (auto i : cube) {
        glm::vec3 p = s.vertices[i].position;
        CHECK(std::abs(p.x) == 0.5f);
        CHECK(std::abs(p.z) == 0.5f);
        CHECK((p.y == 0.0f || p.y == 1.0f));
        // Flat normals point away from the cube's centre (0, 0.5, 0).
        CHECK(glm::dot(s.vertices[i].normal, p - glm::vec3(0, 0.5f, 0)) > 0.0f);
    }
}

TEST_CASE("sphere-on-plane: vertices exactly on the unit sphere") {
    Scene s = loadBuiltin("sphere-on-plane");
    for (auto i : verticesOf(s, "floor")) CHECK(s.vertices[i].position.y == 0.0f);
    auto sphere = verticesOf(s, "sphere");
    CHECK(sphere.size() >= 48 * 24);
    float lowest = 1e9f;
    for (auto i : sphere) {
        glm::vec3 d = s.vertices[i].position - glm::vec3(0, 1, 0);
        CHECK(std::abs(glm::length(d) - 1.0f) < 1e-5f);
        CHECK(glm::dot(glm::normalize(d), s.vertices[i].normal) > 0.9999f);  // smooth normals
        lowest = std::min(lowest, s.vertices[i].position.y);
    }
    CHECK(std::abs(lowest) < 1e-6f);  // resting on the plane
}

TEST_CASE("the builder: boxes are closed and wound outwards") {
    Scene s = buildSceneFromJson(
        oneMaterial(R"([{"material": "m", "box": {"center": [1, 2, 3], "size": [1, 2, 3], "rotationY": 30}}])"),
        "test.json");
    REQUIRE(s.triangleCount() == 12);
    glm::dvec3 centre(1, 2, 3);
    for (std::size_t t = 0; t < 12; ++t) {
        glm::dvec3 g = glm::normalize(windingNormal(s, t));
        glm::dvec3 mid(0.0);
        for (int k = 0; k < 3; ++k) {
            const Vertex& v = s.vertices[s.indices[3 * t + std::size_t(k)]];
            mid += glm::dvec3(v.position) / 3.0;
            CHECK(glm::dot(g, glm::dvec3(v.normal)) > 0.9999);  // flat normals
        }
        CHECK(glm::dot(g, mid - centre) > 0.0);  // away from the box centre
    }
    CHECK(signedVolume(s) == doctest::Approx(6.0).epsilon(1e-5));
    // Rotation about the centre: the footprint's bounding box grows.
    Aabb b = s.bounds();
    CHECK(b.center().x == doctest::Approx(1.0).epsilon(1e-5));
    CHECK(b.extent().y == doctest::Approx(2.0).epsilon(1e-6));
    double c = std::cos(glm::radians(30.0)), sn = std::sin(glm::radians(30.0));
    CHECK(b.extent().x == doctest::Approx(1.0 * c + 3.0 * sn).epsilon(1e-5));
}

TEST_CASE("the builder: closed primitives enclose their volume") {
    auto volume = [](const std::string& item) { return signedVolume(buildSceneFromJson(oneMaterial("[" + item + "]"), "t.json")); };
    const double pi = 3.14159265358979323846;
    // A sphere/cylinder with n segments encloses slightly less than the smooth solid.
    CHECK(volume(R"({"material": "m", "sphere": {"center": [3, 1, 0], "radius": 2, "segments": 256}})") ==
          doctest::Approx(4.0 / 3.0 * pi * 8.0).epsilon(2e-3));
    CHECK(volume(R"({"material": "m", "cylinder": {"base": [0, 1, 2], "radius": 0.5, "height": 2, "segments": 256}})") ==
          doctest::Approx(pi * 0.25 * 2.0).epsilon(1e-3));
    // Cone frustum: pi h (r0^2 + r0 r1 + r1^2) / 3.
    CHECK(volume(R"({"material": "m", "cylinder": {"center": [0, 0, 0], "radius": 1, "radiusTop": 0.5, "height": 3, "segments": 256}})") ==
          doctest::Approx(pi * 3.0 * (1.0 + 0.5 + 0.25) / 3.0).epsilon(1e-3));
    // Arch: block minus the half disc of the opening, extruded.
    CHECK(volume(R"({"material": "m", "arch": {"center": [0, 4, 0], "radius": 1, "width": 3, "top": 1.5, "depth": 0.5, "segments": 256, "rotationY": 90}})") ==
          doctest::Approx((3.0 * 1.5 - 0.5 * pi) * 0.5).epsilon(1e-3));
    // An arch whose width equals its span has no bottom strips and no degenerate triangles.
    Scene tight = buildSceneFromJson(
        oneMaterial(R"([{"material": "m", "arch": {"center": [0, 0, 0], "radius": 1, "width": 2, "top": 1.5, "depth": 1}}])"), "t.json");
    CHECK(tight.warnings.empty());
    CHECK(signedVolume(tight) > 0.0);
    // A quad is one-sided: no volume, but it faces along its normal.
    Scene q = buildSceneFromJson(oneMaterial(R"([{"material": "m", "quad": {"center": [0, 0, 0], "size": [2, 1], "normal": [0, 0, -1]}}])"), "t.json");
    REQUIRE(q.triangleCount() == 2);
    CHECK(glm::normalize(windingNormal(q, 0)).z == doctest::Approx(-1.0));
    CHECK(q.bounds().extent().x == doctest::Approx(2.0));
    CHECK(q.bounds().extent().y == doctest::Approx(1.0));
}

TEST_CASE("the builder: repeat, group and prefab expand as written") {
    // 3 × 4 boxes from nested repeats.
    Scene s = buildSceneFromJson(oneMaterial(R"([
        {"repeat": {"count": 3, "offset": [2, 0, 0]}, "material": "m", "items": [
            {"repeat": {"count": 4, "offset": [0, 0, -1.5]}, "items": [
                {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}}
            ]}
        ]}])"),
                                 "t.json");
    CHECK(s.triangleCount() == 3 * 4 * 12);
    CHECK(s.vertices.size() == 3 * 4 * 24);
    Aabb b = s.bounds();
    CHECK(b.lo == glm::vec3(0.0f, 0.0f, -4.5f));
    CHECK(b.hi == glm::vec3(5.0f, 1.0f, 1.0f));
    CHECK(signedVolume(s) == doctest::Approx(12.0));

    // A prefab placed twice, once turned by 90 degrees about Y.
    Scene p = buildSceneFromJson(R"({
        "materials": {"a": {}, "b": {"roughness": 0.2}},
        "prefabs": {"bar": [{"box": {"min": [0, 0, 0], "max": [2, 1, 0.5]}}]},
        "objects": [
            {"material": "a", "prefab": {"name": "bar"}},
            {"material": "b", "group": {"translate": [10, 0, 0], "rotateY": 90}, "items": [{"prefab": {"name": "bar"}}]}
        ]})",
                                 "t.json");
    REQUIRE(p.draws.size() == 2);
    CHECK(p.triangleCount() == 24);
    Aabb rotated;
    for (auto i : verticesOf(p, "b")) rotated.grow(p.vertices[i].position);
    // Rotation about +Y by 90 degrees maps +z to +x and +x to -z, exactly.
    CHECK(rotated.lo == glm::vec3(10.0f, 0.0f, -2.0f));
    CHECK(rotated.hi == glm::vec3(10.5f, 1.0f, 0.0f));
    CHECK(p.minRoughness() == doctest::Approx(0.2f));
}

TEST_CASE("the builder reads lights, cameras and sky") {
    Scene s = buildSceneFromJson(R"({
        "materials": {"m": {"baseColor": 0.5, "emissive": [1, 2, 3], "metallic": 1, "roughness": 0.3}},
        "sky": 0.25,
        "lights": [
            {"type": "directional", "direction": [0, -2, 0], "irradiance": 3, "color": [1, 0.5, 0.25]},
            {"type": "point", "position": [1, 2, 3], "intensity": 10, "range": 5},
            {"type": "spot", "position": [0, 3, 0], "direction": [0, -1, 0], "intensity": 7, "innerConeDeg": 10, "outerConeDeg": 30}
        ],
        "cameras": [{"name": "a", "position": [0, 1, 5], "target": [0, 1, 0], "fovY": 45, "near": 0.1, "far": 50}],
        // comments are allowed
        "objects": [{"material": "m", "sphere": {"center": [0, 0, 0], "radius": 1}}]
    })",
                                 "t.json");
    CHECK(s.sky == glm::vec3(0.25f));
    REQUIRE(s.lights.size() == 3);
    CHECK(s.lights[0].type == LightType::Directional);
    CHECK(s.lights[0].direction == glm::vec3(0, -1, 0));
    CHECK(s.lights[0].intensity == 3.0f);
    CHECK(s.lights[0].color == glm::vec3(1, 0.5f, 0.25f));
    CHECK(s.lights[1].type == LightType::Point);
    CHECK(s.lights[1].range == 5.0f);
    CHECK(s.lights[2].type == LightType::Spot);
    CHECK(s.lights[2].outerCone == doctest::Approx(glm::radians(30.0f)));
    REQUIRE(s.cameras.size() == 1);
    CHECK(s.cameras[0].fovY == doctest::Approx(glm::radians(45.0f)));
    CHECK(s.materials[0].baseColor == glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
    CHECK(s.materials[0].emissive == glm::vec3(1, 2, 3));
    CHECK(s.materials[0].metallic == 1.0f);
}

TEST_CASE("bad descriptions and names give one sentence naming the source") {
    auto build = [](const std::string& text) { return errorOf([&] { buildSceneFromJson(text, "scenes/broken.json"); }); };
    std::string e = build("{\"materials\": {\"m\": {}}, \"objects\": [");
    CHECK(contains(e, "scenes/broken.json"));
    CHECK(contains(e, "invalid JSON"));
    e = build(oneMaterial(R"([{"material": "m", "boxx": {"center": [0, 0, 0], "size": [1, 1, 1]}}])"));
    CHECK(contains(e, "scenes/broken.json"));
    CHECK(contains(e, "unknown primitive 'boxx'"));
    CHECK(contains(e, "objects[0]"));
    e = build(oneMaterial(R"([{"material": "nope", "box": {"center": [0, 0, 0], "size": [1, 1, 1]}}])"));
    CHECK(contains(e, "scenes/broken.json"));
    CHECK(contains(e, "unknown material 'nope'"));
    e = build(oneMaterial(R"([{"box": {"center": [0, 0, 0], "size": [1, 1, 1]}}])"));
    CHECK(contains(e, "no material"));
    e = build(oneMaterial(R"([{"material": "m", "box": {"center": [0, 0, 0], "sise": [1, 1, 1]}}])"));
    CHECK(contains(e, "unknown key 'sise'"));
    e = build(oneMaterial(R"([{"material": "m", "box": {"center": [0, 0, 0], "size": [1, -1, 1]}}])"));
    CHECK(contains(e, "extent"));
    e = build(oneMaterial(R"([{"material": "m", "repeat": {"count": 0, "offset": [1, 0, 0]}, "items": []}])"));
    CHECK(contains(e, "'count'"));
    e = build(R"({"materials": {"m": {"roughness": 2}}, "objects": []})");
    CHECK(contains(e, "roughness"));
    e = build(R"({"materials": {"m": {}}, "objects": [], "lights": [{"type": "area"}]})");
    CHECK(contains(e, "unknown light type 'area'"));
    e = build(R"({"materials": {"m": {}}, "prefabs": {"p": [{"prefab": {"name": "p"}}]}, "objects": [{"material": "m", "prefab": {"name": "p"}}]})");
    CHECK(contains(e, "nesting"));
    e = build(R"({"materials": {"m": {}}, "objects": []})");
    CHECK(contains(e, "no triangles"));
    CHECK(e.find('\n') == std::string::npos);

    e = errorOf([] { loadBuiltin("nope"); });
    CHECK(contains(e, "builtin:nope"));
    CHECK(contains(e, "atrium"));
    CHECK(contains(e, "sphere-on-plane"));
    e = errorOf([] { loadSceneSpec("builtin:../CMakeLists"); });
    CHECK(contains(e, "builtin:../CMakeLists"));
}

TEST_CASE("scanned models are placed on builtin:plane by translating them to floor_y") {
    Scene model = buildSceneFromJson(oneMaterial(R"([{"material": "m", "sphere": {"center": [0, -0.3, 0], "radius": 0.95}}])"),
                                     "dragon-stand-in");
    placeOnFloor(model);
    CHECK(model.bounds().lo.y == doctest::Approx(kBuiltinFloorY).epsilon(1e-6));
    Scene floor = loadSceneSpec("builtin:plane");
    std::size_t floorTris = floor.triangleCount();
    floor.merge(model);
    CHECK(floor.triangleCount() == floorTris + model.triangleCount());
    CHECK(floor.bounds().lo.y == doctest::Approx(0.0).epsilon(1e-6));
    CHECK(floor.sun() != nullptr);
}

TEST_CASE("scene files may suggest settings; unknown keys there are errors naming the file") {
    Scene c = loadBuiltin("cornell");
    bool grid = false;
    for (auto& [k, v] : c.suggestedSettings) grid |= k == "lpv.grid";
    CHECK(grid);
    const char* bad = R"({"materials": {"m": {"baseColor": [1, 1, 1]}}, "settings": {"lpv.gird": 4},
                         "objects": [{"material": "m", "box": {"center": [0, 0, 0], "size": [1, 1, 1]}}]})";
    CHECK_THROWS_WITH_AS(buildSceneFromJson(bad, "scenes/bad.json"), doctest::Contains("scenes/bad.json"), SceneError);
}

TEST_CASE("gallery: a closed room lit by two spot lights and a point light only") {
    Scene s = loadBuiltin("gallery");
    int spots = 0, points = 0;
    for (auto& l : s.lights) {
        CHECK(l.type != LightType::Directional);
        CHECK(l.intensity > 0.0f);
        spots += l.type == LightType::Spot;
        points += l.type == LightType::Point;
        // Every light is inside the room.
        CHECK(std::abs(l.position.x) < 4.0f);
        CHECK(l.position.y > 0.0f);
        CHECK(l.position.y < 4.0f);
        CHECK(std::abs(l.position.z) < 3.0f);
    }
    CHECK(spots == 2);
    CHECK(points == 1);
    CHECK(s.sky == glm::vec3(0.0f));
    Aabb b = s.bounds();
    CHECK(b.lo.x == doctest::Approx(-4.1f));
    CHECK(b.hi.y == doctest::Approx(4.1f));
    // The camera is inside the closed room.
    glm::vec3 c = s.cameras.front().position;
    CHECK(std::abs(c.x) < 4.0f);
    CHECK(std::abs(c.z) < 3.0f);
}

TEST_CASE("automatic far plane: a moved framed camera still sees the farthest corner of the scene") {
    // A model on builtin:plane gets a floor ten times its footprint and a camera
    // framing the model; a named view or --set camera.position moves that camera,
    // and its far plane must still reach the floor's far corner (not render it as sky).
    // mergeScenes frames the model only (rtgi::defaultCamera of the model's bounds,
    // named "default"): here a framed camera whose far plane covers 2 m.
    Scene s = loadBuiltin("box-on-plane");
    Camera framed = defaultCamera(s);
    framed.far = 2.0f;
    s.cameras = {framed};
    Settings st;
    st.camera.position = glm::vec3(0.3f, 0.4f, 0.3f);
    st.camera.target = glm::vec3(0.0f, 0.2f, 0.0f);
    Camera c = resolveCamera(s, st);
    Aabb b = s.bounds();
    double farthest = 0.0;
    for (double x : {double(b.lo.x), double(b.hi.x)})
        for (double y : {double(b.lo.y), double(b.hi.y)})
            for (double z : {double(b.lo.z), double(b.hi.z)})
                farthest = std::max(farthest, glm::length(glm::dvec3(x, y, z) - glm::dvec3(*st.camera.position)));
    CHECK(double(c.far) >= farthest);
    // An explicit far plane is kept.
    st.camera.nearPlane = 0.01f;
    st.camera.farPlane = 3.0f;
    CHECK(resolveCamera(s, st).far == 3.0f);
}

TEST_CASE("ground planes: builtin:plane's quad is ground; focusBounds holds the model and one model size of ground") {
    Scene floor = loadSceneSpec("builtin:plane");
    REQUIRE(floor.groundVertices.size() == 1);
    // Nothing but ground: the whole plane.
    CHECK(floor.focusBounds().lo.x == doctest::Approx(floor.bounds().lo.x));
    CHECK(floor.focusBounds().hi.z == doctest::Approx(floor.bounds().hi.z));
    // A 1 x 2 x 0.5 box standing on it at x in [3, 4]: grown by its largest extent (2) on every side,
    // clipped to the scene (y from the floor at 0 to the box top 2 + 2, clipped to 2).
    Scene model = buildSceneFromJson(oneMaterial(R"([{"material": "m", "box": {"min": [3, 0, -0.25], "max": [4, 2, 0.25]}}])"),
                                     "box");
    const std::size_t before = floor.vertices.size();
    floor.merge(model);
    REQUIRE(floor.groundVertices.size() == 1);
    CHECK(floor.groundVertices[0].second <= before);  // the ground's range kept its place
    const Aabb f = floor.focusBounds();
    CHECK(f.lo.x == doctest::Approx(1.0));
    CHECK(f.hi.x == doctest::Approx(6.0));
    CHECK(f.lo.y == doctest::Approx(0.0));
    CHECK(f.hi.y == doctest::Approx(2.0));
    CHECK(f.lo.z == doctest::Approx(-2.25));
    CHECK(f.hi.z == doctest::Approx(2.25));
    // Merged the other way round the ground's range moves with the offset.
    Scene boxFirst = model;
    boxFirst.merge(loadSceneSpec("builtin:plane"));
    REQUIRE(boxFirst.groundVertices.size() == 1);
    CHECK(boxFirst.groundVertices[0].first == std::uint32_t(model.vertices.size()));
    CHECK(boxFirst.focusBounds().lo.x == doctest::Approx(1.0));
    // 'ground' is a boolean, on planes and quads only.
    CHECK(contains(errorOf([] { buildSceneFromJson(oneMaterial(R"([{"material": "m", "plane": {"center": [0, 0, 0], "size": [1, 1], "ground": 1}}])"), "bad"); }),
                   "'ground' must be true or false"));
    CHECK(contains(errorOf([] { buildSceneFromJson(oneMaterial(R"([{"material": "m", "box": {"min": [0, 0, 0], "max": [1, 1, 1], "ground": true}}])"), "bad"); }),
                   "ground"));
}
