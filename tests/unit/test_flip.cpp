// LDR-FLIP and HDR-FLIP (render/reference/flip.h) against oracles written
// here from the papers' definitions in double precision: a colour-only
// computation for constant images, the whole LDR-FLIP map by brute force with
// unseparated 2D kernels, the HDR exposure range from the ACES curve inverted
// by bisection, and invariants (identical images, masks, non-finite pixels,
// monotonicity).
#include "render/reference/flip.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

using namespace rtgi;

namespace {

using Rgb = std::array<double, 3>;
constexpr double kPi = std::numbers::pi;

// ---- Oracle: FLIP's colour pipeline in double (FLIP paper, colour pipeline). ----

// sRGB primaries, D65 (IEC 61966-2-1), and the inverse by Gauss-Jordan.
using M3 = std::array<Rgb, 3>;
const M3 kToXyz = {{{0.4123908, 0.3575843, 0.1804808}, {0.2126390, 0.7151687, 0.0721923}, {0.0193308, 0.1191948, 0.9505322}}};

M3 invert(M3 a) {
    M3 b = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    for (int c = 0; c < 3; ++c) {
        int p = c;
        for (int r = c + 1; r < 3; ++r)
            if (std::abs(a[r][c]) > std::abs(a[p][c])) p = r;
        std::swap(a[c], a[p]), std::swap(b[c], b[p]);
        double d = a[c][c];
        for (int k = 0; k < 3; ++k) a[c][k] /= d, b[c][k] /= d;
        for (int r = 0; r < 3; ++r)
            if (r != c) {
                double f = a[r][c];
                for (int k = 0; k < 3; ++k) a[r][k] -= f * a[c][k], b[r][k] -= f * b[c][k];
            }
    }
    return b;
}
Rgb mat(const M3& m, const Rgb& v) {
    return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}
Rgb white() { return mat(kToXyz, {1, 1, 1}); }

Rgb toYyCxCz(const Rgb& rgb) {
    Rgb xyz = mat(kToXyz, rgb), w = white();
    double x = xyz[0] / w[0], y = xyz[1] / w[1], z = xyz[2] / w[2];
    return {116 * y - 16, 500 * (x - y), 200 * (y - z)};
}
Rgb fromYyCxCz(const Rgb& o) {
    Rgb w = white();
    double y = (o[0] + 16) / 116;
    return mat(invert(kToXyz), {(y + o[1] / 500) * w[0], y * w[1], (y - o[2] / 200) * w[2]});
}
Rgb huntLab(Rgb rgb) {
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
    Rgb xyz = mat(kToXyz, rgb), w = white();
    auto f = [](double t) { return t > std::pow(6.0 / 29, 3) ? std::cbrt(t) : t * 841.0 / 108.0 + 4.0 / 29.0; };
    double fx = f(xyz[0] / w[0]), fy = f(xyz[1] / w[1]), fz = f(xyz[2] / w[2]);
    double L = 116 * fy - 16;
    return {L, L / 100 * 500 * (fx - fy), L / 100 * 200 * (fy - fz)};
}
double hyab(const Rgb& p, const Rgb& q) { return std::abs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]); }
double colourError(const Rgb& filteredTest, const Rgb& filteredRef) {
    double cmax = std::pow(hyab(huntLab({0, 1, 0}), huntLab({0, 0, 1})), 0.7);
    double e = std::pow(hyab(huntLab(filteredTest), huntLab(filteredRef)), 0.7);
    return e < 0.4 * cmax ? 0.95 / (0.4 * cmax) * e : 0.95 + 0.05 * (e - 0.4 * cmax) / (0.6 * cmax);
}

FloatImage fromRows(const std::vector<Rgb>& row, int h, int channels = 3) {
    FloatImage img;
    img.width = int(row.size()), img.height = h, img.channels = channels;
    for (int y = 0; y < h; ++y)
        for (const Rgb& c : row) {
            for (int k = 0; k < 3; ++k) img.data.push_back(float(c[std::size_t(k)]));
            if (channels == 4) img.data.push_back(1.0f);
        }
    return img;
}
FloatImage transposed(const FloatImage& img) {
    FloatImage t = img;
    t.width = img.height, t.height = img.width;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < img.channels; ++c)
                t.data[std::size_t((x * t.width + y) * img.channels + c)] = img.at(x, y, c);
    return t;
}
FloatImage constant(const Rgb& c, int w, int h) { return fromRows(std::vector<Rgb>(std::size_t(w), c), h); }

