#include "scene/path.h"

#include "gl/embedded.h"
#include "gl/input_files.h"
#include "render/settings.h"

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace rtgi {

// ---- centripetal Catmull-Rom ------------------------------------------------

namespace {

constexpr int kArcSteps = 256;  // per segment, for the arc-length table

// Knot spacing |Pj+1 - Pj|^0.5 (centripetal), kept away from 0 so that
// repeated keys (a camera that stops) stay finite.
double knotStep(const glm::dvec3& a, const glm::dvec3& b) { return std::max(std::sqrt(glm::length(b - a)), 1e-6); }

}  // namespace

glm::dvec3 CatmullRom::segment(std::size_t i, double u) const {
    const std::size_t n = points.size();
    if (n == 1) return points[0];
    i = std::min(i, n - 2);
    const glm::dvec3 p1 = points[i], p2 = points[i + 1];
    if (glm::length(p2 - p1) < 1e-12) return p1;  // a stop: the segment stays put
    // The ends are extended by reflection: P(-1) = 2 P0 - P1, P(n) = 2 P(n-1) - P(n-2).
    const glm::dvec3 p0 = i > 0 ? points[i - 1] : 2.0 * p1 - p2;
    const glm::dvec3 p3 = i + 2 < n ? points[i + 2] : 2.0 * p2 - p1;
    // Barry-Goldman pyramid on the centripetal knots k0..k3.
    const double k0 = 0, k1 = k0 + knotStep(p0, p1), k2 = k1 + knotStep(p1, p2), k3 = k2 + knotStep(p2, p3);
    const double t = k1 + u * (k2 - k1);
    const glm::dvec3 a1 = (k1 - t) / (k1 - k0) * p0 + (t - k0) / (k1 - k0) * p1;
    const glm::dvec3 a2 = (k2 - t) / (k2 - k1) * p1 + (t - k1) / (k2 - k1) * p2;
    const glm::dvec3 a3 = (k3 - t) / (k3 - k2) * p2 + (t - k2) / (k3 - k2) * p3;
    const glm::dvec3 b1 = (k2 - t) / (k2 - k0) * a1 + (t - k0) / (k2 - k0) * a2;
    const glm::dvec3 b2 = (k3 - t) / (k3 - k1) * a2 + (t - k1) / (k3 - k1) * a3;
    return (k2 - t) / (k2 - k1) * b1 + (t - k1) / (k2 - k1) * b2;
}

void CatmullRom::buildArc() const {
    if (!arc_.empty() || points.size() < 2) return;
    arc_.push_back(0.0);
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        glm::dvec3 prev = segment(i, 0.0);
        for (int s = 1; s <= kArcSteps; ++s) {
            glm::dvec3 p = segment(i, double(s) / kArcSteps);
            arc_.push_back(arc_.back() + glm::length(p - prev));
            prev = p;
        }
    }
}

double CatmullRom::length() const {
    buildArc();
    return arc_.empty() ? 0.0 : arc_.back();
}

std::pair<std::size_t, double> CatmullRom::locate(double t, bool constantSpeed) const {
    const std::size_t n = points.size();
    if (n < 2) return {0, 0.0};
    const double t0 = times.front(), t1 = times.back();
    t = std::clamp(t, t0, t1);
    if (!constantSpeed) {
        std::size_t k = std::size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin());
        k = std::clamp<std::size_t>(k, 1, n - 1) - 1;
        return {k, (t - times[k]) / (times[k + 1] - times[k])};
    }
    buildArc();
    const double s = arc_.back() * (t1 > t0 ? (t - t0) / (t1 - t0) : 0.0);
    std::size_t j = std::size_t(std::lower_bound(arc_.begin(), arc_.end(), s) - arc_.begin());
    j = std::clamp<std::size_t>(j, 1, arc_.size() - 1);
    const double run = arc_[j] - arc_[j - 1];
    const double step = double(j - 1) + (run > 0 ? (s - arc_[j - 1]) / run : 0.0);  // in table steps
    const std::size_t seg = std::min(std::size_t(step / kArcSteps), n - 2);
    return {seg, std::clamp(step / kArcSteps - double(seg), 0.0, 1.0)};
}

glm::dvec3 CatmullRom::at(double t, bool constantSpeed) const {
    auto [i, u] = locate(t, constantSpeed);
    return segment(i, u);
}

// ---- parsing ---------------------------------------------------------------

