#pragma once
// Time in the scene (issue 23, docs/temporal.md): keyframe tracks sampled in
// double per the glTF 2.0 spec (LINEAR / STEP / CUBICSPLINE; rotations slerp
// on the shorter arc), the node hierarchy of an animated glTF kept beside the
// flattened scene, and the scene state at time t (vertices of moving nodes,
// lights, cameras) evaluated from it.
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rtgi {

struct Scene;

enum class Interpolation { Linear, Step, CubicSpline };
const char* toString(Interpolation i);

// One glTF animation sampler (or a path file's keyframes), in double.
struct KeyTrack {
    std::vector<double> times;   // strictly increasing, finite
    // `components` values per key; CUBICSPLINE: in-tangent, value, out-tangent per key (glTF order).
    std::vector<double> values;
    int components = 3;
    Interpolation interpolation = Interpolation::Linear;
    bool rotation = false;  // unit quaternion (x, y, z, w): LINEAR slerps, CUBICSPLINE normalizes

    // Clamped to [times.front(), times.back()] outside the keys (glTF).
    std::vector<double> sample(double t) const;
    // Throws SceneError "<where>: ..." on empty/unsorted/non-finite keys or a value count that does not fit.
    void validate(const std::string& where) const;
};

// Spherical linear interpolation of unit quaternions along the shorter arc
// (glTF 2.0, Appendix C); nearly parallel quaternions fall back to a normalized lerp.
glm::dquat slerpShortest(const glm::dquat& a, const glm::dquat& b, double u);

// A node's local transform: T * R * S (glTF).
struct Trs {
    glm::dvec3 translation{0.0};
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  // glm order w, x, y, z
    glm::dvec3 scale{1.0};
    glm::dmat4 matrix() const;
};

enum class AnimatedProperty { Translation, Rotation, Scale };

// One node instance of the flattened scene (a glTF node reached through the
// hierarchy) with what it places: the vertex ranges it appended, its lights
// and cameras (indices into the Scene's arrays).
struct AnimatedNode {
    int parent = -1;  // index into SceneAnimation::nodes
    std::string name;
    std::optional<glm::dmat4> matrix;  // a node given by "matrix" (glTF: not animatable)
    Trs rest;                          // its TRS in the flattened (rest) scene
    int track[3] = {-1, -1, -1};       // per AnimatedProperty: index into SceneAnimation::tracks
    std::vector<std::pair<std::uint32_t, std::uint32_t>> vertexRanges;  // (first, count)
    std::vector<int> lights, cameras;
};

struct SceneAnimation {
    std::vector<AnimatedNode> nodes;  // parents before children
    std::vector<KeyTrack> tracks;
    bool empty() const { return tracks.empty(); }
    double duration() const;  // last key time over all tracks (0 without tracks)
    // World matrices of every node at time t (rest: the flattened scene's pose).
    std::vector<glm::dmat4> worldAt(double t) const;
    std::vector<glm::dmat4> restWorld() const;
    // Offsets vertex ranges, light and camera indices (Scene::merge).
    void offset(std::uint32_t vertices, int lights, int cameras);
};

// One rigid motion of a scene state: the vertex ranges (first, count) of one
// object and the matrix that takes them from the rest pose to where they are.
// The GPU scene moves such objects by their matrices instead of re-uploading
// the vertices (GpuScene::setTransforms; docs/temporal.md, "Object motion").
struct RigidMotion {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> ranges;
    glm::dmat4 delta{1.0};
};

// Moves the rigid set of vertices `ranges` of `scene` by the matrix `delta`
// (positions by delta, normals by its inverse transpose), reading from `rest`,
// and records the motion in scene.motions.
void transformVertices(Scene& scene, const Scene& rest, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& ranges,
                       const glm::dmat4& delta);

// The scene's own animation (glTF) at time t: `rest` with every animated
// node's vertices, lights and cameras moved (out.motions starts empty and
// lists the moved nodes). Returns whether geometry moved.
bool applySceneAnimation(Scene& out, const Scene& rest, double t);

}  // namespace rtgi
