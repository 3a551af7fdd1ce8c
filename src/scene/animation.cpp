#include "scene/animation.h"

#include "scene/scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace rtgi {

const char* toString(Interpolation i) {
    switch (i) {
        case Interpolation::Linear: return "LINEAR";
        case Interpolation::Step: return "STEP";
        case Interpolation::CubicSpline: return "CUBICSPLINE";
    }
    return "?";
}

void KeyTrack::validate(const std::string& where) const {
    if (times.empty()) throw SceneError(where + ": the sampler has no keyframes");
    if (components < 1) throw SceneError(where + ": the sampler has no components");
    for (std::size_t i = 0; i < times.size(); ++i) {
        if (!std::isfinite(times[i])) throw SceneError(where + ": keyframe time " + std::to_string(i) + " is not finite");
        if (i > 0 && !(times[i] > times[i - 1]))
            throw SceneError(where + ": keyframe times must increase strictly (key " + std::to_string(i) + ")");
    }
    const std::size_t per = std::size_t(components) * (interpolation == Interpolation::CubicSpline ? 3 : 1);
    if (values.size() != per * times.size())
        throw SceneError(where + ": " + std::to_string(values.size()) + " output values for " +
                         std::to_string(times.size()) + " keyframes (expected " + std::to_string(per * times.size()) +
                         (interpolation == Interpolation::CubicSpline ? ": in-tangent, value, out-tangent per key)" : ")"));
    for (double v : values)
        if (!std::isfinite(v)) throw SceneError(where + ": an output value is not finite");
}

glm::dquat slerpShortest(const glm::dquat& a, const glm::dquat& bIn, double u) {
    glm::dquat b = bIn;
    double d = glm::dot(a, b);
    if (d < 0.0) {  // the shorter arc: q and -q are the same rotation
        b = -b;
        d = -d;
    }
    if (d > 1.0 - 1e-12) return glm::normalize(a * (1.0 - u) + b * u);
    const double theta = std::acos(std::min(d, 1.0));
    const double s = std::sin(theta);
    return a * (std::sin((1.0 - u) * theta) / s) + b * (std::sin(u * theta) / s);
}

std::vector<double> KeyTrack::sample(double t) const {
    const std::size_t n = std::size_t(components);
    const bool cubic = interpolation == Interpolation::CubicSpline;
    const std::size_t stride = cubic ? 3 * n : n;
    auto value = [&](std::size_t key) {  // the key's value (the middle of a cubic triple)
        const double* p = values.data() + key * stride + (cubic ? n : 0);
        return std::vector<double>(p, p + n);
    };
    auto normalized = [&](std::vector<double> v) {
        if (!rotation) return v;
        double len = 0;
        for (double x : v) len += x * x;
        len = std::sqrt(len);
        if (len > 0)
            for (double& x : v) x /= len;
        return v;
    };
    if (t <= times.front() || times.size() == 1) return normalized(value(0));
    if (t >= times.back()) return normalized(value(times.size() - 1));
    // The key k with times[k] <= t < times[k + 1].
    const std::size_t k = std::size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
    const double td = times[k + 1] - times[k];
    const double s = (t - times[k]) / td;
    if (interpolation == Interpolation::Step) return value(k);
    if (interpolation == Interpolation::Linear) {
        std::vector<double> a = value(k), b = value(k + 1), out(n);
        if (rotation && n == 4) {
            glm::dquat q = slerpShortest(glm::dquat(a[3], a[0], a[1], a[2]), glm::dquat(b[3], b[0], b[1], b[2]), s);
            return {q.x, q.y, q.z, q.w};
        }
        for (std::size_t c = 0; c < n; ++c) out[c] = a[c] + s * (b[c] - a[c]);
        return out;
    }
    // CUBICSPLINE (glTF 2.0 Appendix C): Hermite with tangents scaled by the key interval.
    const double s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    const double* p0 = values.data() + k * stride;        // a_k, v_k, b_k
    const double* p1 = values.data() + (k + 1) * stride;  // a_k+1, v_k+1, b_k+1
    std::vector<double> out(n);
    for (std::size_t c = 0; c < n; ++c)
        out[c] = h00 * p0[n + c] + h10 * td * p0[2 * n + c] + h01 * p1[n + c] + h11 * td * p1[c];
    return normalized(out);
}

glm::dmat4 Trs::matrix() const {
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), translation) * glm::mat4_cast(rotation);
    return glm::scale(m, scale);
}