FloatImage randomImage(int w, int h, unsigned seed, float scale = 1.0f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, scale);
    FloatImage img;
    img.width = w, img.height = h, img.channels = 4;
    for (int i = 0; i < w * h; ++i) img.data.insert(img.data.end(), {u(rng), u(rng), u(rng), 1.0f});
    return img;
}

const FlipOptions kDefault{};
const double kPpd = kDefault.pixelsPerDegree;

}  // namespace

TEST_CASE("Flip: the default observer is the papers' 0.7 m wide 4K monitor at 0.7 m") {
    CHECK(kPpd == doctest::Approx(0.7 * 3840 / 0.7 * kPi / 180).epsilon(1e-12));  // 67.02 pixels per degree
}

TEST_CASE("Flip: identical images give exactly 0 everywhere") {
    FloatImage a = randomImage(37, 23, 1), hdr = randomImage(37, 23, 2, 40.0f);
    FlipResult l = ldrFlip(a, a), h = hdrFlip(hdr, hdr);
    CHECK(l.mean == 0.0);
    CHECK(h.mean == 0.0);
    CHECK(std::all_of(l.errorMap.data.begin(), l.errorMap.data.end(), [](float v) { return v == 0.0f; }));
    CHECK(std::all_of(h.errorMap.data.begin(), h.errorMap.data.end(), [](float v) { return v == 0.0f; }));
    CHECK(l.pixels == 37u * 23u);
    CHECK(l.errorMap.channels == 1);
}

TEST_CASE("Flip: constant images give the colour term alone, as the paper's formulas in double") {
    const Rgb pairs[][2] = {{{0, 0, 0}, {1, 1, 1}},        {{1, 0, 0}, {0, 1, 0}},       {{0.5, 0.5, 0.5}, {0.52, 0.52, 0.52}},
                            {{0.1, 0.1, 0.1}, {0.11, 0.11, 0.11}}, {{0, 1, 0}, {0, 0, 1}}, {{0.2, 0.4, 0.8}, {0.25, 0.4, 0.7}},
                            {{0.9, 0.9, 0.9}, {0.9, 0.9, 0.9}}};
    for (const auto& p : pairs) {
        const Rgb test = p[0], ref = p[1];
        CAPTURE(test);
        CAPTURE(ref);
        // No spatial structure: the CSF filters (normalised) return the
        // constant, and the feature detectors (zero-sum) return 0.
        double expected = colourError(fromYyCxCz(toYyCxCz(p[0])), fromYyCxCz(toYyCxCz(p[1])));
        FlipResult r = ldrFlip(constant(p[0], 24, 20), constant(p[1], 24, 20));
        CHECK(std::abs(r.mean - expected) < 1e-4);
        CHECK(*std::max_element(r.errorMap.data.begin(), r.errorMap.data.end()) - *std::min_element(r.errorMap.data.begin(), r.errorMap.data.end()) < 1e-5f);
    }
    // Green vs blue is the pair that defines c_max: ΔE_c = 1 exactly.
    CHECK(std::abs(ldrFlip(constant({0, 1, 0}, 8, 8), constant({0, 0, 1}, 8, 8)).mean - 1.0) < 1e-4);
}

TEST_CASE("Flip: inputs outside [0, 1] are clamped, RGBA is read as RGB") {
    FloatImage a = constant({1.7, -0.3, 0.5}, 16, 16), b = constant({1.0, 0.0, 0.5}, 16, 16);
    CHECK(ldrFlip(a, b).mean == 0.0);
    FloatImage t = randomImage(16, 16, 5), r = randomImage(16, 16, 6);
    FloatImage t3 = t, r3 = r;
    for (FloatImage* img : {&t3, &r3}) {
        std::vector<float> d;
        for (std::size_t i = 0; i < img->data.size(); i += 4) d.insert(d.end(), {img->data[i], img->data[i + 1], img->data[i + 2]});
        img->data = d, img->channels = 3;
    }
    CHECK(ldrFlip(t, r).mean == ldrFlip(t3, r3).mean);
}

