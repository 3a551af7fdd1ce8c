#include "bench/temporal.h"

#include <algorithm>
#include <cmath>

namespace rtgi {

std::vector<std::int32_t> reprojectPixels(const FrameGeometry& g, const FloatImage& prevDepth, double tolerance) {
    const int w = g.depth.width, h = g.depth.height;
    std::vector<std::int32_t> out(std::size_t(w) * std::size_t(h), -2);
    const glm::dmat4 invView = glm::inverse(g.view);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            const double d = g.depth.at(x, y, 0);
            if (!(d > 0)) continue;  // sky
            out[i] = -1;
            const double u = (x + 0.5) / w, v = (y + 0.5) / h;
            // The surface point in the world, then in the previous view and image.
            const glm::dvec4 pView((2 * u - 1) * g.tanHalfFovY * g.aspect * d, (2 * v - 1) * g.tanHalfFovY * d, -d, 1.0);
            const glm::dvec4 prevViewPos = g.prevView * (invView * pView);
            const double expected = -prevViewPos.z;
            if (!(expected > 0)) continue;  // behind the previous camera
            const glm::dvec4 clip = g.prevProj * prevViewPos;
            const double pu = 0.5 * clip.x / clip.w + 0.5, pv = 0.5 * clip.y / clip.w + 0.5;
            if (!(pu >= 0 && pu < 1 && pv >= 0 && pv < 1)) continue;  // off screen last frame
            const int px = std::min(int(pu * w), w - 1), py = std::min(int(pv * h), h - 1);
            const double dPrev = prevDepth.at(px, py, 0);
            if (!(dPrev > 0)) continue;
            if (std::abs(dPrev - expected) > tolerance * expected) continue;
            out[i] = py * w + px;
        }
    return out;
}

std::optional<double> flickerRms(const FloatImage& I, const FloatImage& R, const FloatImage& Ip, const FloatImage& Rp,
                                 const std::vector<std::int32_t>& prev, int channels) {
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t p = 0; p < prev.size(); ++p) {
        if (prev[p] < 0) continue;
        const std::size_t q = std::size_t(prev[p]);
        for (int c = 0; c < channels; ++c) {
            const double e = double(I.data[p * std::size_t(I.channels) + std::size_t(c)]) -
                             double(R.data[p * std::size_t(R.channels) + std::size_t(c)]);
            const double ep = double(Ip.data[q * std::size_t(Ip.channels) + std::size_t(c)]) -
                              double(Rp.data[q * std::size_t(Rp.channels) + std::size_t(c)]);
            sum += (e - ep) * (e - ep);
            ++n;
        }
    }
    if (n == 0) return std::nullopt;
    return std::sqrt(sum / double(n));
}

std::optional<double> maskedRmse(const FloatImage& I, const FloatImage& R, const std::vector<std::uint8_t>& mask,
                                 int channels) {
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t p = 0; p < mask.size(); ++p) {
        if (!mask[p]) continue;
        for (int c = 0; c < channels; ++c) {
            const double e = double(I.data[p * std::size_t(I.channels) + std::size_t(c)]) -
                             double(R.data[p * std::size_t(R.channels) + std::size_t(c)]);
            sum += e * e;
            ++n;
        }
    }
    if (n == 0) return std::nullopt;
    return std::sqrt(sum / double(n));
}

Lag lagAfter(const std::vector<std::optional<double>>& error, int event, double tolerance) {
    Lag lag;
    if (event < 1 || event >= int(error.size()) || !error[std::size_t(event - 1)]) return lag;
    lag.levelBefore = *error[std::size_t(event - 1)];
    for (int j = event; j < int(error.size()); ++j) {
        if (!error[std::size_t(j)]) continue;
        lag.peak = std::max(lag.peak, *error[std::size_t(j)]);
        if (*error[std::size_t(j)] <= (1 + tolerance) * lag.levelBefore) {
            lag.frames = j - event;
            return lag;
        }
    }
    return lag;
}

Summary summarize(const std::vector<std::optional<double>>& values) {
    std::vector<double> v;
    for (auto& x : values)
        if (x) v.push_back(*x);
    Summary s;
    s.count = int(v.size());
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    double sum = 0;
    for (double x : v) sum += x;
    s.mean = sum / double(v.size());
    s.max = v.back();
    // Nearest rank: the smallest value with at least 95 % of the values at or below it.
    s.p95 = v[std::size_t(std::ceil(0.95 * double(v.size()))) - 1];
    return s;
}

}  // namespace rtgi
