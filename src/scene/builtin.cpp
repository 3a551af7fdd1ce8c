// Built-in scene builder: scenes/NAME.json (data) → Scene (flattened world
// space geometry). Geometry comes from a handful of primitives so that the
// descriptions stay short and analytic scenes stay exact (docs/scenes.md
// documents the schema).
//
// Conventions shared by every primitive:
// - Outward winding: every triangle is counter-clockwise seen from the side
//   its vertex normals point to. Generators give each vertex its intended
//   normal and tri() orders the indices accordingly, so no generator has to
//   get the winding right by hand.
// - Flat normals on planar faces (boxes, quads, caps, arch faces); smooth
//   normals on spheres, cylinder sides and arch intrados.
// - Transforms are rigid (translation + rotation about Y), so normals
//   transform with the upper 3×3 of the matrix. Multiples of 90° use exact
//   sines and cosines, so axis-aligned geometry stays exactly axis-aligned.
#include "scene/builtin.h"

#include "render/settings.h"

#include "gl/embedded.h"

#include <glm/gtc/constants.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string_view>

namespace rtgi {
namespace {

using Json = nlohmann::ordered_json;

constexpr int kMaxNesting = 32;
constexpr long kMaxRepeat = 100000;
constexpr std::size_t kMaxTriangles = 20'000'000;

// ---------------------------------------------------------------------------
// Local meshes

struct Mesh {
    std::vector<Vertex> v;
    std::vector<std::uint32_t> i;