TEST_CASE("Flip: a larger constant difference gives a larger error") {
    double previous = 0;
    for (double d : {0.01, 0.03, 0.1, 0.2, 0.4}) {
        double m = ldrFlip(constant({0.3 + d, 0.3 + d, 0.3 + d}, 16, 16), constant({0.3, 0.3, 0.3}, 16, 16)).mean;
        CAPTURE(d);
        CHECK(m > previous);
        previous = m;
    }
}

namespace {

// ---- Oracle: the whole LDR-FLIP map by brute force, 2D kernels as the paper
// defines them (no separation), clamp-to-edge, double precision. ----

// A (2r+1)² kernel, index (i + r)·n + (j + r) for offset (i, j) = (x, y).
struct Kernel2D {
    int r = 0;
    std::vector<double> k;
    double at(int i, int j) const { return k[std::size_t((i + r) * (2 * r + 1) + j + r)]; }
};

// CSF of one opponent channel (FLIP paper, spatial filtering):
// Σ a √(π/b) exp(−π² d² / b), d in degrees, on the square of radius
// ⌈3 √(0.04 / 2π²) ppd⌉, normalised to sum 1.
Kernel2D csfKernel(double ppd, double a1, double b1, double a2, double b2) {
    Kernel2D f;
    f.r = int(std::ceil(3 * std::sqrt(0.04 / (2 * kPi * kPi)) * ppd));
    double total = 0;
    for (int i = -f.r; i <= f.r; ++i)
        for (int j = -f.r; j <= f.r; ++j) {
            double d2 = (i * i + j * j) / (ppd * ppd);
            double s = a1 * std::sqrt(kPi / b1) * std::exp(-kPi * kPi * d2 / b1) +
                       (a2 > 0 ? a2 * std::sqrt(kPi / b2) * std::exp(-kPi * kPi * d2 / b2) : 0.0);
            f.k.push_back(s);
            total += s;
        }
    for (double& v : f.k) v /= total;
    return f;
}

// Edge (first) or point (second) derivative of a Gaussian along x times the
// Gaussian along y, σ = w/2 · ppd, w = 0.082; positive weights normalised to
// 1, negative ones to −1 (FLIP paper, feature pipeline).
Kernel2D detector(double ppd, bool point) {
    Kernel2D f;
    double sd = 0.5 * 0.082 * ppd, pos = 0, neg = 0;
    f.r = int(std::ceil(3 * sd));
    for (int i = -f.r; i <= f.r; ++i)
        for (int j = -f.r; j <= f.r; ++j) {
            double g = std::exp(-(i * i + j * j) / (2 * sd * sd)), v = point ? (i * i / (sd * sd) - 1) * g : -i * g;
            (v > 0 ? pos : neg) += v;
            f.k.push_back(v);
        }
    for (double& v : f.k) v = v > 0 ? v / pos : v / -neg;
    return f;
}

struct OracleMap {
    std::vector<double> colour, feature;  // ΔE_c, ΔE_f per pixel
    double flip(std::size_t i) const { return std::pow(colour[i], 1 - feature[i]); }
};

// `test`, `ref`: linear RGB in [0, 1].
OracleMap flipOracle(const FloatImage& test, const FloatImage& ref, double ppd) {
    const int w = ref.width, h = ref.height;
    const Kernel2D csf[3] = {csfKernel(ppd, 1, 0.0047, 0, 1), csfKernel(ppd, 1, 0.0053, 0, 1),
                             csfKernel(ppd, 34.1, 0.04, 13.5, 0.025)};
    const Kernel2D edgeK = detector(ppd, false), pointK = detector(ppd, true);
    auto opponent = [&](const FloatImage& img) {
        std::vector<Rgb> o;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) o.push_back(toYyCxCz({img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)}));
        return o;
    };
    const std::vector<Rgb> ot = opponent(test), orf = opponent(ref);
    auto px = [&](const std::vector<Rgb>& o, int x, int y) {
        return o[std::size_t(std::clamp(y, 0, h - 1) * w + std::clamp(x, 0, w - 1))];
    };
    auto filtered = [&](const std::vector<Rgb>& o, int x, int y) {
        Rgb f{};
        for (int c = 0; c < 3; ++c)
            for (int i = -csf[c].r; i <= csf[c].r; ++i)
                for (int j = -csf[c].r; j <= csf[c].r; ++j) f[std::size_t(c)] += csf[c].at(i, j) * px(o, x + i, y + j)[std::size_t(c)];
        return fromYyCxCz(f);
    };
    // ‖(K ⋆ Y, Kᵀ ⋆ Y)‖ on the normalised luminance (Yy + 16) / 116.
    auto feature = [&](const std::vector<Rgb>& o, const Kernel2D& k, int x, int y) {
        double gx = 0, gy = 0;
        for (int i = -k.r; i <= k.r; ++i)
            for (int j = -k.r; j <= k.r; ++j) {
                double yn = (px(o, x + i, y + j)[0] + 16) / 116;
                gx += k.at(i, j) * yn;
                gy += k.at(j, i) * yn;
            }
        return std::hypot(gx, gy);
    };
    OracleMap m;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            m.colour.push_back(colourError(filtered(ot, x, y), filtered(orf, x, y)));
            double d = std::max(std::abs(feature(orf, edgeK, x, y) - feature(ot, edgeK, x, y)),
                                std::abs(feature(orf, pointK, x, y) - feature(ot, pointK, x, y)));
            m.feature.push_back(std::sqrt(d / std::numbers::sqrt2));
        }
    return m;
}

