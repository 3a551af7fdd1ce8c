#include "render/reference/metrics.h"

#include "scene/color.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace rtgi {

double pixelLuminance(const FloatImage& img, std::size_t i, int channels) {
    const float* p = &img.data[i * std::size_t(img.channels)];
    if (channels == 1 || img.channels == 1) return p[0];
    return luminance(p[0], p[1], p[2]);
}

namespace {
// A pixel whose compared channels are not all finite, in either image, is
// left out of every error sum (a single NaN would make RMSE NaN and a single
// Inf would make it Inf, hiding the error of the rest) and counted instead.
bool finitePixel(const FloatImage& img, std::size_t i, int channels) {
    const float* p = &img.data[i * std::size_t(img.channels)];
    int n = img.channels == 1 ? 1 : channels;
    for (int c = 0; c < n; ++c)
        if (!std::isfinite(p[c])) return false;
    return true;
}
bool nanPixel(const FloatImage& img, std::size_t i, int channels) {
    const float* p = &img.data[i * std::size_t(img.channels)];
    int n = img.channels == 1 ? 1 : channels;
    for (int c = 0; c < n; ++c)
        if (std::isnan(p[c])) return true;
    return false;
}
void checkSizes(const FloatImage& a, const FloatImage& b) {
    if (a.width != b.width || a.height != b.height)
        throw std::runtime_error("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                                 " vs " + std::to_string(b.width) + "x" + std::to_string(b.height));
}
}  // namespace

ErrorMetrics compareImages(const FloatImage& t, const FloatImage& r, int channels, double peak,
                           const std::vector<std::uint8_t>& mask) {
    checkSizes(t, r);
    ErrorMetrics m;
    const std::size_t n = std::size_t(t.width) * std::size_t(t.height);
    double se = 0, ae = 0, bias = 0, rel = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!mask.empty() && !mask[i]) continue;
        if (!finitePixel(t, i, channels) || !finitePixel(r, i, channels)) {
            ++(nanPixel(t, i, channels) || nanPixel(r, i, channels) ? m.nanPixels : m.infPixels);
            continue;
        }
        ++m.pixels;
        for (int c = 0; c < channels; ++c) {
            double a = t.data[i * std::size_t(t.channels) + std::size_t(c)];
            double b = r.data[i * std::size_t(r.channels) + std::size_t(c)];
            double d = a - b;
            se += d * d;
            ae += std::abs(d);
            bias += d;
            rel += d * d / (b * b + 1e-4);  // ε = 0.01 keeps dark pixels from dominating
            ++count;
        }
    }
    if (count > 0) {
        m.rmse = std::sqrt(se / double(count));
        m.mae = ae / double(count);
        m.bias = bias / double(count);
        m.relRmse = std::sqrt(rel / double(count));
        double mse = se / double(count);
        m.psnr = mse > 0 ? 10.0 * std::log10(peak * peak / mse) : std::numeric_limits<double>::infinity();
    }
    m.ssim = ssimLuminance(t, r, channels, peak);
    return m;
}

std::vector<std::uint8_t> depthInteriorMask(const FloatImage& depth, double relativeJump) {
    const int w = depth.width, h = depth.height;
    const std::size_t ch = std::size_t(depth.channels);
    auto at = [&](int x, int y) { return double(depth.data[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * ch]); };
    std::vector<std::uint8_t> mask(std::size_t(w) * std::size_t(h), 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double d = at(x, y);
            if (!(d > 0.0)) continue;
            bool interior = true;
            for (int dy = -1; dy <= 1 && interior; ++dy)
                for (int dx = -1; dx <= 1 && interior; ++dx) {
                    const int nx = std::clamp(x + dx, 0, w - 1), ny = std::clamp(y + dy, 0, h - 1);
                    const double n = at(nx, ny);
                    interior = n > 0.0 && std::abs(n - d) <= relativeJump * d;
                }
            mask[std::size_t(y) * std::size_t(w) + std::size_t(x)] = interior ? 1 : 0;
        }
    return mask;
}