namespace {

using Json = nlohmann::json;

struct Reader {
    std::string where;  // "benchmarks/paths/atrium.json: path 'x'"
    [[noreturn]] void fail(const std::string& at, const std::string& what) const {
        throw ConfigError(where + (at.empty() ? "" : ": " + at) + ": " + what);
    }
    double number(const Json& j, const std::string& at) const {
        if (!j.is_number()) fail(at, "expected a number");
        double v = j.get<double>();
        if (!std::isfinite(v)) fail(at, "is not finite");
        return v;
    }
    glm::dvec3 vec3(const Json& j, const std::string& at) const {
        if (!j.is_array() || j.size() != 3) fail(at, "expected [x, y, z]");
        return {number(j[0], at + "[0]"), number(j[1], at + "[1]"), number(j[2], at + "[2]")};
    }
    void allow(const Json& j, const std::string& at, std::initializer_list<const char*> keys) const {
        if (!j.is_object()) fail(at, "expected an object");
        for (auto& [k, v] : j.items()) {
            bool ok = false;
            for (const char* a : keys) ok = ok || k == a;
            if (!ok) {
                std::string list;
                for (const char* a : keys) list += std::string(list.empty() ? "" : ", ") + a;
                fail(at, "unknown key '" + k + "' (allowed: " + list + ")");
            }
        }
    }
    const Json& keys(const Json& j, const std::string& at) const {
        if (!j.contains("keys") || !j["keys"].is_array() || j["keys"].empty()) fail(at, "needs a non-empty 'keys' array");
        return j["keys"];
    }
    Interpolation interpolation(const Json& j, const std::string& at, Interpolation dflt) const {
        if (!j.contains("interpolation")) return dflt;
        std::string s = j["interpolation"].is_string() ? j["interpolation"].get<std::string>() : "";
        if (s == "linear") return Interpolation::Linear;
        if (s == "step") return Interpolation::Step;
        fail(at + ".interpolation", "expected \"linear\" or \"step\"");
    }
    // A track of `field` over `keys` (keys without the field are skipped).
    std::optional<KeyTrack> track(const Json& ks, const std::string& at, const char* field, int components,
                                  Interpolation interp) const {
        KeyTrack k;
        k.components = components;
        k.interpolation = interp;
        for (std::size_t i = 0; i < ks.size(); ++i) {
            const std::string ka = at + ".keys[" + std::to_string(i) + "]";
            if (!ks[i].contains(field)) continue;
            k.times.push_back(number(ks[i].value("t", Json()), ka + ".t"));
            if (components == 1) k.values.push_back(number(ks[i][field], ka + "." + field));
            else if (components == 3) {
                glm::dvec3 v = vec3(ks[i][field], ka + "." + field);
                k.values.insert(k.values.end(), {v.x, v.y, v.z});
            } else fail(ka, "internal: unsupported component count");
        }
        if (k.times.empty()) return std::nullopt;
        try {
            k.validate(at + "." + field);
        } catch (const SceneError& e) {
            throw ConfigError(where + ": " + e.what());
        }
        return k;
    }
};

std::string sceneKeyOf(const Scene& scene) {
    std::string key = scene.name;
    if (key.rfind("builtin:", 0) == 0) key = key.substr(8);
    for (char& ch : key)
        if (ch == '/' || ch == '+' || ch == ':') ch = '_';
    return key;
}

// The embedded benchmarks/paths/*.json that apply to the scene.
std::vector<std::pair<std::string, Json>> pathFilesFor(const Scene& scene) {
    const std::string key = sceneKeyOf(scene);
    std::vector<std::pair<std::string, Json>> out;
    for (int i = 0; i < kEmbeddedFileCount; ++i) {
        std::string p = kEmbeddedFiles[i].path;
        if (p.rfind("benchmarks/paths/", 0) != 0) continue;
        Json j = Json::parse(kEmbeddedFiles[i].text, nullptr, false);
        if (j.is_discarded() || !j.contains("paths")) continue;
        std::string fileScene = j.value("scene", "");
        if (!fileScene.empty() && key.find(fileScene) == std::string::npos) continue;
        out.emplace_back(p, std::move(j));
    }
    return out;
}

Path parsePathJson(const Json& j, const std::string& source, const std::string& name) {
    Path p;
    p.name = name;
    p.source = source;
    Reader r{source + (name.empty() ? "" : ": path '" + name + "'")};
    r.allow(j, "", {"description", "fps", "duration", "camera", "sun", "lights", "objects", "events", "comment"});
    p.description = j.value("description", "");
    if (j.contains("fps")) {
        p.fps = r.number(j["fps"], "fps");
        if (!(p.fps > 0 && p.fps <= 1000)) r.fail("fps", "must lie in (0, 1000]");
    }
    double last = 0;
    auto grow = [&](const KeyTrack& k) { last = std::max(last, k.times.back()); };
    if (j.contains("camera")) {
        const Json& c = j["camera"];
        r.allow(c, "camera", {"constant_speed", "keys", "comment"});
        CameraPath cp;
        if (c.contains("constant_speed")) {
            if (!c["constant_speed"].is_boolean()) r.fail("camera.constant_speed", "expected true or false");
            cp.constantSpeed = c["constant_speed"].get<bool>();
        }
        const Json& ks = r.keys(c, "camera");
        for (std::size_t i = 0; i < ks.size(); ++i) {
            const std::string at = "camera.keys[" + std::to_string(i) + "]";
            r.allow(ks[i], at, {"t", "position", "target", "fov"});
            if (!ks[i].contains("position") || !ks[i].contains("target") || !ks[i].contains("t"))
                r.fail(at, "needs t, position and target");
            double t = r.number(ks[i]["t"], at + ".t");
            if (i > 0 && !(t > cp.position.times.back())) r.fail(at + ".t", "key times must increase strictly");
            glm::dvec3 pos = r.vec3(ks[i]["position"], at + ".position"), tgt = r.vec3(ks[i]["target"], at + ".target");
            if (glm::length(tgt - pos) <= 0) r.fail(at, "position and target coincide");
            cp.position.times.push_back(t);
            cp.position.points.push_back(pos);
            cp.target.times.push_back(t);
            cp.target.points.push_back(tgt);
        }
        cp.fovDeg = r.track(ks, "camera", "fov", 1, Interpolation::Linear);
        if (cp.fovDeg)
            for (double f : cp.fovDeg->values)
                if (!(f > 1 && f < 179)) r.fail("camera", "fov must lie in (1, 179) degrees");
        last = std::max(last, cp.position.times.back());
        p.camera = std::move(cp);
    }
    if (j.contains("sun")) {
        const Json& s = j["sun"];
        r.allow(s, "sun", {"keys", "comment"});
        const Json& ks = r.keys(s, "sun");
        SunPath sp;
        sp.elevationAzimuthDeg.components = 2;
        for (std::size_t i = 0; i < ks.size(); ++i) {
            const std::string at = "sun.keys[" + std::to_string(i) + "]";
            r.allow(ks[i], at, {"t", "elevation", "azimuth", "irradiance"});
            if (!ks[i].contains("t") || !ks[i].contains("elevation") || !ks[i].contains("azimuth"))
                r.fail(at, "needs t, elevation and azimuth (degrees)");
            sp.elevationAzimuthDeg.times.push_back(r.number(ks[i]["t"], at + ".t"));
            double el = r.number(ks[i]["elevation"], at + ".elevation");
            if (!(el > 0 && el <= 90)) r.fail(at + ".elevation", "must lie in (0, 90] degrees (a sun below the horizon lights nothing)");
            sp.elevationAzimuthDeg.values.push_back(el);
            sp.elevationAzimuthDeg.values.push_back(r.number(ks[i]["azimuth"], at + ".azimuth"));
        }
        try {
            sp.elevationAzimuthDeg.validate("sun");
        } catch (const SceneError& e) {
            throw ConfigError(r.where + ": " + e.what());
        }
        sp.irradiance = r.track(ks, "sun", "irradiance", 1, Interpolation::Linear);
        grow(sp.elevationAzimuthDeg);
        p.sun = std::move(sp);
    }
    if (j.contains("lights")) {
        if (!j["lights"].is_array()) r.fail("lights", "expected an array");
        for (std::size_t li = 0; li < j["lights"].size(); ++li) {
            const Json& l = j["lights"][li];
            const std::string at = "lights[" + std::to_string(li) + "]";
            r.allow(l, at, {"light", "interpolation", "keys", "comment"});
            if (!l.contains("light") || !l["light"].is_string()) r.fail(at, "needs 'light' (the light's name)");
            LightPath lp;
            lp.light = l["light"].get<std::string>();
            Interpolation in = r.interpolation(l, at, Interpolation::Linear);
            const Json& ks = r.keys(l, at);
            for (std::size_t i = 0; i < ks.size(); ++i)
                r.allow(ks[i], at + ".keys[" + std::to_string(i) + "]", {"t", "intensity", "color"});
            lp.intensity = r.track(ks, at, "intensity", 1, in);
            lp.color = r.track(ks, at, "color", 3, in);
            if (!lp.intensity && !lp.color) r.fail(at, "its keys set neither intensity nor color");
            for (auto* k : {&lp.intensity, &lp.color})
                if (*k) {
                    for (double v : (*k)->values)
                        if (v < 0) r.fail(at, "intensity and color must not be negative");
                    grow(**k);
                    // A switched light is a step event (lag, docs/temporal.md).
                    if (in == Interpolation::Step)
                        for (std::size_t i = 1; i < (*k)->times.size(); ++i) p.events.push_back((*k)->times[i]);
                }
            p.lights.push_back(std::move(lp));
        }
    }
    if (j.contains("objects")) {
        if (!j["objects"].is_array()) r.fail("objects", "expected an array");
        for (std::size_t oi = 0; oi < j["objects"].size(); ++oi) {
            const Json& o = j["objects"][oi];
            const std::string at = "objects[" + std::to_string(oi) + "]";
            r.allow(o, at, {"name", "select", "interpolation", "keys", "comment"});
            ObjectPath op;
            op.name = o.value("name", "object " + std::to_string(oi));
            if (!o.contains("select")) r.fail(at, "needs 'select': {\"min\": [x,y,z], \"max\": [x,y,z]}");
            r.allow(o["select"], at + ".select", {"min", "max"});
            op.select.lo = glm::vec3(r.vec3(o["select"].value("min", Json()), at + ".select.min"));
            op.select.hi = glm::vec3(r.vec3(o["select"].value("max", Json()), at + ".select.max"));
            if (op.select.empty()) r.fail(at + ".select", "min exceeds max");
            Interpolation in = r.interpolation(o, at, Interpolation::Linear);
            const Json& ks = r.keys(o, at);
            for (std::size_t i = 0; i < ks.size(); ++i)
                r.allow(ks[i], at + ".keys[" + std::to_string(i) + "]", {"t", "translate", "rotate_y"});
            auto tr = r.track(ks, at, "translate", 3, in);
            if (!tr) r.fail(at, "its keys need 'translate' (world offset)");
            op.translate = *tr;
            op.rotateYDeg = r.track(ks, at, "rotate_y", 1, in);
            grow(op.translate);
            p.objects.push_back(std::move(op));
        }
    }
    if (j.contains("events")) {
        if (!j["events"].is_array()) r.fail("events", "expected an array of times (seconds)");
        for (std::size_t i = 0; i < j["events"].size(); ++i) p.events.push_back(r.number(j["events"][i], "events[" + std::to_string(i) + "]"));
    }
    std::sort(p.events.begin(), p.events.end());
    p.events.erase(std::unique(p.events.begin(), p.events.end()), p.events.end());
    if (j.contains("duration")) {
        p.duration = r.number(j["duration"], "duration");
        if (!(p.duration >= 0 && p.duration <= 3600)) r.fail("duration", "must lie in [0, 3600] seconds");
    } else {
        p.duration = last;
    }
    if (!p.camera && !p.sun && p.lights.empty() && p.objects.empty())
        r.fail("", "the path moves nothing (no camera, sun, lights or objects)");
    return p;
}

}  // namespace