// Largest |ldrFlip map − oracle map|.
double maxDifference(const FlipResult& f, const OracleMap& o) {
    double d = 0;
    for (std::size_t i = 0; i < o.colour.size(); ++i) d = std::max(d, std::abs(f.errorMap.data[i] - o.flip(i)));
    return d;
}

}  // namespace

TEST_CASE("Flip: the error map equals the paper's definition evaluated by brute force in double") {
    // Random images: structure everywhere, in both directions, up to the
    // borders. Tolerance: float planes; ΔE_f is a square root, so a float
    // residual of 1e-7 in the detectors is up to 3e-4 in ΔE_f where the
    // images nearly agree.
    for (unsigned seed : {1u, 2u}) {
        FloatImage t = randomImage(23, 19, 40 + seed), r = randomImage(23, 19, 50 + seed);
        // Blend the test towards the reference so that errors span the range.
        for (std::size_t i = 0; i < t.data.size(); ++i) t.data[i] = r.data[i] + 0.1f * seed * (t.data[i] - r.data[i]);
        FlipResult f = ldrFlip(t, r);
        OracleMap o = flipOracle(t, r, kPpd);
        CAPTURE(seed);
        CHECK(maxDifference(f, o) < 3e-4);  // measured 1e-5
        double mean = 0;
        for (std::size_t i = 0; i < o.colour.size(); ++i) mean += o.flip(i) / double(o.colour.size());
        CHECK(f.mean == doctest::Approx(mean).epsilon(1e-5));
    }
    // Saturated primaries next to each other: the chroma filters push the
    // filtered colours out of the RGB cube, where the clamp matters.
    // Test: 1-pixel red/green columns; reference: 3-pixel yellow/blue rows.
    FloatImage st = randomImage(21, 15, 71), sr = st;
    for (int y = 0; y < 15; ++y)
        for (int x = 0; x < 21; ++x)
            for (int c = 0; c < 3; ++c) {
                std::size_t i = std::size_t((y * 21 + x) * 4 + c);
                st.data[i] = float(x % 2 ? c == 0 : c == 1);
                sr.data[i] = float((y / 3) % 2 ? c < 2 : c == 2);
            }
    CHECK(maxDifference(ldrFlip(st, sr), flipOracle(st, sr, kPpd)) < 3e-4);
    // Another observer: 30 pixels per degree (kernel radii 5 and 4).
    FlipOptions o30;
    o30.pixelsPerDegree = 30;
    FloatImage t = randomImage(17, 13, 61), r = randomImage(17, 13, 62);
    CHECK(maxDifference(ldrFlip(t, r, o30), flipOracle(t, r, 30)) < 3e-4);
}

