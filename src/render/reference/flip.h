#pragma once
// FLIP, the perceptual difference evaluator of Andersson et al., "FLIP: A
// Difference Evaluator for Alternating Images" (HPG 2020; LDR-FLIP), and its
// HDR extension, Andersson et al., "Visualizing Errors in Rendered High
// Dynamic Range Images" (Eurographics 2021; HDR-FLIP), on the CPU. The
// algorithm, constants and measured cost are in docs/flip.md.
#include "gl/image_io.h"

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <optional>
#include <vector>

namespace rtgi {

struct FlipOptions {
    // Observer: pixels per degree of visual angle. The papers' default is a
    // 0.7 m wide 3840-pixel monitor seen from 0.7 m: 3840 · π / 180 ≈ 67.02.
    // At least 1.
    double pixelsPerDegree = 3840.0 * std::numbers::pi / 180.0;
    // HDR-FLIP only: the exposure range in stops (the images are scaled by
    // 2^exposure before tonemapping). Unset: computed from the reference as
    // HDR-FLIP does (docs/flip.md, "Exposure range").
    std::optional<double> startExposure, stopExposure;
};

struct FlipResult {
    double mean = 0;               // mean of errorMap over the mask's pixels finite in both images
    FloatImage errorMap;           // 1 channel, per-pixel FLIP in [0, 1]; 0 at non-finite pixels
    std::size_t pixels = 0;        // pixels in the mean
    std::size_t nonFinitePixels = 0;  // mask pixels left out: NaN or ±Inf in an RGB channel of either image
    double startExposure = 0, stopExposure = 0;  // HDR only
    int exposures = 0;                            // HDR only: LDR-FLIP evaluations, ≥ 2
};

// LDR-FLIP. `test` and `ref`: linear RGB display values (channels 3 or 4, the
// 4th ignored) of the same size; values outside [0, 1] are clamped to it. The
// paper's inputs are sRGB-encoded; it decodes them to linear RGB with the sRGB
// transfer function as its first step, so passing the decoded values here is
// the same metric (for an 8-bit sRGB PNG: decode, then call ldrFlip). `mask`:
// w·h bytes, non-zero = pixel in the mean (empty = every pixel); the error map
// covers every pixel. A pixel with a NaN or ±Inf in either image is left out
// of the mean and counted; before filtering it is given the same finite value
// in both images (the reference's where finite, else black), so it adds no
// difference to its neighbours and no NaN spreads. Throws std::runtime_error
// on a size, channel or mask mismatch, or pixelsPerDegree < 1.
FlipResult ldrFlip(const FloatImage& test, const FloatImage& ref, const FlipOptions& options = {},
                   const std::vector<std::uint8_t>& mask = {});

// HDR-FLIP. `test` and `ref`: linear HDR radiance (negative values are taken
// as 0). For each exposure e of `exposures` evenly spaced from start to stop,
// both images are scaled by 2^e, tonemapped with the ACES filmic curve and
// compared with LDR-FLIP; the error map is the per-pixel maximum. Masks and
// non-finite pixels as ldrFlip; the automatic exposure range uses the
// reference's luminance over the mask's finite pixels. Throws
// std::runtime_error on a size mismatch or start > stop.
FlipResult hdrFlip(const FloatImage& test, const FloatImage& ref, const FlipOptions& options = {},
                   const std::vector<std::uint8_t>& mask = {});

// The error map (channel 0, [0, 1]) as an RGBA image through a magma-like
// ramp (black → purple → red → orange → pale yellow), the papers' colour map.
// The colours are display (sRGB-encoded) values: write them with
// writePng(..., encodeSrgb = false).
FloatImage flipErrorColorMap(const FloatImage& errorMap);

}  // namespace rtgi