int Path::frameCount() const { return int(std::llround(duration * fps)) + 1; }

Path parsePath(const std::string& text, const std::string& source, const std::string& name) {
    Json j = Json::parse(text, nullptr, false);
    if (j.is_discarded()) throw ConfigError(source + ": not valid JSON");
    return parsePathJson(j, source, name);
}

std::vector<std::string> namedPaths(const Scene& scene) {
    std::vector<std::string> names;
    for (auto& [file, j] : pathFilesFor(scene))
        for (auto& [name, v] : j["paths"].items()) names.push_back(name);
    return names;
}

Path loadPath(const std::string& spec, const Scene& scene) {
    Path p;
    const bool isFile = spec.find('/') != std::string::npos ||
                        (spec.size() > 5 && spec.compare(spec.size() - 5, 5, ".json") == 0);
    if (isFile) {
        std::string text;
        try {
            text = readInputFile(spec, InputKind::Config);
        } catch (const InputError& e) {
            throw ConfigError(std::string("--path ") + e.what());
        }
        p = parsePath(text, spec, "");
        p.name = std::filesystem::path(spec).stem().string();
    } else {
        bool found = false;
        for (auto& [file, j] : pathFilesFor(scene))
            if (!found && j["paths"].contains(spec)) {
                p = parsePathJson(j["paths"][spec], file, spec);
                found = true;
            }
        if (!found) {
            std::string list;
            for (auto& n : namedPaths(scene)) list += (list.empty() ? "" : ", ") + n;
            throw ConfigError("--path '" + spec + "': no path of that name for scene " + scene.name +
                              " in benchmarks/paths/ (" + (list.empty() ? "none for this scene" : "known: " + list) +
                              "); a file needs a '/' or the .json suffix");
        }
    }
    checkPathAgainst(p, scene);
    return p;
}