TEST_CASE("Flip: a shifted step edge equals the paper's formulas in double and adds a feature term") {
    // Vertical luminance edges (constant along y), the test's one pixel right
    // of the reference's: the whole map against ΔE = ΔE_c^(1 − ΔE_f) from the
    // oracles above. Blurred far below the CSF cut-off, the same shift gives a
    // smaller feature term ΔE_f (read back from the map as 1 − ln ΔE / ln ΔE_c).
    const int w = 96, h = 6;
    auto edge = [&](double at, double blurSigma, Rgb left = {0.1, 0.1, 0.1}, Rgb right = {0.7, 0.7, 0.7}) {
        std::vector<Rgb> row;
        for (int x = 0; x < w; ++x) {
            double s = blurSigma > 0 ? 0.5 * std::erfc(-(x - at) / (blurSigma * std::numbers::sqrt2)) : (x >= at ? 1.0 : 0.0);
            row.push_back({left[0] + s * (right[0] - left[0]), left[1] + s * (right[1] - left[1]), left[2] + s * (right[2] - left[2])});
        }
        return row;
    };
    struct Outcome {
        double maxFeature = 0, peak = 0;
    };
    auto evaluate = [&](const std::vector<Rgb>& rt, const std::vector<Rgb>& rr) {
        FloatImage ti = fromRows(rt, h), ri = fromRows(rr, h);
        FlipResult f = ldrFlip(ti, ri);
        OracleMap oracle = flipOracle(ti, ri, kPpd);
        CHECK(maxDifference(f, oracle) < 3e-4);  // tolerance as above; measured 8e-5
        // The same images transposed (constant along x): the vertical passes.
        FloatImage tt = transposed(ti), rt2 = transposed(ri);
        CHECK(maxDifference(ldrFlip(tt, rt2), flipOracle(tt, rt2, kPpd)) < 3e-4);
        Outcome o;
        for (std::size_t i = 0; i < oracle.colour.size(); ++i) {
            double e = f.errorMap.data[i], ec = oracle.colour[i];
            if (ec > 1e-3 && ec < 0.999) o.maxFeature = std::max(o.maxFeature, 1.0 - std::log(e) / std::log(ec));
            o.peak = std::max(o.peak, e);
        }
        return o;
    };
    Outcome sharp = evaluate(edge(48.5, 0), edge(47.5, 0));
    // σ = 12 px ≈ 0.18°, far wider than the achromatic CSF (≈1 px).
    Outcome blurred = evaluate(edge(48.5, 12), edge(47.5, 12));
    // Chromatic edges exercise the red-green and blue-yellow filters
    // (blue-yellow: the sum of two Gaussians).
    for (double blur : {0.0, 3.0}) {
        evaluate(edge(48.5, blur, {0.2, 0.2, 0.7}, {0.6, 0.6, 0.1}), edge(47.5, blur, {0.2, 0.2, 0.7}, {0.6, 0.6, 0.1}));
        evaluate(edge(48.5, blur, {0.6, 0.1, 0.2}, {0.1, 0.35, 0.2}), edge(46.5, blur, {0.6, 0.1, 0.2}, {0.1, 0.35, 0.2}));
    }
    CHECK(sharp.maxFeature > 0.2);
    CHECK(blurred.maxFeature < 0.5 * sharp.maxFeature);
    CHECK(blurred.peak < sharp.peak);
    // Far from the edge the images agree: exactly no error there.
    FlipResult f = ldrFlip(fromRows(edge(48.5, 0), h), fromRows(edge(47.5, 0), h));
    CHECK(f.errorMap.data[0] == 0.0f);
}

namespace {
// Narkowicz's ACES fit with its 0.6 pre-exposure, as HDR-FLIP uses it.
double acesOracle(double x) {
    double y = 0.6 * x;
    return std::clamp(y * (2.51 * y + 0.03) / (y * (2.43 * y + 0.59) + 0.14), 0.0, 1.0);
}
// acesOracle(x) = t by bisection (the curve is increasing on [0, 12]).
double acesSolve(double t) {
    double lo = 0, hi = 12;
    for (int i = 0; i < 200; ++i) (acesOracle(0.5 * (lo + hi)) < t ? lo : hi) = 0.5 * (lo + hi);
    return 0.5 * (lo + hi);
}
}  // namespace