double ssimLuminance(const FloatImage& a, const FloatImage& b, int channels, double L) {
    checkSizes(a, b);
    const int w = a.width, h = a.height;
    if (w == 0 || h == 0) return 1.0;
    std::vector<double> x(std::size_t(w * h)), y(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        x[i] = pixelLuminance(a, i, channels);
        y[i] = pixelLuminance(b, i, channels);
        if (!std::isfinite(x[i]) || !std::isfinite(y[i])) x[i] = y[i] = 0.0;  // counted by compareImages
    }
    // 11×11 Gaussian, σ = 1.5, normalized; separable. Borders clamp to the
    // edge so every pixel has a full window (small test images included).
    std::array<double, 11> g{};
    double gs = 0;
    for (int k = 0; k < 11; ++k) gs += g[std::size_t(k)] = std::exp(-double((k - 5) * (k - 5)) / (2.0 * 1.5 * 1.5));
    for (auto& v : g) v /= gs;
    auto blur = [&](const std::vector<double>& in) {
        std::vector<double> tmp(in.size()), out(in.size());
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                double s = 0;
                for (int k = 0; k < 11; ++k) s += g[std::size_t(k)] * in[std::size_t(j * w + std::clamp(i + k - 5, 0, w - 1))];
                tmp[std::size_t(j * w + i)] = s;
            }
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                double s = 0;
                for (int k = 0; k < 11; ++k) s += g[std::size_t(k)] * tmp[std::size_t(std::clamp(j + k - 5, 0, h - 1) * w + i)];
                out[std::size_t(j * w + i)] = s;
            }
        return out;
    };
    std::vector<double> xx(x.size()), yy(x.size()), xy(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        xx[i] = x[i] * x[i];
        yy[i] = y[i] * y[i];
        xy[i] = x[i] * y[i];
    }
    auto mx = blur(x), my = blur(y), sxx = blur(xx), syy = blur(yy), sxy = blur(xy);
    const double c1 = (0.01 * L) * (0.01 * L), c2 = (0.03 * L) * (0.03 * L);  // Wang et al. K1, K2
    double sum = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i], cxy = sxy[i] - mx[i] * my[i];
        sum += ((2 * mx[i] * my[i] + c1) * (2 * cxy + c2)) / ((mx[i] * mx[i] + my[i] * my[i] + c1) * (vx + vy + c2));
    }
    return sum / double(x.size());
}

double errorQuantile(const FloatImage& t, const FloatImage& r, int channels, double q) {
    checkSizes(t, r);
    std::vector<double> e;
    e.reserve(std::size_t(t.width) * std::size_t(t.height));
    for (std::size_t i = 0; i < std::size_t(t.width) * std::size_t(t.height); ++i) {
        double d = std::abs(pixelLuminance(t, i, channels) - pixelLuminance(r, i, channels));
        if (std::isfinite(d)) e.push_back(d);  // NaN breaks nth_element's ordering; Inf is counted elsewhere
    }
    if (e.empty()) return 0.0;
    auto k = std::size_t(std::clamp(q, 0.0, 1.0) * double(e.size() - 1) + 0.5);
    std::nth_element(e.begin(), e.begin() + std::ptrdiff_t(k), e.end());
    return e[k];
}

namespace {

// Ramp black -> purple -> red -> orange -> yellow (inferno-like, monotonic in
// lightness). NaN (a NaN in either image) is shown in cyan, outside the ramp;
// +Inf saturates to yellow like any error above the scale.
std::array<float, 3> ramp(double v) {
    static const float stops[5][3] = {{0, 0, 0.02f}, {0.34f, 0.06f, 0.43f}, {0.73f, 0.21f, 0.33f}, {0.97f, 0.55f, 0.04f},
                                      {0.99f, 1.0f, 0.64f}};
    if (std::isnan(v)) return {0.0f, 1.0f, 1.0f};
    v = std::clamp(v, 0.0, 1.0) * 4.0;
    int i = std::min(3, int(v));
    float f = float(v - i);
    return {stops[i][0] + f * (stops[i + 1][0] - stops[i][0]), stops[i][1] + f * (stops[i + 1][1] - stops[i][1]),
            stops[i][2] + f * (stops[i + 1][2] - stops[i][2])};
}

// 3×5 pixel glyphs for the colour-bar labels (rows top to bottom, 3 bits each).
int glyph(char c, int row) {
    static const char* digits[] = {"111101101101111", "010110010010111", "111001111100111", "111001111001111",
                                   "101101111001001", "111100111001111", "111100111101111", "111001001001001",
                                   "111101111101111", "111101111001111"};
    const char* g = nullptr;
    if (c >= '0' && c <= '9') g = digits[c - '0'];
    else if (c == '.') g = "000000000000010";
    else if (c == '-') g = "000000111000000";
    else if (c == '+') g = "000010111010000";
    else if (c == 'e') g = "000111111100111";
    if (!g) return 0;
    int bits = 0;
    for (int k = 0; k < 3; ++k) bits = bits * 2 + (g[row * 3 + k] == '1');
    return bits;
}

// Text at pixel (x, yTop) in an image whose row 0 is the bottom; scale 1.
void drawText(FloatImage& img, int x, int yTop, const std::string& s) {
    for (char c : s) {
        for (int row = 0; row < 5; ++row) {
            int bits = glyph(c, row);
            for (int k = 0; k < 3; ++k) {
                if (!(bits & (4 >> k))) continue;
                int px = x + k, py = yTop - row;
                if (px < 0 || py < 0 || px >= img.width || py >= img.height) continue;
                for (int ch = 0; ch < 3; ++ch) img.data[std::size_t((py * img.width + px) * 4 + ch)] = 1.0f;
            }
        }
        x += 4;
    }
}

}  // namespace

