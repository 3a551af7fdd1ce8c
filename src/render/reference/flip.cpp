#include "render/reference/flip.h"

#include "scene/color.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

namespace rtgi {

namespace {

using std::numbers::pi;
using Plane = std::vector<float>;

// ---------------------------------------------------------------------------
// Colour spaces (FLIP paper, colour pipeline; sRGB primaries, D65 white).

using Mat3 = std::array<std::array<double, 3>, 3>;

// Linear sRGB -> CIE XYZ, the exact rational form of the sRGB matrix that the
// FLIP reference code uses.
constexpr Mat3 kRgbToXyz = {{{10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
                             {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
                             {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}}};

Mat3 inverse(const Mat3& m) {
    Mat3 r{};
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            // Cofactor of m[j][i] (transposed adjugate).
            int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            r[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
        }
    return r;
}

const Mat3& xyzToRgb() {
    static const Mat3 m = inverse(kRgbToXyz);
    return m;
}

// The reference white: XYZ of linear RGB (1, 1, 1).
constexpr std::array<double, 3> kWhite = {kRgbToXyz[0][0] + kRgbToXyz[0][1] + kRgbToXyz[0][2], 1.0,
                                          kRgbToXyz[2][0] + kRgbToXyz[2][1] + kRgbToXyz[2][2]};

std::array<double, 3> mul(const Mat3& m, double a, double b, double c) {
    return {m[0][0] * a + m[0][1] * b + m[0][2] * c, m[1][0] * a + m[1][1] * b + m[1][2] * c,
            m[2][0] * a + m[2][1] * b + m[2][2] * c};
}

// CIELAB's cube root with its linear toe (δ = 6/29). The root in float
// (cbrtf): the per-pixel transcendentals dominate the cost after the filters,
// and float's 1e-7 is far below FLIP's resolution.
double labF(double t) {
    constexpr double d = 6.0 / 29.0;
    return t > d * d * d ? double(std::cbrt(float(t))) : t / (3.0 * d * d) + 4.0 / 29.0;
}

// Linear RGB (clamped to the unit cube) -> Hunt-adjusted L*a*b*: a and b
// scaled by 0.01·L* (FLIP, colour pipeline).
std::array<double, 3> huntLab(double r, double g, double b) {
    r = std::clamp(r, 0.0, 1.0), g = std::clamp(g, 0.0, 1.0), b = std::clamp(b, 0.0, 1.0);
    auto xyz = mul(kRgbToXyz, r, g, b);
    double fx = labF(xyz[0] / kWhite[0]), fy = labF(xyz[1] / kWhite[1]), fz = labF(xyz[2] / kWhite[2]);
    double L = 116.0 * fy - 16.0;
    return {L, 0.01 * L * 500.0 * (fx - fy), 0.01 * L * 200.0 * (fy - fz)};
}

// HyAB distance (Abasi et al. 2020): |ΔL| + ‖Δ(a, b)‖.
double hyab(const std::array<double, 3>& p, const std::array<double, 3>& q) {
    double da = p[1] - q[1], db = p[2] - q[2];
    return std::abs(p[0] - q[0]) + std::sqrt(da * da + db * db);
}

constexpr double kQc = 0.7, kPc = 0.4, kPt = 0.95;  // FLIP, colour metric
constexpr double kFeatureW = 0.082;  // FLIP, feature pipeline; q_f = 0.5 is the square root in flipMap

// c_max: the HyAB distance of the most different pair, pure green vs pure
// blue, raised to q_c (FLIP, colour metric).
double cmax() {
    static const double c = std::pow(hyab(huntLab(0, 1, 0), huntLab(0, 0, 1)), kQc);
    return c;
}

// Error redistribution (FLIP, colour metric): [0, p_c·c_max) -> [0, p_t), the rest
// -> [p_t, 1].
double redistribute(double e) {
    double c = cmax(), pcc = kPc * c;
    return e < pcc ? kPt / pcc * e : kPt + (e - pcc) / (c - pcc) * (1.0 - kPt);
}

// ---------------------------------------------------------------------------
// Separable filters.

// One 1D kernel of odd size 2r+1, centre at index r.
using Kernel = std::vector<float>;

// A 2D filter Σ_t k_t ⊗ k_t: a sum of separable terms.
using SeparableSum = std::vector<Kernel>;

// Contrast sensitivity filter of one YyCxCz channel (FLIP, spatial filtering):
// S(x) = Σ_i a_i √(π/b_i) exp(−π² ‖x‖² / b_i), x in degrees, evaluated on the
// (2r+1)² pixel square and normalised to sum 1. Each Gaussian term is
// separable, so the square kernel is exactly Σ_i k_i ⊗ k_i with
// k_i = g_i · √(a_i √(π/b_i) / total).
SeparableSum csfFilter(double ppd, int radius, std::initializer_list<std::array<double, 2>> terms) {
    std::vector<std::vector<double>> g;
    std::vector<double> weight;
    double total = 0;
    for (auto [a, b] : terms) {
        std::vector<double> k(std::size_t(2 * radius + 1));
        double sum = 0;
        for (int i = -radius; i <= radius; ++i) {
            double x = i / ppd;
            k[std::size_t(i + radius)] = std::exp(-pi * pi * x * x / b);
            sum += k[std::size_t(i + radius)];
        }
        double w = a * std::sqrt(pi / b);
        total += w * sum * sum;
        g.push_back(std::move(k));
        weight.push_back(w);
    }
    SeparableSum out;
    for (std::size_t t = 0; t < g.size(); ++t) {
        double s = std::sqrt(weight[t] / total);
        Kernel k;
        for (double v : g[t]) k.push_back(float(v * s));
        // Taps below 1e-9 change no float result (the kernel sums to about 1):
        // the achromatic and red-green Gaussians (σ ≈ 1 px at 67 ppd) keep 13
        // of their 21 taps.
        while (k.size() > 1 && k.front() < 1e-9f) k.erase(k.begin()), k.pop_back();
        out.push_back(std::move(k));
    }
    return out;
}

// Edge and point detectors (FLIP, feature pipeline): the first and second
// derivative of a Gaussian of σ = w/2 · ppd pixels along one axis, positive
// weights normalised to sum 1 and negative ones to −1, times the Gaussian
// normalised to sum 1 along the other axis (the 2D normalisation of the
// reference factors this way).
struct FeatureKernels {
    Kernel smooth, edge, point;
};

FeatureKernels featureKernels(double ppd) {
    double sd = 0.5 * kFeatureW * ppd;
    int r = int(std::ceil(3.0 * sd));
    std::vector<double> g, e, p;
    for (int i = -r; i <= r; ++i) {
        double gi = std::exp(-double(i) * i / (2.0 * sd * sd));
        g.push_back(gi);
        e.push_back(-i * gi);
        p.push_back((double(i) * i / (sd * sd) - 1.0) * gi);
    }
    auto normalised = [](const std::vector<double>& k) {
        double pos = 0, neg = 0;
        for (double v : k) (v > 0 ? pos : neg) += v;
        Kernel out;
        for (double v : k) out.push_back(float(v > 0 ? v / pos : (v < 0 ? v / -neg : 0.0)));
        return out;
    };
    return {normalised(g), normalised(e), normalised(p)};
}

struct FlipKernels {
    SeparableSum achromatic, redGreen, blueYellow;
    FeatureKernels features;
};

FlipKernels flipKernels(double ppd) {
    // CSF parameters of the FLIP paper; A and RG are single Gaussians (a2 = 0).
    // One radius for all channels, from the widest term: 3 σ of b = 0.04.
    int r = int(std::ceil(3.0 * std::sqrt(0.04 / (2.0 * pi * pi)) * ppd));
    return {csfFilter(ppd, r, {{1.0, 0.0047}}), csfFilter(ppd, r, {{1.0, 0.0053}}),
            csfFilter(ppd, r, {{34.1, 0.04}, {13.5, 0.025}}), featureKernels(ppd)};
}

// Runs f(y0, y1) over bands of rows [0, rows) on the hardware's threads.
template <class F>
void parallelRows(int rows, const F& f) {
    int n = std::clamp(int(std::thread::hardware_concurrency()), 1, 64);
    n = std::min(n, std::max(1, rows / 16));
    std::vector<std::thread> workers;
    for (int i = 1; i < n; ++i) workers.emplace_back([&f, i, n, rows] { f(rows * i / n, rows * (i + 1) / n); });
    f(0, rows / n);
    for (auto& t : workers) t.join();
}

// How a 1D pass writes dst: overwrite, add to it, or overwrite with a
// zero-sum kernel evaluated as Σ_t k_t (s_t − s_centre), which is the same sum
// in exact arithmetic but exactly 0 on a constant signal (the feature
// detectors' response is raised to q_f = 0.5, which would turn a float
// residual of 1e-8 into 1e-4).
enum class Write { overwrite, accumulate, zeroSum };

// One tap of a 1D pass over a row: d (+)= k · (s − c), c = the centre row for
// zero-sum kernels. The first tap of a non-accumulating pass overwrites, so
// no pass clears its output first.
inline void tap(float* d, const float* s, const float* c, float k, int w, bool first, Write mode) {
    if (mode == Write::zeroSum) {
        if (first)
            for (int x = 0; x < w; ++x) d[x] = k * (s[x] - c[x]);
        else
            for (int x = 0; x < w; ++x) d[x] += k * (s[x] - c[x]);
    } else if (first) {
        for (int x = 0; x < w; ++x) d[x] = k * s[x];
    } else {
        for (int x = 0; x < w; ++x) d[x] += k * s[x];
    }
}

// dst = src ⋆ k along x, edge pixels repeated (clamp-to-edge, as the
// reference implementation's BORDER_REPLICATE).
void filterRows(const Plane& src, Plane& dst, int w, int h, const Kernel& k, Write mode) {
    int r = int(k.size() / 2);
    parallelRows(h, [&](int y0, int y1) {
        std::vector<float> pad(std::size_t(w + 2 * r));
        for (int y = y0; y < y1; ++y) {
            const float* s = &src[std::size_t(y) * std::size_t(w)];
            for (int i = 0; i < w + 2 * r; ++i) pad[std::size_t(i)] = s[std::clamp(i - r, 0, w - 1)];
            float* d = &dst[std::size_t(y) * std::size_t(w)];
            for (std::size_t t = 0; t < k.size(); ++t)
                tap(d, &pad[t], &pad[std::size_t(r)], k[t], w, t == 0 && mode != Write::accumulate, mode);
        }
    });
}

// dst = src ⋆ k along y, clamp-to-edge.
void filterCols(const Plane& src, Plane& dst, int w, int h, const Kernel& k, Write mode) {
    int r = int(k.size() / 2);
    parallelRows(h, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            float* d = &dst[std::size_t(y) * std::size_t(w)];
            const float* c = &src[std::size_t(y) * std::size_t(w)];
            for (std::size_t t = 0; t < k.size(); ++t) {
                const float* s = &src[std::size_t(std::clamp(y + int(t) - r, 0, h - 1)) * std::size_t(w)];
                tap(d, s, c, k[t], w, t == 0 && mode != Write::accumulate, mode);
            }
        }
    });
}

void filter2D(const Plane& src, Plane& dst, Plane& tmp, int w, int h, const SeparableSum& f) {
    for (std::size_t t = 0; t < f.size(); ++t) {
        filterRows(src, tmp, w, h, f[t], Write::overwrite);
        filterCols(tmp, dst, w, h, f[t], t > 0 ? Write::accumulate : Write::overwrite);
    }
}

// ---------------------------------------------------------------------------
// LDR-FLIP.

// What the error needs of one image: Hunt-adjusted L*a*b* of the
// CSF-filtered image, and the edge and point feature magnitudes.
struct Perceived {
    Plane L, a, b, edge, point;
};

// All planes of one evaluation, allocated once per call and reused by every
// exposure of HDR-FLIP (fresh allocations cost more than the filters: page
// faults and clearing).
struct Workspace {
    int w, h;
    Plane yy, cx, cz, lum, tmp, fy, fx, fz;
    Perceived test, ref;
    Plane error;
    Workspace(int width, int height) : w(width), h(height) {
        std::size_t n = std::size_t(w) * std::size_t(h);
        for (Plane* p : {&yy, &cx, &cz, &lum, &tmp, &fy, &fx, &fz, &error}) p->resize(n);
        for (Perceived* q : {&test, &ref})
            for (Plane* p : {&q->L, &q->a, &q->b, &q->edge, &q->point}) p->resize(n);
    }
};

// Runs f(i) for every pixel index, over row bands.
template <class F>
void forEachPixel(int w, int h, const F& f) {
    parallelRows(h, [&](int y0, int y1) {
        for (std::size_t i = std::size_t(y0) * std::size_t(w); i < std::size_t(y1) * std::size_t(w); ++i) f(i);
    });
}

// `rgb`: interleaved linear RGB in [0, 1], finite.
void perceive(const std::vector<float>& rgb, const FlipKernels& k, Workspace& ws, Perceived& p) {
    int w = ws.w, h = ws.h;
    // Linear RGB -> YyCxCz (FLIP, colour pipeline): the linearised L*a*b*, whose
    // opponent channels the CSF filters act on.
    forEachPixel(w, h, [&](std::size_t i) {
        auto xyz = mul(kRgbToXyz, rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
        double x = xyz[0] / kWhite[0], y = xyz[1] / kWhite[1], z = xyz[2] / kWhite[2];
        ws.yy[i] = float(116.0 * y - 16.0);
        ws.cx[i] = float(500.0 * (x - y));
        ws.cz[i] = float(200.0 * (y - z));
        ws.lum[i] = float(y);  // (Yy + 16) / 116: the feature pipeline's normalised achromatic channel
    });

    filter2D(ws.yy, ws.fy, ws.tmp, w, h, k.achromatic);
    filter2D(ws.cx, ws.fx, ws.tmp, w, h, k.redGreen);
    filter2D(ws.cz, ws.fz, ws.tmp, w, h, k.blueYellow);
    // Back to linear RGB, clamped to the unit cube, then Hunt-adjusted L*a*b*.
    forEachPixel(w, h, [&](std::size_t i) {
        double y = (ws.fy[i] + 16.0) / 116.0;
        double x = y + ws.fx[i] / 500.0, z = y - ws.fz[i] / 200.0;
        auto c = mul(xyzToRgb(), x * kWhite[0], y * kWhite[1], z * kWhite[2]);
        auto lab = huntLab(c[0], c[1], c[2]);
        p.L[i] = float(lab[0]), p.a[i] = float(lab[1]), p.b[i] = float(lab[2]);
    });

    // Features on the unfiltered normalised luminance: x derivatives smoothed
    // along y, y derivatives smoothed along x (yy and cx are free again).
    const FeatureKernels& f = k.features;
    Plane &ex = ws.yy, &px = ws.cx;
    filterCols(ws.lum, ws.tmp, w, h, f.smooth, Write::overwrite);
    filterRows(ws.tmp, ex, w, h, f.edge, Write::zeroSum);
    filterRows(ws.tmp, px, w, h, f.point, Write::zeroSum);
    filterRows(ws.lum, ws.tmp, w, h, f.smooth, Write::overwrite);
    filterCols(ws.tmp, p.edge, w, h, f.edge, Write::zeroSum);
    filterCols(ws.tmp, p.point, w, h, f.point, Write::zeroSum);
    forEachPixel(w, h, [&](std::size_t i) {
        p.edge[i] = std::sqrt(ex[i] * ex[i] + p.edge[i] * p.edge[i]);
        p.point[i] = std::sqrt(px[i] * px[i] + p.point[i] * p.point[i]);
    });
}

// Per-pixel LDR-FLIP of two sanitised images (interleaved RGB in [0, 1])
// into ws.error.
void flipMap(const std::vector<float>& test, const std::vector<float>& ref, const FlipKernels& k, Workspace& ws) {
    perceive(test, k, ws, ws.test);
    perceive(ref, k, ws, ws.ref);
    const Perceived &t = ws.test, &r = ws.ref;
    forEachPixel(ws.w, ws.h, [&](std::size_t i) {
        // Colour: HyAB^q_c, redistributed (FLIP, colour metric).
        float h = float(hyab({r.L[i], r.a[i], r.b[i]}, {t.L[i], t.a[i], t.b[i]}));
        double dc = redistribute(std::pow(h, float(kQc)));
        // Features: (max(|Δ‖edge‖|, |Δ‖point‖|) / √2)^q_f (FLIP, feature metric).
        double df = std::max(std::abs(double(r.edge[i]) - t.edge[i]), std::abs(double(r.point[i]) - t.point[i]));
        df = std::sqrt(df / std::numbers::sqrt2);  // q_f = 0.5
        // ΔE = ΔE_c^(1 − ΔE_f) (FLIP, final error).
        ws.error[i] = std::pow(float(dc), float(1.0 - df));
    });
}

// ---------------------------------------------------------------------------
// Inputs, masks, results.

struct Inputs {
    int w = 0, h = 0;
    std::vector<float> test, ref;  // interleaved RGB, finite
    std::vector<std::uint8_t> use;     // 1 = in the mean (masked and finite)
    std::vector<std::uint8_t> finite;  // 1 = finite RGB in both images
    std::size_t nonFinite = 0;
};

bool finiteRgb(const FloatImage& img, std::size_t i) {
    const float* p = &img.data[i * std::size_t(img.channels)];
    return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

Inputs sanitise(const FloatImage& test, const FloatImage& ref, const std::vector<std::uint8_t>& mask,
                const FlipOptions& options) {
    if (test.width != ref.width || test.height != ref.height)
        throw std::runtime_error("FLIP: images differ in size: " + std::to_string(test.width) + "x" +
                                 std::to_string(test.height) + " vs " + std::to_string(ref.width) + "x" +
                                 std::to_string(ref.height));
    for (const FloatImage* img : {&test, &ref})
        if ((img->channels != 3 && img->channels != 4) ||
            img->data.size() != std::size_t(img->width) * std::size_t(img->height) * std::size_t(img->channels))
            throw std::runtime_error("FLIP: images must be RGB or RGBA with width·height·channels floats (got " +
                                     std::to_string(img->channels) + " channels)");
    std::size_t n = std::size_t(ref.width) * std::size_t(ref.height);
    if (!mask.empty() && mask.size() != n)
        throw std::runtime_error("FLIP: the mask has " + std::to_string(mask.size()) + " entries for " +
                                 std::to_string(n) + " pixels");
    // Below 1 pixel per degree the feature detectors' Gaussian (σ = 0.041 ·
    // ppd pixels) underflows to a single tap.
    if (!(options.pixelsPerDegree >= 1.0) || !std::isfinite(options.pixelsPerDegree))
        throw std::runtime_error("FLIP: pixelsPerDegree must be finite and at least 1 (got " +
                                 std::to_string(options.pixelsPerDegree) + ")");
    Inputs in;
    in.w = ref.width, in.h = ref.height;
    in.test.resize(3 * n), in.ref.resize(3 * n), in.use.resize(n), in.finite.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        bool ft = finiteRgb(test, i), fr = finiteRgb(ref, i);
        bool masked = mask.empty() || mask[i];
        for (std::size_t c = 0; c < 3; ++c) {
            float t = test.data[i * std::size_t(test.channels) + c], r = ref.data[i * std::size_t(ref.channels) + c];
            // A non-finite pixel gets the same value in both images (the
            // reference's if finite, else the test's, else black), so that
            // its neighbours see no difference there.
            if (!(ft && fr)) t = r = fr ? r : (ft ? t : 0.0f);
            in.test[3 * i + c] = t, in.ref[3 * i + c] = r;
        }
        in.finite[i] = ft && fr;
        in.use[i] = masked && ft && fr;
        in.nonFinite += masked && !(ft && fr);
    }
    return in;
}

FlipResult finish(const Inputs& in, Plane e) {
    FlipResult res;
    res.errorMap.width = in.w, res.errorMap.height = in.h, res.errorMap.channels = 1;
    double sum = 0;
    for (std::size_t i = 0; i < e.size(); ++i) {
        if (in.use[i]) {
            sum += e[i];
            ++res.pixels;
        }
    }
    // Pixels non-finite in an input show no error (they are counted instead).
    for (std::size_t i = 0; i < e.size(); ++i)
        if (!in.finite[i]) e[i] = 0.0f;
    res.errorMap.data = std::move(e);
    res.nonFinitePixels = in.nonFinite;
    res.mean = res.pixels ? sum / double(res.pixels) : 0.0;
    return res;
}

// ACES filmic tonemapper as HDR-FLIP uses it: Narkowicz's fit
// x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14) with the fit's 0.6 pre-exposure
// folded into the coefficients, clamped to [0, 1] (HDR-FLIP paper).
constexpr double kAces[6] = {0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14};

double aces(double x) {
    if (x > 1e10) return 1.0;  // the curve passes 1 at x ≈ 12; avoids ∞/∞ for huge radiance
    double y = (kAces[0] * x * x + kAces[1] * x + kAces[2]) / (kAces[3] * x * x + kAces[4] * x + kAces[5]);
    return std::clamp(y, 0.0, 1.0);
}

// The x with aces(x) = t (HDR-FLIP, exposure range): the positive root of
// (k0 − k3 t) x² + (k1 − k4 t) x + (k2 − k5 t) = 0.
double acesInverse(double t) {
    double c0 = (kAces[1] - kAces[4] * t) / (kAces[0] - kAces[3] * t);
    double c1 = (kAces[2] - kAces[5] * t) / (kAces[0] - kAces[3] * t);
    return -0.5 * c0 + std::sqrt(0.25 * c0 * c0 - c1);
}

}  // namespace

FlipResult ldrFlip(const FloatImage& test, const FloatImage& ref, const FlipOptions& options,
                   const std::vector<std::uint8_t>& mask) {
    Inputs in = sanitise(test, ref, mask, options);
    for (auto* img : {&in.test, &in.ref})
        for (float& v : *img) v = std::clamp(v, 0.0f, 1.0f);
    Workspace ws(in.w, in.h);
    flipMap(in.test, in.ref, flipKernels(options.pixelsPerDegree), ws);
    return finish(in, std::move(ws.error));
}

FlipResult hdrFlip(const FloatImage& test, const FloatImage& ref, const FlipOptions& options,
                   const std::vector<std::uint8_t>& mask) {
    Inputs in = sanitise(test, ref, mask, options);
    for (auto* img : {&in.test, &in.ref})
        for (float& v : *img) v = std::max(v, 0.0f);

    // Exposure range (HDR-FLIP paper): the start exposure maps the
    // reference's largest luminance, the stop exposure its median, to the
    // tonemapped value t = 0.85.
    constexpr double t = 0.85;
    double start = 0, stop = 0;
    if (!options.startExposure || !options.stopExposure) {
        std::vector<double> lum, positive;
        for (std::size_t i = 0; i < in.use.size(); ++i)
            if (in.use[i]) {
                const float* p = &in.ref[3 * i];
                double y = luminance(p[0], p[1], p[2]);
                lum.push_back(y);
                if (y > 0) positive.push_back(y);
            }
        // The median as numpy's 50th percentile (mean of the two middle
        // values for an even count). With more than half the pixels black the
        // median is 0 and the stop exposure infinite: the median of the
        // non-black pixels is used instead (a documented deviation).
        auto median = [](std::vector<double> v) {
            std::size_t m = v.size() / 2;
            std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(m), v.end());
            double hi = v[m];
            if (v.size() % 2) return hi;
            return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(m)));
        };
        if (!positive.empty()) {
            double yMax = *std::max_element(positive.begin(), positive.end());
            double yMed = median(lum);
            if (yMed <= 0) yMed = median(positive);
            start = std::log2(acesInverse(t) / yMax);
            stop = std::log2(acesInverse(t) / yMed);
        }  // else a black reference: start = stop = 0, as the reference code
    }
    start = options.startExposure.value_or(start);
    stop = options.stopExposure.value_or(stop);
    if (!(start <= stop) || !std::isfinite(start) || !std::isfinite(stop))
        throw std::runtime_error("FLIP: the start exposure (" + std::to_string(start) +
                                 ") must be finite and not above the stop exposure (" + std::to_string(stop) + ")");
    // Number of exposures, as the HDR-FLIP paper: one per stop, at least 2.
    int count = std::max(2, int(std::ceil(stop - start)));

    FlipKernels k = flipKernels(options.pixelsPerDegree);
    Workspace ws(in.w, in.h);
    Plane worst(in.use.size(), 0.0f);
    std::vector<float> tt(in.test.size()), tr(in.ref.size());
    for (int i = 0; i < count; ++i) {
        double scale = std::exp2(start + i * (stop - start) / double(count - 1));
        forEachPixel(in.w, in.h, [&](std::size_t j) {
            for (std::size_t c = 3 * j; c < 3 * j + 3; ++c) {
                tt[c] = float(aces(scale * in.test[c]));
                tr[c] = float(aces(scale * in.ref[c]));
            }
        });
        flipMap(tt, tr, k, ws);
        forEachPixel(in.w, in.h, [&](std::size_t j) { worst[j] = std::max(worst[j], ws.error[j]); });
    }
    FlipResult res = finish(in, std::move(worst));
    res.startExposure = start, res.stopExposure = stop, res.exposures = count;
    return res;
}

