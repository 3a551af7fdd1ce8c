#include "render/ao/ao_params.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace rtgi {

glm::ivec2 horizonSampling(int samples) {
    int dirs = samples >= 24 ? 6 : 4;
    if (samples < 4) dirs = samples;
    return {dirs, std::max(1, samples / dirs)};
}

double sphereKernelRadius(double u) { return 2.0 * std::sin(std::asin(std::clamp(u, 0.0, 1.0)) / 3.0); }

std::vector<glm::vec4> sphereKernel(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    // Antithetic pairs (o, -o) at consecutive indices: every linear map the
    // estimators apply (reflection by the noise vector, rotation) keeps them
    // antipodal, so on a plane exactly one of each pair lies below it and the
    // half-space normalization min(v, 0.5)*2 is not biased by the kernel's
    // random imbalance (docs/ao.md, "Normalization").
    const int m = (n + 1) / 2;
    std::vector<glm::vec4> base;
    for (int i = 0; i < m; ++i) {
        // Stratify the radius over the pairs so small kernels still follow d(x).
        double u = (i + uni(rng)) / m;
        double theta = 2.0 * M_PI * uni(rng), cosPhi = 2.0 * uni(rng) - 1.0;
        double sinPhi = std::sqrt(std::max(0.0, 1.0 - cosPhi * cosPhi)), r = sphereKernelRadius(u);
        base.emplace_back(float(r * std::cos(theta) * sinPhi), float(r * std::sin(theta) * sinPhi),
                          float(r * cosPhi), 0.0f);
    }
    // Shuffle the pairs so a prefix of the kernel is not radially sorted.
    std::shuffle(base.begin(), base.end(), rng);
    std::vector<glm::vec4> k;
    for (const glm::vec4& o : base) {
        k.push_back(o);
        if (int(k.size()) < n) k.push_back(-o);
    }
    return k;
}

std::vector<glm::vec4> voSamplePairs(int pairs, int grid) {
    // Vogel spiral over the full disk with 2*pairs points, then keep every
    // point with its mirror: positions p_i (i < pairs) and -p_i.
    const int n = 2 * pairs;
    std::vector<glm::dvec2> pts;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < pairs; ++i) {
        double r = std::sqrt((i + 0.5) / pairs) * 0.92;  // stay off the rim where z_s -> 0
        double a = i * golden;
        pts.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    for (int i = 0; i < pairs; ++i) pts.push_back(-pts[std::size_t(i)]);
    std::vector<double> volume(std::size_t(n), 0.0);
    const double cell = 2.0 / grid;
    for (int gy = 0; gy < grid; ++gy)
        for (int gx = 0; gx < grid; ++gx) {
            glm::dvec2 q(-1 + (gx + 0.5) * cell, -1 + (gy + 0.5) * cell);
            double r2 = glm::dot(q, q);
            if (r2 >= 1.0) continue;
            std::size_t best = 0;
            double bestD = 1e9;
            for (std::size_t i = 0; i < pts.size(); ++i) {
                glm::dvec2 d = q - pts[i];
                double dd = glm::dot(d, d);
                if (dd < bestD) bestD = dd, best = i;
            }
            volume[best] += 2.0 * std::sqrt(1.0 - r2) * cell * cell;
        }
    std::vector<glm::vec4> out;
    for (int i = 0; i < pairs; ++i) {
        glm::dvec2 p = pts[std::size_t(i)];
        double zs = std::sqrt(std::max(0.0, 1.0 - glm::dot(p, p)));
        double v = 0.5 * (volume[std::size_t(i)] + volume[std::size_t(i + pairs)]);
        out.emplace_back(float(p.x), float(p.y), float(zs), float(v));
    }
    return out;
}

std::vector<glm::vec2> poissonDisk(int k, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
    std::vector<glm::vec2> pts;
    // Expected spacing of k points in a unit disk, relaxed whenever darts fail.
    float minD = 1.6f / std::sqrt(float(k));
    int fails = 0;
    while (int(pts.size()) < k) {
        glm::vec2 c(uni(rng), uni(rng));
        if (glm::dot(c, c) > 1.0f) continue;
        bool ok = std::all_of(pts.begin(), pts.end(), [&](glm::vec2 p) { return glm::distance(p, c) >= minD; });
        if (ok) {
            pts.push_back(c);
            fails = 0;
        } else if (++fails > 200) {
            minD *= 0.9f;
            fails = 0;
        }
    }
    return pts;
}

gpu::AoParams makeAoParams(const AoSettings& s, glm::ivec2 aoSize, glm::ivec2 fullSize, float fovY) {
    gpu::AoParams p{};
    const float cotHalf = 1.0f / std::tan(0.5f * fovY);
    const float aspect = float(fullSize.x) / float(fullSize.y);
    // Loos & Sloan dual radii: the second, small radius catches detail (seed 003 4.2.1 uses 0.25 vs 1).
    p.radius = {s.radius, 0.25f * s.radius, 2.0f * s.radius, std::tan(glm::radians(s.angleBiasDeg))};
    p.focal = {cotHalf / aspect, cotHalf, 1.0f / cotHalf, aspect};
    glm::ivec2 hs = horizonSampling(s.samples);
    p.counts = {s.samples, hs.x, hs.y, int(s.variant)};
    p.flags = {s.removeEdgeHighlight, s.useNormals, s.multiBounce, int(s.radiusMode)};
    p.size = {aoSize.x, aoSize.y, fullSize.x, fullSize.y};
    const int pairs = std::min(RTGI_AO_MAX_VO_PAIRS, std::max(1, s.samples / 2));
    p.misc = {s.dualCombineMin ? 1.0f : 0.0f, s.nearfield, float(pairs), float(s.dynamicProbe)};
    p.bitmask = {s.thicknessMode == AoSettings::ThicknessMode::Infinite ? -1.0f : s.thickness,
                 s.thicknessMode == AoSettings::ThicknessMode::Depth ? 1.0f : 0.0f, float(s.rays), 0.0f};
    auto k = sphereKernel(std::min(s.samples, RTGI_AO_MAX_KERNEL));
    std::copy(k.begin(), k.end(), p.kernel);
    auto vo = voSamplePairs(pairs);
    double sum = 0;
    for (auto& v : vo) sum += v.w;
    for (std::size_t i = 0; i < vo.size(); ++i) p.voSamples[i] = {vo[i].x, vo[i].y, vo[i].z, float(vo[i].w / sum)};
    auto probe = poissonDisk(s.dynamicProbe);
    for (std::size_t i = 0; i < probe.size(); ++i) p.probe[i] = {probe[i], 0, 0};
    return p;
}

}  // namespace rtgi