namespace {

std::vector<std::pair<std::uint32_t, std::uint32_t>> selectRanges(const Scene& scene, const Aabb& box) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> ranges;
    for (std::uint32_t i = 0; i < scene.vertices.size(); ++i) {
        const glm::vec3 q = scene.vertices[i].position;
        if (glm::all(glm::greaterThanEqual(q, box.lo)) && glm::all(glm::lessThanEqual(q, box.hi))) {
            if (!ranges.empty() && ranges.back().first + ranges.back().second == i) ++ranges.back().second;
            else ranges.emplace_back(i, 1);
        }
    }
    return ranges;
}

const Light* findLight(const Scene& s, const std::string& name) {
    for (auto& l : s.lights)
        if (l.name == name) return &l;
    return nullptr;
}

}  // namespace

void checkPathAgainst(const Path& p, const Scene& scene) {
    const std::string where = p.source + (p.name.empty() ? "" : ": path '" + p.name + "'");
    for (auto& l : p.lights)
        if (!findLight(scene, l.light)) {
            std::string list;
            for (auto& x : scene.lights) list += (list.empty() ? "" : ", ") + ("'" + x.name + "'");
            throw ConfigError(where + ": light '" + l.light + "' is not in scene " + scene.name + " (lights: " +
                              (list.empty() ? "none" : list) + ")");
        }
    if (p.sun && !scene.sun()) throw ConfigError(where + ": it moves the sun, but scene " + scene.name + " has none");
    for (auto& o : p.objects)
        if (selectRanges(scene, o.select).empty())
            throw ConfigError(where + ": object '" + o.name + "' selects no vertex of scene " + scene.name);
}

