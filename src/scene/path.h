#pragma once
// Camera paths and scripted scene changes (issue 23, docs/temporal.md):
// camera keyframes (position, target, fov) on a centripetal Catmull-Rom
// spline (optionally at constant speed), sun keyframes (elevation/azimuth),
// light intensity/colour keyframes (a light switching on or off), and rigid
// motion of the geometry inside a box. Read from `--path FILE` or by name
// from benchmarks/paths/<scene>.json; evaluated at t = frame / fps.
#include "scene/animation.h"
#include "scene/scene.h"

#include <optional>
#include <string>
#include <vector>

namespace rtgi {

// Centripetal Catmull-Rom (alpha = 0.5) through `points` reached at `times`
// (the key times, strictly increasing); the ends are extended by reflecting
// the neighbouring key. constantSpeed: the curve at uniform arc length over
// [times.front(), times.back()] instead of reaching key i at times[i].
struct CatmullRom {
    std::vector<glm::dvec3> points;
    std::vector<double> times;
    // Point on segment i (points[i] .. points[i+1]) at fraction u in [0, 1] of its knot interval.
    glm::dvec3 segment(std::size_t i, double u) const;
    // Segment and fraction at time t (clamped); constantSpeed: by arc length.
    std::pair<std::size_t, double> locate(double t, bool constantSpeed) const;
    glm::dvec3 at(double t, bool constantSpeed) const;
    double length() const;  // arc length (numerical, 256 steps per segment)

private:
    mutable std::vector<double> arc_;  // cumulative arc length table (lazily built)
    void buildArc() const;
};

struct CameraPath {
    CatmullRom position, target;
    std::optional<KeyTrack> fovDeg;  // LINEAR, degrees
    bool constantSpeed = false;
};

struct SunPath {
    KeyTrack elevationAzimuthDeg;  // 2 components, LINEAR: toward-sun elevation above the horizon, azimuth from +z towards +x
    std::optional<KeyTrack> irradiance;
};

struct LightPath {
    std::string light;                      // Light::name
    std::optional<KeyTrack> intensity, color;
};

struct ObjectPath {
    std::string name;
    Aabb select;  // every vertex range of the scene that lies entirely inside moves
    KeyTrack translate;                  // 3 components, world offset
    std::optional<KeyTrack> rotateYDeg;  // about the selection's centre
};

struct Path {
    std::string name, source, description;
    double fps = 30.0;
    double duration = 0.0;  // seconds; frames = round(duration * fps) + 1 (both ends)
    std::optional<CameraPath> camera;
    std::optional<SunPath> sun;
    std::vector<LightPath> lights;
    std::vector<ObjectPath> objects;
    std::vector<double> events;  // step events (seconds) for the lag: STEP light keys and "events"

    int frameCount() const;
    double timeOfFrame(int frame) const { return double(frame) / fps; }
};

// `spec` is a file (contains '/' or ends in .json) or the name of a path in
// benchmarks/paths/ for the scene. Throws ConfigError naming the file / name
// and the problem (unknown light, empty keys, ...).
Path loadPath(const std::string& spec, const Scene& scene);
Path parsePath(const std::string& jsonText, const std::string& source, const std::string& name);
// Names of the named paths that apply to a scene.
std::vector<std::string> namedPaths(const Scene& scene);
// Checks the path against the scene (lights exist, selections hit geometry).
void checkPathAgainst(const Path& path, const Scene& scene);

// What changed from the rest scene at time t.
struct SceneChange {
    bool geometry = false;  // vertices moved (GPU vertex buffer, BVH)
    bool lights = false;    // a light's position, direction, colour or intensity differs from the rest scene
};

// The scene at time t: its own glTF animation, then the path's sun, lights and objects.
// `out` must start as a copy of `rest` (vertices are rewritten from rest).
SceneChange evaluateScene(Scene& out, const Scene& rest, const Path* path, double t);
// The camera at time t: the path's when it has one, else `fallback`.
Camera pathCamera(const Path* path, double t, const Camera& fallback);

}  // namespace rtgi