TEST_CASE("hdrFlip: the exposure range follows HDR-FLIP's formulas from the reference's luminance") {
    // Grey pixels: luminance = the value. 10 values, median = mean of the
    // 5th and 6th = (0.5 + 0.6) / 2, maximum 100.
    std::vector<Rgb> row;
    for (double v : {0.1, 0.9, 0.2, 100.0, 0.3, 0.6, 0.4, 0.8, 0.5, 0.7}) row.push_back({v, v, v});
    FloatImage ref = fromRows(row, 1), test = ref;
    test.data[0] = 0.3f;
    FlipResult r = hdrFlip(test, ref);
    double x = acesSolve(0.85);
    double start = std::log2(x / 100.0), stop = std::log2(x / 0.55);
    CHECK(r.startExposure == doctest::Approx(start).epsilon(1e-6));
    CHECK(r.stopExposure == doctest::Approx(stop).epsilon(1e-6));
    CHECK(r.exposures == std::max(2, int(std::ceil(stop - start))));  // ceil(7.5) = 8
    CHECK(r.exposures == 8);

    // Coloured pixels: Rec. 709 luminance; odd count, median = middle value.
    std::vector<Rgb> colours = {{1, 0, 0}, {0, 2, 0}, {0, 0, 4}};  // Y = 0.2126, 1.4304, 0.2888
    FlipResult c = hdrFlip(fromRows(colours, 1), fromRows(colours, 1));
    CHECK(c.startExposure == doctest::Approx(std::log2(x / 1.4304)).epsilon(1e-6));
    CHECK(c.stopExposure == doctest::Approx(std::log2(x / 0.2888)).epsilon(1e-6));
    CHECK(c.exposures == 3);  // stop − start = log2(1.4304 / 0.2888) = 2.31
}

TEST_CASE("hdrFlip with one exposure equals LDR-FLIP of the exposed, tonemapped images") {
    FloatImage t = randomImage(40, 30, 11, 8.0f), r = randomImage(40, 30, 12, 8.0f);
    for (double e : {-2.0, 0.0, 1.5}) {
        FlipOptions o;
        o.startExposure = o.stopExposure = e;
        FlipResult h = hdrFlip(t, r, o);
        FloatImage tt = t, rr = r;
        for (FloatImage* img : {&tt, &rr})
            for (std::size_t i = 0; i < img->data.size(); ++i)
                if (i % 4 != 3) img->data[i] = float(acesOracle(std::exp2(e) * img->data[i]));
        FlipResult l = ldrFlip(tt, rr);
        CAPTURE(e);
        CHECK(h.exposures == 2);
        CHECK(h.mean == doctest::Approx(l.mean).epsilon(1e-5));
        double maxDiff = 0;
        for (std::size_t i = 0; i < l.errorMap.data.size(); ++i)
            maxDiff = std::max(maxDiff, double(std::abs(h.errorMap.data[i] - l.errorMap.data[i])));
        CHECK(maxDiff < 1e-4);
    }
    // HDR-FLIP is the per-pixel maximum over exposures: never below one of them.
    FlipOptions wide;
    wide.startExposure = -2.0, wide.stopExposure = 1.5;
    FlipResult all = hdrFlip(t, r, wide);
    FlipOptions one;
    one.startExposure = one.stopExposure = 1.5;
    FlipResult last = hdrFlip(t, r, one);
    for (std::size_t i = 0; i < all.errorMap.data.size(); ++i) CHECK(all.errorMap.data[i] >= last.errorMap.data[i] - 1e-6f);
}

TEST_CASE("Flip: the masked mean is the mean of the error map over the mask") {
    FloatImage t = randomImage(33, 17, 21), r = randomImage(33, 17, 22);
    std::mt19937 rng(3);
    std::vector<std::uint8_t> mask(33 * 17);
    for (auto& m : mask) m = std::uint8_t(rng() % 3 == 0);
    for (bool hdr : {false, true}) {
        FlipResult all = hdr ? hdrFlip(t, r) : ldrFlip(t, r);
        FlipResult masked = hdr ? hdrFlip(t, r, {}, mask) : ldrFlip(t, r, {}, mask);
        double sum = 0;
        std::size_t n = 0;
        for (std::size_t i = 0; i < mask.size(); ++i)
            if (mask[i]) sum += masked.errorMap.data[i], ++n;
        CHECK(masked.pixels == n);
        CHECK(masked.mean == doctest::Approx(sum / double(n)).epsilon(1e-12));
        if (!hdr) CHECK(masked.errorMap.data == all.errorMap.data);  // the mask selects, it does not change the map
        CHECK(masked.mean != all.mean);
    }
}