// Magma-like ramp through nine control points approximating matplotlib's magma
// (Smith & van der Walt 2015, CC0), linear between them in display values.
FloatImage flipErrorColorMap(const FloatImage& errorMap) {
    static const float stops[9][3] = {{0.001f, 0.000f, 0.014f}, {0.114f, 0.065f, 0.277f}, {0.317f, 0.072f, 0.485f},
                                      {0.513f, 0.139f, 0.507f}, {0.716f, 0.215f, 0.475f}, {0.904f, 0.310f, 0.392f},
                                      {0.987f, 0.536f, 0.382f}, {0.997f, 0.765f, 0.527f}, {0.987f, 0.991f, 0.750f}};
    FloatImage out;
    out.width = errorMap.width, out.height = errorMap.height, out.channels = 4;
    std::size_t n = std::size_t(errorMap.width) * std::size_t(errorMap.height);
    out.data.resize(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
        double v = errorMap.data[i * std::size_t(errorMap.channels)];
        v = std::isfinite(v) ? std::clamp(v, 0.0, 1.0) * 8.0 : 0.0;
        int s = std::min(7, int(v));
        float f = float(v - s);
        for (int c = 0; c < 3; ++c) out.data[4 * i + std::size_t(c)] = stops[s][c] + f * (stops[s + 1][c] - stops[s][c]);
        out.data[4 * i + 3] = 1.0f;
    }
    return out;
}

}  // namespace rtgi