FloatImage errorHeatmap(const FloatImage& t, const FloatImage& r, int channels, double maxError) {
    checkSizes(t, r);
    const int barW = 44;  // 4 gap + 8 bar + 2 gap + label text (up to 7 glyphs × 4 px + margin)
    FloatImage out;
    out.width = t.width + barW;
    out.height = t.height;
    out.channels = 4;
    out.data.assign(std::size_t(out.width * out.height * 4), 0.0f);
    for (std::size_t i = 3; i < out.data.size(); i += 4) out.data[i] = 1.0f;
    // all-equal images: any scale shows black; a non-finite scale (from a
    // caller's own statistics) would turn every pixel NaN or 0
    double scale = maxError > 0 && std::isfinite(maxError) ? maxError : 1.0;
    for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x) {
            std::size_t i = std::size_t(y * t.width + x);
            auto c = ramp(std::abs(pixelLuminance(t, i, channels) - pixelLuminance(r, i, channels)) / scale);
            for (int ch = 0; ch < 3; ++ch) out.data[std::size_t((y * out.width + x) * 4 + ch)] = c[std::size_t(ch)];
        }
    for (int y = 0; y < t.height; ++y) {
        auto c = ramp(t.height > 1 ? double(y) / double(t.height - 1) : 0.0);
        for (int x = t.width + 4; x < t.width + 12; ++x)
            for (int ch = 0; ch < 3; ++ch) out.data[std::size_t((y * out.width + x) * 4 + ch)] = c[std::size_t(ch)];
    }
    char top[32];
    std::snprintf(top, sizeof top, "%.2g", scale);
    drawText(out, t.width + 14, t.height - 1, top);
    drawText(out, t.width + 14, 4, "0");
    return out;
}

double rmsStandardError(const FloatImage& se, int channels, const std::vector<std::uint8_t>& mask) {
    const std::size_t n = std::size_t(se.width) * std::size_t(se.height);
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!mask.empty() && !mask[i]) continue;
        for (int c = 0; c < channels; ++c) {
            const double v = se.data[i * std::size_t(se.channels) + std::size_t(c)];
            sum += v * v;
            ++count;
        }
    }
    return count > 0 ? std::sqrt(sum / double(count)) : 0.0;
}

RmseUncertainty rmseUncertainty(const FloatImage& test, const FloatImage& ref, const FloatImage& se, int channels,
                                const std::vector<std::uint8_t>& mask, double z) {
    const std::size_t n = std::size_t(ref.width) * std::size_t(ref.height);
    const auto at = [](const FloatImage& img, std::size_t i, int c) {
        return double(img.data[i * std::size_t(img.channels) + std::size_t(std::min(c, img.channels - 1))]);
    };
    double sq = 0, noise = 0, var = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!mask.empty() && !mask[i]) continue;
        bool finite = true;
        for (int c = 0; c < channels; ++c)
            finite &= std::isfinite(at(test, i, c)) && std::isfinite(at(ref, i, c)) && std::isfinite(at(se, i, c));
        if (!finite) continue;
        double sdSum = 0;  // Σ_c √Var((d_c − e_c)²): fully correlated channels
        for (int c = 0; c < channels; ++c) {
            const double d = at(test, i, c) - at(ref, i, c), s2 = at(se, i, c) * at(se, i, c);
            sq += d * d;
            noise += s2;
            const double d2 = std::max(0.0, d * d - s2);
            sdSum += std::sqrt(4.0 * d2 * s2 + 2.0 * s2 * s2);
        }
        var += sdSum * sdSum;
        count += std::size_t(channels);
    }
    RmseUncertainty u;
    u.z = z;
    if (count == 0) return u;
    const double m = double(count);
    const double mse = sq / m, noiseMse = noise / m, deb = mse - noiseMse, sd = std::sqrt(var) / m;
    u.rmse = std::sqrt(mse);
    u.rmseDebiased = std::sqrt(std::max(0.0, deb));
    u.low = std::sqrt(std::max(0.0, deb - z * sd));
    u.high = std::sqrt(std::max(0.0, deb + z * sd));
    u.noiseRms = std::sqrt(noiseMse);
    return u;
}

}  // namespace rtgi