TEST_CASE("Flip: NaN/Inf pixels are left out, counted, and do not spread") {
    FloatImage t = randomImage(30, 20, 31), r = randomImage(30, 20, 32);
    std::size_t nanAt = 5 * 30 + 7, infAt = 12 * 30 + 20;
    FloatImage tb = t, rb = r;
    tb.data[4 * nanAt + 1] = std::numeric_limits<float>::quiet_NaN();
    rb.data[4 * infAt + 2] = std::numeric_limits<float>::infinity();
    // The documented replacement: the reference's value in both where the
    // reference is finite, else the test's.
    FloatImage te = t, re = r;
    for (int c = 0; c < 3; ++c) {
        te.data[4 * nanAt + std::size_t(c)] = r.data[4 * nanAt + std::size_t(c)];
        re.data[4 * infAt + std::size_t(c)] = t.data[4 * infAt + std::size_t(c)];
    }
    // The equivalent finite pair, with the two pixels masked out so that
    // HDR-FLIP's exposure range comes from the same pixels.
    std::vector<std::uint8_t> mask(30 * 20, 1);
    mask[nanAt] = mask[infAt] = 0;
    for (bool hdr : {false, true}) {
        CAPTURE(hdr);
        FlipResult bad = hdr ? hdrFlip(tb, rb) : ldrFlip(tb, rb);
        FlipResult same = hdr ? hdrFlip(te, re, {}, mask) : ldrFlip(te, re, {}, mask);
        CHECK(bad.nonFinitePixels == 2);
        CHECK(bad.pixels == 30u * 20u - 2u);
        CHECK(std::isfinite(bad.mean));
        CHECK(std::all_of(bad.errorMap.data.begin(), bad.errorMap.data.end(), [](float v) { return std::isfinite(v); }));
        CHECK(bad.errorMap.data[nanAt] == 0.0f);
        CHECK(bad.errorMap.data[infAt] == 0.0f);
        double sum = 0;
        for (std::size_t i = 0; i < same.errorMap.data.size(); ++i) {
            if (i == nanAt || i == infAt) continue;
            CHECK(bad.errorMap.data[i] == same.errorMap.data[i]);
            sum += same.errorMap.data[i];
        }
        CHECK(bad.mean == doctest::Approx(sum / double(bad.pixels)).epsilon(1e-12));
    }
}

TEST_CASE("Flip: bad input is rejected with a message") {
    FloatImage a = randomImage(8, 8, 1), b = randomImage(8, 9, 2);
    CHECK_THROWS_AS(ldrFlip(a, b), std::runtime_error);
    CHECK_THROWS_AS(ldrFlip(a, a, {}, std::vector<std::uint8_t>(3, 1)), std::runtime_error);
    FlipOptions o;
    o.startExposure = 2.0, o.stopExposure = 1.0;
    CHECK_THROWS_AS(hdrFlip(a, a, o), std::runtime_error);
    o = {};
    o.pixelsPerDegree = 0.5;
    CHECK_THROWS_AS(ldrFlip(a, a, o), std::runtime_error);
    o.pixelsPerDegree = 1.0;  // the smallest accepted observer still gives finite errors
    FlipResult r = ldrFlip(a, randomImage(8, 8, 3), o);
    CHECK(std::isfinite(r.mean));
    CHECK(r.mean > 0.0);
}

TEST_CASE("flipErrorColorMap: dark to bright, increasing luminance, opaque") {
    FloatImage e;
    e.width = 101, e.height = 1, e.channels = 1;
    for (int i = 0; i <= 100; ++i) e.data.push_back(float(i) / 100.0f);
    FloatImage c = flipErrorColorMap(e);
    REQUIRE(c.channels == 4);
    auto lum = [&](int i) { return 0.2126 * c.data[std::size_t(4 * i)] + 0.7152 * c.data[std::size_t(4 * i + 1)] + 0.0722 * c.data[std::size_t(4 * i + 2)]; };
    CHECK(lum(0) < 0.01);
    CHECK(lum(100) > 0.9);
    for (int i = 1; i <= 100; ++i) CHECK(lum(i) > lum(i - 1));
    for (int i = 0; i <= 100; ++i) CHECK(c.data[std::size_t(4 * i + 3)] == 1.0f);
}