SceneChange evaluateScene(Scene& out, const Scene& rest, const Path* path, double t) {
    SceneChange ch;
    ch.geometry = applySceneAnimation(out, rest, t);
    if (path) {
        if (path->sun)
            for (auto& l : out.lights)
                if (l.type == LightType::Directional) {
                    auto ea = path->sun->elevationAzimuthDeg.sample(t);
                    const double el = glm::radians(ea[0]), az = glm::radians(ea[1]);
                    const glm::dvec3 toward(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
                    l.direction = glm::vec3(-toward);
                    if (path->sun->irradiance) l.intensity = float(path->sun->irradiance->sample(t)[0]);
                    break;  // the sun: the first directional light (Scene::sun)
                }
        for (auto& lp : path->lights)
            for (auto& l : out.lights)
                if (l.name == lp.light) {
                    if (lp.intensity) l.intensity = float(lp.intensity->sample(t)[0]);
                    if (lp.color) {
                        auto c = lp.color->sample(t);
                        l.color = glm::vec3(float(c[0]), float(c[1]), float(c[2]));
                    }
                }
        for (auto& o : path->objects) {
            auto ranges = selectRanges(rest, o.select);
            auto tr = o.translate.sample(t);
            const glm::dvec3 c(o.select.center());
            glm::dmat4 m = glm::translate(glm::dmat4(1.0), c + glm::dvec3(tr[0], tr[1], tr[2]));
            if (o.rotateYDeg) m = glm::rotate(m, glm::radians(o.rotateYDeg->sample(t)[0]), glm::dvec3(0, 1, 0));
            m = glm::translate(m, -c);
            if (m != glm::dmat4(1.0)) {
                transformVertices(out, rest, ranges, m);
                ch.geometry = true;
            }
        }
    }
    for (std::size_t i = 0; i < out.lights.size() && i < rest.lights.size(); ++i) {
        const Light &a = out.lights[i], &b = rest.lights[i];
        if (a.position != b.position || a.direction != b.direction || a.color != b.color || a.intensity != b.intensity)
            ch.lights = true;
    }
    return ch;
}

Camera pathCamera(const Path* path, double t, const Camera& fallback) {
    if (!path || !path->camera) return fallback;
    const CameraPath& cp = *path->camera;
    Camera c = fallback;
    auto [seg, u] = cp.position.locate(t, cp.constantSpeed);
    c.position = glm::vec3(cp.position.segment(seg, u));
    c.target = glm::vec3(cp.target.segment(seg, u));
    if (cp.fovDeg) {
        // The fov at the time the position curve is at (the same key fraction).
        const auto& ts = cp.position.times;
        const double tk = ts.size() > 1 ? ts[seg] + u * (ts[seg + 1] - ts[seg]) : ts[0];
        c.fovY = float(glm::radians(cp.fovDeg->sample(tk)[0]));
    }
    c.name = path->name;
    return c;
}

}  // namespace rtgi