double SceneAnimation::duration() const {
    double d = 0;
    for (auto& t : tracks)
        if (!t.times.empty()) d = std::max(d, t.times.back());
    return d;
}

namespace {

std::vector<glm::dmat4> worldOf(const SceneAnimation& a, const double* t) {
    std::vector<glm::dmat4> world(a.nodes.size());
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        const AnimatedNode& n = a.nodes[i];
        glm::dmat4 local;
        if (n.matrix) {
            local = *n.matrix;
        } else {
            Trs trs = n.rest;
            if (t) {
                auto get = [&](AnimatedProperty p) -> const KeyTrack* {
                    int k = n.track[int(p)];
                    return k >= 0 ? &a.tracks[std::size_t(k)] : nullptr;
                };
                if (auto* k = get(AnimatedProperty::Translation)) {
                    auto v = k->sample(*t);
                    trs.translation = {v[0], v[1], v[2]};
                }
                if (auto* k = get(AnimatedProperty::Rotation)) {
                    auto v = k->sample(*t);
                    trs.rotation = glm::dquat(v[3], v[0], v[1], v[2]);
                }
                if (auto* k = get(AnimatedProperty::Scale)) {
                    auto v = k->sample(*t);
                    trs.scale = {v[0], v[1], v[2]};
                }
            }
            local = trs.matrix();
        }
        world[i] = n.parent >= 0 ? world[std::size_t(n.parent)] * local : local;
    }
    return world;
}

}  // namespace

std::vector<glm::dmat4> SceneAnimation::worldAt(double t) const { return worldOf(*this, &t); }
std::vector<glm::dmat4> SceneAnimation::restWorld() const { return worldOf(*this, nullptr); }

void SceneAnimation::offset(std::uint32_t vertices, int lights, int cameras) {
    for (auto& n : nodes) {
        for (auto& r : n.vertexRanges) r.first += vertices;
        for (int& l : n.lights) l += lights;
        for (int& c : n.cameras) c += cameras;
    }
}

void transformVertices(Scene& scene, const Scene& rest,
                       const std::vector<std::pair<std::uint32_t, std::uint32_t>>& ranges, const glm::dmat4& delta) {
    const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(delta)));
    for (auto [first, count] : ranges)
        for (std::uint32_t i = first; i < first + count && i < rest.vertices.size(); ++i) {
            const Vertex& r = rest.vertices[i];
            Vertex& v = scene.vertices[i];
            v.position = glm::vec3(delta * glm::dvec4(glm::dvec3(r.position), 1.0));
            glm::dvec3 n = normalMatrix * glm::dvec3(r.normal);
            double len = glm::length(n);
            v.normal = len > 0 ? glm::vec3(n / len) : r.normal;
        }
    scene.motions.push_back({ranges, delta});
}

bool applySceneAnimation(Scene& out, const Scene& rest, double t) {
    out.motions.clear();
    const SceneAnimation& a = rest.animation;
    if (a.empty()) return false;
    const std::vector<glm::dmat4> w0 = a.restWorld(), wt = a.worldAt(t);
    bool moved = false;
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        const AnimatedNode& n = a.nodes[i];
        const glm::dmat4 delta = wt[i] * glm::inverse(w0[i]);
        if (!n.vertexRanges.empty() && delta != glm::dmat4(1.0)) {
            transformVertices(out, rest, n.vertexRanges, delta);
            moved = true;
        }
        for (int li : n.lights) {
            Light& l = out.lights[std::size_t(li)];
            l.position = glm::vec3(wt[i][3]);
            glm::dvec3 d = glm::dmat3(wt[i]) * glm::dvec3(0, 0, -1);
            if (glm::length(d) > 0) l.direction = glm::vec3(glm::normalize(d));
        }
        for (int ci : n.cameras) {
            Camera& c = out.cameras[std::size_t(ci)];
            const Camera& c0 = rest.cameras[std::size_t(ci)];
            const double dist = std::max(1e-3, double(glm::length(c0.target - c0.position)));
            c.position = glm::vec3(wt[i][3]);
            glm::dvec3 f = glm::dmat3(wt[i]) * glm::dvec3(0, 0, -1), up = glm::dmat3(wt[i]) * glm::dvec3(0, 1, 0);
            if (glm::length(f) > 0) c.target = glm::vec3(glm::dvec3(wt[i][3]) + glm::normalize(f) * dist);
            if (glm::length(up) > 0) c.up = glm::vec3(glm::normalize(up));
        }
    }
    return moved;
}

}  // namespace rtgi