    std::uint32_t vert(glm::vec3 p, glm::vec3 n, glm::vec2 uv) {
        v.push_back({p, n, uv});
        return std::uint32_t(v.size() - 1);
    }
    // Triangle wound CCW seen from the side its vertex normals point to;
    // zero-area triangles (e.g. an arch whose width equals its span) are left out.
    void tri(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        glm::vec3 e1 = v[b].position - v[a].position, e2 = v[c].position - v[a].position;
        glm::vec3 g = glm::cross(e1, e2);
        if (glm::length(g) <= 1e-7f * glm::length(e1) * glm::length(e2)) return;
        glm::vec3 facing = v[a].normal + v[b].normal + v[c].normal;
        if (glm::dot(g, facing) < 0.0f) std::swap(b, c);
        i.insert(i.end(), {a, b, c});
    }
    // Planar quad p0..p3 (in cyclic order) with flat normal n; uv in metres.
    void quad(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3, glm::vec3 n) {
        float w = glm::length(p1 - p0), h = glm::length(p3 - p0);
        auto a = vert(p0, n, {0, 0}), b = vert(p1, n, {w, 0}), c = vert(p2, n, {w, h}), d = vert(p3, n, {0, h});
        tri(a, b, c);
        tri(a, c, d);
    }
};

// Rotation about +Y by deg degrees (right-handed: +Z turns towards +X), exact
// for multiples of 90°.
glm::mat4 rotateY(double deg) {
    double s, c;
    double quarter = deg / 90.0;
    if (std::abs(quarter - std::round(quarter)) < 1e-12) {
        static constexpr double kSin[4] = {0, 1, 0, -1};
        int q = int(((long long)std::llround(quarter) % 4 + 4) % 4);
        s = kSin[q];
        c = kSin[(q + 1) % 4];
    } else {
        double r = glm::radians(deg);
        s = std::sin(r);
        c = std::cos(r);
    }
    glm::mat4 m(1.0f);
    m[0][0] = float(c);
    m[0][2] = float(-s);
    m[2][0] = float(s);
    m[2][2] = float(c);
    return m;
}

glm::mat4 translate(glm::vec3 t) {
    glm::mat4 m(1.0f);
    m[3] = glm::vec4(t, 1.0f);
    return m;
}

// Axis-aligned box centred at the origin with half extents h.
Mesh makeBox(glm::vec3 h) {
    Mesh m;
    for (int axis = 0; axis < 3; ++axis) {
        int u = (axis + 1) % 3, w = (axis + 2) % 3;
        for (float s : {-1.0f, 1.0f}) {
            glm::vec3 n(0.0f), du(0.0f), dw(0.0f), c(0.0f);
            n[axis] = s;
            c[axis] = s * h[axis];
            du[u] = h[u];
            dw[w] = h[w];
            m.quad(c - du - dw, c + du - dw, c + du + dw, c - du + dw, n);
        }
    }
    return m;
}

// Quad centred at the origin with normal n; w along the horizontal edge
// (x for horizontal quads), h along the other edge (z for horizontal quads).
Mesh makeQuad(glm::vec3 n, float w, float h) {
    glm::vec3 u = std::abs(n.y) > 0.999f ? glm::vec3(1, 0, 0) : glm::normalize(glm::cross(glm::vec3(0, 1, 0), n));
    glm::vec3 v = glm::cross(n, u);
    glm::vec3 du = 0.5f * w * u, dv = 0.5f * h * v;
    Mesh m;
    m.quad(-du - dv, du - dv, du + dv, -du + dv, n);
    return m;
}

// UV sphere centred at the origin: `segments` around Y, `rings` from pole to pole.
Mesh makeSphere(float r, int segments, int rings) {
    Mesh m;
    const double pi = glm::pi<double>();
    auto dir = [&](int ring, int seg) {
        double th = pi * ring / rings, ph = 2.0 * pi * seg / segments;
        return glm::vec3(float(std::sin(th) * std::cos(ph)), float(std::cos(th)), float(std::sin(th) * std::sin(ph)));
    };
    // Rows 1..rings-1 with a duplicated seam column for the texture seam.
    std::vector<std::uint32_t> row((std::size_t(rings) + 1) * std::size_t(segments + 1));
    auto at = [&](int ring, int seg) -> std::uint32_t& { return row[std::size_t(ring) * std::size_t(segments + 1) + std::size_t(seg)]; };
    for (int ring = 1; ring < rings; ++ring)
        for (int seg = 0; seg <= segments; ++seg) {
            glm::vec3 d = dir(ring, seg % segments);
            at(ring, seg) = m.vert(r * d, d, {float(seg) / float(segments), float(ring) / float(rings)});
        }
    for (int seg = 0; seg < segments; ++seg) {
        float uc = (float(seg) + 0.5f) / float(segments);
        auto top = m.vert({0, r, 0}, {0, 1, 0}, {uc, 0});
        auto bottom = m.vert({0, -r, 0}, {0, -1, 0}, {uc, 1});
        m.tri(top, at(1, seg), at(1, seg + 1));
        m.tri(bottom, at(rings - 1, seg), at(rings - 1, seg + 1));
        for (int ring = 1; ring + 1 < rings; ++ring) {
            m.tri(at(ring, seg), at(ring + 1, seg), at(ring + 1, seg + 1));
            m.tri(at(ring, seg), at(ring + 1, seg + 1), at(ring, seg + 1));
        }
    }
    return m;
}

// Cylinder (or cone frustum) around +Y from y = 0 to y = height.
Mesh makeCylinder(float r0, float r1, float height, int segments, bool caps) {
    Mesh m;
    const double pi = glm::pi<double>();
    // Side normal of a frustum: radial, tilted up by the slope (r0 − r1) / h.
    float slope = (r0 - r1) / height;
    std::vector<glm::vec2> cs;
    for (int s = 0; s <= segments; ++s) {
        double ph = 2.0 * pi * (s % segments) / segments;
        cs.push_back({float(std::cos(ph)), float(std::sin(ph))});
    }
    for (int s = 0; s < segments; ++s) {
        std::uint32_t idx[4];
        for (int k = 0; k < 2; ++k) {
            glm::vec2 d = cs[std::size_t(s + k)];
            glm::vec3 n = glm::normalize(glm::vec3(d.x, slope, d.y));
            float u = float(s + k) / float(segments);
            idx[2 * k] = m.vert({r0 * d.x, 0, r0 * d.y}, n, {u, 0});
            idx[2 * k + 1] = m.vert({r1 * d.x, height, r1 * d.y}, n, {u, height});
        }
        m.tri(idx[0], idx[2], idx[3]);
        m.tri(idx[0], idx[3], idx[1]);
    }
    if (caps) {
        for (int top = 0; top < 2; ++top) {
            float y = top ? height : 0.0f, r = top ? r1 : r0;
            if (r <= 0.0f) continue;
            glm::vec3 n(0, top ? 1.0f : -1.0f, 0);
            auto c = m.vert({0, y, 0}, n, {0.5f, 0.5f});
            std::vector<std::uint32_t> ring;
            for (int s = 0; s < segments; ++s) {
                glm::vec2 d = cs[std::size_t(s)];
                ring.push_back(m.vert({r * d.x, y, r * d.y}, n, 0.5f + 0.5f * d));
            }
            for (int s = 0; s < segments; ++s) m.tri(c, ring[std::size_t(s)], ring[std::size_t((s + 1) % segments)]);
        }
    }
    return m;
}

// Arcade arch: the solid block [−w/2, w/2] × [0, top] × [−d/2, d/2] minus the
// half disc of radius r centred at the origin (the springing line is y = 0),
// i.e. the arch with its spandrels, spanning along X.
Mesh makeArch(float r, float w, float top, float d, int segments) {
    Mesh m;
    const double pi = glm::pi<double>();
    float hw = 0.5f * w, hd = 0.5f * d;
    // Angles of the intrados vertices, plus the two directions through the
    // block's upper corners so that each sector meets one straight edge.
    std::vector<double> ang;
    for (int s = 0; s <= segments; ++s) ang.push_back(pi * s / segments);
    double corner = std::atan2(double(top), double(hw));
    ang.push_back(corner);
    ang.push_back(pi - corner);
    std::sort(ang.begin(), ang.end());
    ang.erase(std::unique(ang.begin(), ang.end(), [](double a, double b) { return b - a < 1e-6; }), ang.end());
    auto outer = [&](double a) {
        if (a < 1e-12) return glm::vec2(hw, 0.0f);  // springing line: exact
        if (a > pi - 1e-12) return glm::vec2(-hw, 0.0f);
        double c = std::cos(a), s = std::sin(a);
        double t = 1e30;
        if (c > 1e-9) t = std::min(t, hw / c);
        if (c < -1e-9) t = std::min(t, -hw / c);
        if (s > 1e-9) t = std::min(t, top / s);
        glm::vec2 q(float(t * c), float(t * s));
        if (std::abs(t * c - hw) < 1e-6) q.x = hw;  // snap onto the edge it hits
        if (std::abs(t * c + hw) < 1e-6) q.x = -hw;
        if (std::abs(t * s - top) < 1e-6 || (a > corner - 1e-9 && a < pi - corner + 1e-9)) q.y = top;
        return q;
    };
    for (std::size_t k = 0; k + 1 < ang.size(); ++k) {
        double a0 = ang[k], a1 = ang[k + 1];
        glm::vec2 d0(float(std::cos(a0)), float(std::sin(a0))), d1(float(std::cos(a1)), float(std::sin(a1)));
        if (k == 0) d0 = {1, 0};
        if (k + 2 == ang.size()) d1 = {-1, 0};
        glm::vec2 p0 = r * d0, p1 = r * d1, q0 = outer(a0), q1 = outer(a1);
        // Front (+Z) and back (−Z) faces of the sector.
        for (float z : {hd, -hd})
            m.quad({p0, z}, {p1, z}, {q1, z}, {q0, z}, {0, 0, z > 0 ? 1.0f : -1.0f});
        // Intrados: normals point to the arch centre, out of the solid.
        glm::vec3 n0(-d0, 0.0f), n1(-d1, 0.0f);
        float u0 = r * float(a0), u1 = r * float(a1);
        auto a = m.vert({p0, -hd}, n0, {u0, 0}), b = m.vert({p1, -hd}, n1, {u1, 0});
        auto c = m.vert({p1, hd}, n1, {u1, d}), e = m.vert({p0, hd}, n0, {u0, d});
        m.tri(a, b, c);
        m.tri(a, c, e);
    }
    m.quad({-hw, top, -hd}, {hw, top, -hd}, {hw, top, hd}, {-hw, top, hd}, {0, 1, 0});
    m.quad({hw, 0, -hd}, {hw, top, -hd}, {hw, top, hd}, {hw, 0, hd}, {1, 0, 0});
    m.quad({-hw, 0, -hd}, {-hw, top, -hd}, {-hw, top, hd}, {-hw, 0, hd}, {-1, 0, 0});
    if (hw - r > 1e-6f) {
        m.quad({r, 0, -hd}, {hw, 0, -hd}, {hw, 0, hd}, {r, 0, hd}, {0, -1, 0});
        m.quad({-hw, 0, -hd}, {-r, 0, -hd}, {-r, 0, hd}, {-hw, 0, hd}, {0, -1, 0});
    }
    return m;
}

// ---------------------------------------------------------------------------
// Reading the description

class Builder {
public:
    explicit Builder(std::string source) : source_(std::move(source)) {}

    Scene build(const std::string& text);

private:
    std::string source_;
    Scene scene_;
    std::map<std::string, int> materialIndex_;
    std::vector<std::vector<std::uint32_t>> trianglesByMaterial_;
    const Json* prefabs_ = nullptr;
    std::size_t triangles_ = 0;

    [[noreturn]] void fail(const std::string& where, const std::string& what) const {
        throw SceneError(source_ + ": " + (where.empty() ? "" : where + ": ") + what);
    }

    // --- typed accessors (all errors name the JSON path) -------------------
    void allowKeys(const Json& obj, const std::string& where, std::initializer_list<std::string_view> keys) const {
        if (!obj.is_object()) fail(where, "expected a JSON object");
        for (auto it = obj.begin(); it != obj.end(); ++it) {
            if (it.key() == "comment" || it.key() == "description") continue;
            if (std::find(keys.begin(), keys.end(), it.key()) == keys.end()) {
                std::string list;
                for (auto k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
                fail(where, "unknown key '" + it.key() + "' (expected " + (list.empty() ? "none" : list) + ")");
            }
        }
    }
    double number(const Json& obj, const std::string& where, const char* key) const {
        if (!obj.contains(key)) fail(where, std::string("missing '") + key + "'");
        const Json& j = obj.at(key);
        if (!j.is_number()) fail(where, std::string("'") + key + "' must be a number");
        double x = j.get<double>();
        if (!std::isfinite(x)) fail(where, std::string("'") + key + "' is not finite");
        return x;
    }
    double number(const Json& obj, const std::string& where, const char* key, double fallback) const {
        return obj.contains(key) ? number(obj, where, key) : fallback;
    }
    double positive(const Json& obj, const std::string& where, const char* key) const {
        double x = number(obj, where, key);
        if (!(x > 0.0)) fail(where, std::string("'") + key + "' must be positive");
        return x;
    }
    double positive(const Json& obj, const std::string& where, const char* key, double fallback) const {
        return obj.contains(key) ? positive(obj, where, key) : fallback;
    }
    double unitInterval(const Json& obj, const std::string& where, const char* key, double fallback) const {
        double x = number(obj, where, key, fallback);
        if (x < 0.0 || x > 1.0) fail(where, std::string("'") + key + "' must lie in [0, 1]");
        return x;
    }
    int integer(const Json& obj, const std::string& where, const char* key, int fallback, int lo, long hi) const {
        if (!obj.contains(key)) return fallback;
        const Json& j = obj.at(key);
        if (!j.is_number_integer() || j.get<long long>() < lo || j.get<long long>() > hi)
            fail(where, std::string("'") + key + "' must be an integer in [" + std::to_string(lo) + ", " +
                            std::to_string(hi) + "]");
        return int(j.get<long long>());
    }
    bool boolean(const Json& obj, const std::string& where, const char* key, bool fallback) const {
        if (!obj.contains(key)) return fallback;
        if (!obj.at(key).is_boolean()) fail(where, std::string("'") + key + "' must be true or false");
        return obj.at(key).get<bool>();
    }
    std::string string(const Json& obj, const std::string& where, const char* key) const {
        if (!obj.contains(key) || !obj.at(key).is_string()) fail(where, std::string("'") + key + "' must be a string");
        return obj.at(key).get<std::string>();
    }
    // n numbers; a single number is accepted for colours (grey) when n == 3 and allowScalar.
    std::vector<double> numbers(const Json& obj, const std::string& where, const char* key, std::size_t nMin,
                                std::size_t nMax, bool allowScalar = false) const {
        if (!obj.contains(key)) fail(where, std::string("missing '") + key + "'");
        const Json& j = obj.at(key);
        std::vector<double> out;
        if (allowScalar && j.is_number()) {
            out.assign(3, j.get<double>());
        } else {
            if (!j.is_array() || j.size() < nMin || j.size() > nMax)
                fail(where, std::string("'") + key + "' must be an array of " + std::to_string(nMin) +
                                (nMax > nMin ? " or " + std::to_string(nMax) : std::string()) + " numbers");
            for (auto& e : j) {
                if (!e.is_number()) fail(where, std::string("'") + key + "' must contain numbers only");
                out.push_back(e.get<double>());
            }
        }
        for (double x : out)
            if (!std::isfinite(x)) fail(where, std::string("'") + key + "' is not finite");
        return out;
    }
    glm::vec3 vec3(const Json& obj, const std::string& where, const char* key) const {
        auto v = numbers(obj, where, key, 3, 3);
        return {float(v[0]), float(v[1]), float(v[2])};
    }
    glm::vec3 vec3(const Json& obj, const std::string& where, const char* key, glm::vec3 fallback) const {
        return obj.contains(key) ? vec3(obj, where, key) : fallback;
    }
    glm::vec3 direction(const Json& obj, const std::string& where, const char* key) const {
        glm::vec3 d = vec3(obj, where, key);
        if (!(glm::length(d) > 1e-12f)) fail(where, std::string("'") + key + "' must not be the zero vector");
        return glm::normalize(d);
    }
    glm::vec3 colour(const Json& obj, const std::string& where, const char* key, glm::vec3 fallback) const {
        if (!obj.contains(key)) return fallback;
        auto v = numbers(obj, where, key, 3, 3, true);
        for (double x : v)
            if (x < 0.0) fail(where, std::string("'") + key + "' must not be negative");
        return {float(v[0]), float(v[1]), float(v[2])};
    }

    // --- sections ----------------------------------------------------------
    void readMaterials(const Json& mats);
    void readLights(const Json& lights);
    Camera readCamera(const Json& cam, const std::string& where) const;
    void readItems(const Json& items, const std::string& where, const glm::mat4& xf, const std::string& material,
                   int depth);
    void readItem(const Json& item, const std::string& where, const glm::mat4& xf, const std::string& material,
                  int depth);
    void emit(const Mesh& mesh, const glm::mat4& xf, const std::string& material, const std::string& where);
};

void Builder::readMaterials(const Json& mats) {
    if (!mats.is_object() || mats.empty()) fail("materials", "expected an object of named materials");
    for (auto it = mats.begin(); it != mats.end(); ++it) {
        std::string where = "materials." + it.key();
        const Json& m = it.value();
        allowKeys(m, where, {"baseColor", "metallic", "roughness", "emissive"});
        Material mat;
        mat.name = it.key();
        if (m.contains("baseColor")) {
            auto c = numbers(m, where, "baseColor", 3, 4, true);
            for (double x : c)
                if (x < 0.0 || x > 1.0) fail(where, "'baseColor' components must lie in [0, 1] (linear albedo)");
            mat.baseColor = {float(c[0]), float(c[1]), float(c[2]), c.size() > 3 ? float(c[3]) : 1.0f};
        }
        mat.metallic = float(unitInterval(m, where, "metallic", 0.0));
        mat.roughness = float(unitInterval(m, where, "roughness", 1.0));
        mat.emissive = colour(m, where, "emissive", glm::vec3(0.0f));
        materialIndex_[mat.name] = int(scene_.materials.size());
        scene_.materials.push_back(mat);
    }
    trianglesByMaterial_.resize(scene_.materials.size());
}

void Builder::readLights(const Json& lights) {
    if (!lights.is_array()) fail("lights", "expected an array of lights");
    for (std::size_t k = 0; k < lights.size(); ++k) {
        std::string where = "lights[" + std::to_string(k) + "]";
        const Json& l = lights[k];
        if (!l.is_object()) fail(where, "expected a JSON object");
        std::string type = string(l, where, "type");
        Light light;
        light.name = l.contains("name") ? string(l, where, "name") : type + std::to_string(k);
        light.color = colour(l, where, "color", glm::vec3(1.0f));
        if (type == "directional") {
            allowKeys(l, where, {"type", "name", "color", "direction", "irradiance"});
            light.type = LightType::Directional;
            light.direction = direction(l, where, "direction");
            light.intensity = float(number(l, where, "irradiance"));
        } else if (type == "point" || type == "spot") {
            if (type == "point")
                allowKeys(l, where, {"type", "name", "color", "position", "intensity", "range", "radius"});
            else
                allowKeys(l, where,
                          {"type", "name", "color", "position", "intensity", "range", "radius", "direction",
                           "innerConeDeg", "outerConeDeg"});
            light.type = type == "point" ? LightType::Point : LightType::Spot;
            light.position = vec3(l, where, "position");
            light.intensity = float(number(l, where, "intensity"));
            light.range = float(number(l, where, "range", 0.0));
            light.radius = float(number(l, where, "radius", 0.0));
            if (!(light.radius >= 0.0f && light.radius <= 1e4f)) fail(where, "light radius must be in 0..1e4");
            if (type == "spot") {
                light.direction = direction(l, where, "direction");
                double inner = number(l, where, "innerConeDeg", 0.0), outer = number(l, where, "outerConeDeg", 45.0);
                if (inner < 0.0 || outer <= inner || outer > 90.0)
                    fail(where, "spot cones need 0 <= innerConeDeg < outerConeDeg <= 90");
                light.innerCone = float(glm::radians(inner));
                light.outerCone = float(glm::radians(outer));
            }
        } else {
            fail(where, "unknown light type '" + type + "' (expected directional, point or spot)");
        }
        if (light.intensity < 0.0f) fail(where, "light intensity must not be negative");
        scene_.lights.push_back(light);
    }
}

Camera Builder::readCamera(const Json& c, const std::string& where) const {
    allowKeys(c, where, {"name", "position", "target", "up", "fovY", "near", "far"});
    Camera cam;
    cam.name = c.contains("name") ? string(c, where, "name") : "camera";
    cam.position = vec3(c, where, "position");
    cam.target = vec3(c, where, "target");
    if (c.contains("up")) cam.up = direction(c, where, "up");
    double fov = number(c, where, "fovY", 60.0);
    if (!(fov > 1.0 && fov < 179.0)) fail(where, "'fovY' must lie in (1, 179) degrees");
    cam.fovY = float(glm::radians(fov));
    cam.near = float(positive(c, where, "near", 0.05));
    cam.far = float(positive(c, where, "far", 200.0));
    if (!(cam.far > cam.near)) fail(where, "'far' must exceed 'near'");
    glm::vec3 view = cam.target - cam.position;
    if (!(glm::length(view) > 1e-6f)) fail(where, "'target' must differ from 'position'");
    if (glm::length(glm::cross(glm::normalize(view), cam.up)) < 1e-4f) fail(where, "'up' is parallel to the view direction");
    return cam;
}

void Builder::emit(const Mesh& mesh, const glm::mat4& xf, const std::string& material, const std::string& where) {
    if (material.empty()) fail(where, "no material given (set 'material' here or on an enclosing repeat/group)");
    auto it = materialIndex_.find(material);
    if (it == materialIndex_.end()) fail(where, "unknown material '" + material + "'");
    triangles_ += mesh.i.size() / 3;
    if (triangles_ > kMaxTriangles) fail(where, "the scene exceeds " + std::to_string(kMaxTriangles) + " triangles");
    auto base = std::uint32_t(scene_.vertices.size());
    glm::mat3 rot(xf);
    for (const Vertex& v : mesh.v)
        scene_.vertices.push_back({glm::vec3(xf * glm::vec4(v.position, 1.0f)), glm::normalize(rot * v.normal), v.uv});
    auto& out = trianglesByMaterial_[std::size_t(it->second)];
    for (auto i : mesh.i) out.push_back(base + i);
}

void Builder::readItems(const Json& items, const std::string& where, const glm::mat4& xf, const std::string& material,
                        int depth) {
    if (!items.is_array()) fail(where, "expected an array of items");
    for (std::size_t k = 0; k < items.size(); ++k)
        readItem(items[k], where + "[" + std::to_string(k) + "]", xf, material, depth);
}

void Builder::readItem(const Json& item, const std::string& where, const glm::mat4& xf, const std::string& inherited,
                       int depth) {
    if (depth > kMaxNesting) fail(where, "nesting deeper than " + std::to_string(kMaxNesting) + " (prefab cycle?)");
    if (!item.is_object()) fail(where, "expected a JSON object");
    static constexpr std::string_view kKinds[] = {"box", "quad", "plane", "sphere", "cylinder", "arch",
                                                  "repeat", "group", "prefab"};
    std::string kind;
    for (auto it = item.begin(); it != item.end(); ++it)
        if (std::find(std::begin(kKinds), std::end(kKinds), it.key()) != std::end(kKinds)) {
            if (!kind.empty()) fail(where, "an item holds one primitive, found both '" + kind + "' and '" + it.key() + "'");
            kind = it.key();
        }
    if (kind.empty()) {
        std::string first;
        for (auto it = item.begin(); it != item.end(); ++it)
            if (it.key() != "material" && it.key() != "items" && it.key() != "comment" && it.key() != "description") {
                first = it.key();
                break;
            }
        fail(where, (first.empty() ? std::string("no primitive given") : "unknown primitive '" + first + "'") +
                        " (expected box, quad, plane, sphere, cylinder, arch, repeat, group or prefab)");
    }
    std::string material = inherited;
    if (item.contains("material")) material = string(item, where, "material");
    if (!material.empty() && !materialIndex_.count(material)) fail(where, "unknown material '" + material + "'");
    bool container = kind == "repeat" || kind == "group";
    if (container)
        allowKeys(item, where, {kind, "material", "items"});
    else
        allowKeys(item, where, {kind, "material"});
    const Json& p = item.at(kind);
    std::string at = where + "." + kind;
    bool ground = false;  // a "plane" marked "ground" (below)

    if (kind == "repeat") {
        allowKeys(p, at, {"count", "offset"});
        if (!p.contains("count")) fail(at, "missing 'count'");
        int count = integer(p, at, "count", 1, 1, kMaxRepeat);
        glm::vec3 offset = vec3(p, at, "offset");
        if (!item.contains("items")) fail(where, "a repeat needs 'items'");
        for (int n = 0; n < count; ++n)
            readItems(item.at("items"), where + ".items", xf * translate(float(n) * offset), material, depth + 1);
        return;
    }
    if (kind == "group") {
        allowKeys(p, at, {"translate", "rotateY"});
        glm::mat4 local = translate(vec3(p, at, "translate", glm::vec3(0.0f))) * rotateY(number(p, at, "rotateY", 0.0));
        if (!item.contains("items")) fail(where, "a group needs 'items'");
        readItems(item.at("items"), where + ".items", xf * local, material, depth + 1);
        return;
    }
    if (kind == "prefab") {
        if (p.is_string()) fail(at, "expected {\"name\": ..., \"translate\": ..., \"rotateY\": ...}");
        allowKeys(p, at, {"name", "translate", "rotateY"});
        std::string name = string(p, at, "name");
        if (!prefabs_ || !prefabs_->contains(name)) fail(at, "unknown prefab '" + name + "'");
        glm::mat4 local = translate(vec3(p, at, "translate", glm::vec3(0.0f))) * rotateY(number(p, at, "rotateY", 0.0));
        readItems(prefabs_->at(name), "prefabs." + name, xf * local, material, depth + 1);
        return;
    }

    // Leaf primitives: a local mesh and its placement.
    Mesh mesh;
    glm::mat4 local(1.0f);
    if (kind == "box") {
        allowKeys(p, at, {"center", "size", "min", "max", "rotationY"});
        glm::vec3 lo, hi;
        if (p.contains("min") || p.contains("max")) {
            if (p.contains("center") || p.contains("size")) fail(at, "give either center/size or min/max, not both");
            lo = vec3(p, at, "min");
            hi = vec3(p, at, "max");
        } else {
            glm::vec3 c = vec3(p, at, "center"), s = vec3(p, at, "size");
            lo = c - 0.5f * s;
            hi = c + 0.5f * s;
        }
        if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) fail(at, "the box has a zero or negative extent");
        mesh = makeBox(0.5f * (hi - lo));
        local = translate(0.5f * (lo + hi)) * rotateY(number(p, at, "rotationY", 0.0));
    } else if (kind == "quad" || kind == "plane") {
        allowKeys(p, at, {"center", "size", "normal", "rotationY", "ground"});
        // "ground": true marks a plane that stands in for an unbounded floor (Scene::groundVertices).
        if (p.contains("ground")) {
            if (!p.at("ground").is_boolean()) fail(at, "'ground' must be true or false");
            ground = p.at("ground").get<bool>();
        }
        auto s = numbers(p, at, "size", 2, 2);
        if (!(s[0] > 0.0 && s[1] > 0.0)) fail(at, "'size' must be positive");
        glm::vec3 n = p.contains("normal") ? direction(p, at, "normal") : glm::vec3(0, 1, 0);
        mesh = makeQuad(n, float(s[0]), float(s[1]));
        local = translate(vec3(p, at, "center")) * rotateY(number(p, at, "rotationY", 0.0));
    } else if (kind == "sphere") {
        allowKeys(p, at, {"center", "radius", "segments", "rings"});
        int segments = integer(p, at, "segments", 32, 3, 4096);
        int rings = integer(p, at, "rings", std::max(2, segments / 2), 2, 4096);
        mesh = makeSphere(float(positive(p, at, "radius")), segments, rings);
        local = translate(vec3(p, at, "center"));
    } else if (kind == "cylinder") {
        allowKeys(p, at, {"center", "base", "radius", "radiusTop", "height", "segments", "caps"});
        float r = float(positive(p, at, "radius"));
        float rTop = float(number(p, at, "radiusTop", r));
        if (rTop < 0.0f) fail(at, "'radiusTop' must not be negative");
        float h = float(positive(p, at, "height"));
        glm::vec3 base;
        if (p.contains("base") == p.contains("center")) fail(at, "give exactly one of 'base' (bottom centre) or 'center'");
        base = p.contains("base") ? vec3(p, at, "base") : vec3(p, at, "center") - glm::vec3(0, 0.5f * h, 0);
        mesh = makeCylinder(r, rTop, h, integer(p, at, "segments", 32, 3, 4096), boolean(p, at, "caps", true));
        local = translate(base);
    } else {  // arch
        allowKeys(p, at, {"center", "radius", "width", "top", "depth", "segments", "rotationY"});
        float r = float(positive(p, at, "radius"));
        float w = float(positive(p, at, "width"));
        float top = float(positive(p, at, "top"));
        if (w < 2.0f * r) fail(at, "'width' must be at least twice the 'radius'");
        if (!(top > r)) fail(at, "'top' must exceed the 'radius'");
        mesh = makeArch(r, w, top, float(positive(p, at, "depth")), integer(p, at, "segments", 24, 2, 4096));
        local = translate(vec3(p, at, "center")) * rotateY(number(p, at, "rotationY", 0.0));
    }
    const auto first = std::uint32_t(scene_.vertices.size());
    emit(mesh, xf * local, material, where);
    if (ground) scene_.groundVertices.push_back({first, std::uint32_t(scene_.vertices.size())});
}

Scene Builder::build(const std::string& text) {
    Json doc;
    try {
        doc = Json::parse(text, nullptr, true, /*ignore_comments=*/true);
    } catch (const Json::parse_error& e) {
        std::string msg = e.what();
        if (auto p = msg.find("] "); msg.rfind("[json.exception", 0) == 0 && p != std::string::npos) msg = msg.substr(p + 2);
        fail("", "invalid JSON (" + msg + ")");
    }
    allowKeys(doc, "", {"materials", "prefabs", "objects", "lights", "camera", "cameras", "sky", "settings"});
    if (!doc.contains("materials")) fail("", "missing 'materials'");
    readMaterials(doc.at("materials"));
    if (doc.contains("prefabs")) {
        if (!doc.at("prefabs").is_object()) fail("prefabs", "expected an object of named item arrays");
        prefabs_ = &doc.at("prefabs");
    }
    if (doc.contains("lights")) readLights(doc.at("lights"));
    if (doc.contains("camera") && doc.contains("cameras")) fail("", "give either 'camera' or 'cameras', not both");
    if (doc.contains("camera")) scene_.cameras.push_back(readCamera(doc.at("camera"), "camera"));
    if (doc.contains("cameras")) {
        const Json& cams = doc.at("cameras");
        if (!cams.is_array()) fail("cameras", "expected an array of cameras");
        for (std::size_t k = 0; k < cams.size(); ++k)
            scene_.cameras.push_back(readCamera(cams[k], "cameras[" + std::to_string(k) + "]"));
    }
    scene_.sky = colour(doc, "", "sky", glm::vec3(0.0f));
    if (doc.contains("settings")) {
        // Suggested settings (exposure, LPV grid for the scene's scale): the
        // keys are checked against the settings table when they are applied.
        if (!doc.at("settings").is_object()) fail("settings", "expected an object of configuration keys");
        try {
            scene_.suggestedSettings = flattenJsonConfig(doc.at("settings").dump(), "settings");
        } catch (const ConfigError& e) {
            fail("settings", e.what());
        }
        Settings probe;
        for (auto& [k, v] : scene_.suggestedSettings) {
            try {
                applySetting(probe, k, v);
            } catch (const ConfigError& e) {
                fail("settings", e.what());
            }
        }
    }
    if (!doc.contains("objects")) fail("", "missing 'objects'");
    readItems(doc.at("objects"), "objects", glm::mat4(1.0f), "", 0);

    // One draw range per material, in the order the materials are declared.
    for (std::size_t m = 0; m < trianglesByMaterial_.size(); ++m) {
        auto& tris = trianglesByMaterial_[m];
        if (tris.empty()) continue;
        DrawRange d;
        d.firstIndex = std::uint32_t(scene_.indices.size());
        d.indexCount = std::uint32_t(tris.size());
        d.material = int(m);
        scene_.indices.insert(scene_.indices.end(), tris.begin(), tris.end());
        scene_.draws.push_back(d);
    }
    scene_.name = source_;
    return std::move(scene_);
}

constexpr std::string_view kScenePrefix = "scenes/", kSceneSuffix = ".json";

}  // namespace

Scene buildSceneFromJson(const std::string& text, const std::string& sourceName) {
    Scene s = Builder(sourceName).build(text);
    validateAndRepair(s, sourceName);
    return s;
}

std::vector<std::string> builtinSceneNames() {
    std::set<std::string> names;
    for (int k = 0; k < kEmbeddedFileCount; ++k) {
        std::string_view p = kEmbeddedFiles[k].path;
        if (p.size() > kScenePrefix.size() + kSceneSuffix.size() && p.substr(0, kScenePrefix.size()) == kScenePrefix &&
            p.substr(p.size() - kSceneSuffix.size()) == kSceneSuffix) {
            std::string_view name = p.substr(kScenePrefix.size(), p.size() - kScenePrefix.size() - kSceneSuffix.size());
            if (name.find('/') == std::string_view::npos) names.emplace(name);
        }
    }
    return {names.begin(), names.end()};
}

Scene loadBuiltin(const std::string& name) {
    auto names = builtinSceneNames();
    if (std::find(names.begin(), names.end(), name) == names.end()) {
        std::string list;
        for (auto& n : names) list += (list.empty() ? "" : ", ") + n;
        throw SceneError("unknown built-in scene 'builtin:" + name + "' (valid: " + list + ")");
    }
    std::string path = std::string(kScenePrefix) + name + std::string(kSceneSuffix);
    auto text = readEmbeddedFile(path);
    if (!text) throw SceneError(path + ": the embedded scene description is missing");
    Scene s = Builder(path).build(*text);
    s.name = "builtin:" + name;
    validateAndRepair(s, s.name);
    return s;
}

void placeOnFloor(Scene& model, float floorY) {
    Aabb b = model.bounds();
    if (b.empty()) return;
    float dy = floorY - b.lo.y;
    for (auto& v : model.vertices) v.position.y += dy;
    for (auto& l : model.lights) l.position.y += dy;
    for (auto& c : model.cameras) {
        c.position.y += dy;
        c.target.y += dy;
    }
}

}  // namespace rtgi
