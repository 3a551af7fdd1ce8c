#pragma once
// Error metrics between a tested image and a reference (SPEC 7.2), on the
// CPU in double precision: RMSE, MAE, PSNR, relative RMSE for HDR radiance,
// SSIM on luminance (11×11 Gaussian window, σ = 1.5, Wang et al. 2004), and
// an error heat map with a colour bar.
#include "gl/image_io.h"

#include <cstdint>
#include <vector>

namespace rtgi {

struct ErrorMetrics {
    double rmse = 0, mae = 0, bias = 0;  // over masked pixels and compared channels; bias = mean(test − ref)
    double psnr = 0;                     // 10·log10(peak² / MSE); +inf for identical images
    double relRmse = 0;                  // sqrt(mean((t − r)² / (r² + 0.01²))): HDR radiance
    double ssim = 0;                     // mean SSIM of luminance over all pixels
    std::size_t pixels = 0;     // pixels in the sums (masked, finite in both images)
    std::size_t nanPixels = 0;  // masked pixels left out: a NaN in a compared channel of either image
    std::size_t infPixels = 0;  // masked pixels left out: ±Inf (and no NaN) in either image
};

// Luminance (Rec. 709) of pixel i, or channel 0 for single-channel data.
double pixelLuminance(const FloatImage& img, std::size_t i, int channels);

// `channels`: 1 compares channel 0 (AO), 3 compares rgb. `mask` (empty =
// every pixel) selects pixels for RMSE/MAE/PSNR/relative RMSE; SSIM always
// uses the whole image. Pixels with NaN/Inf in either image are left out of
// the sums and counted in nanPixels / infPixels (SSIM sets their luminance to
// 0 in both images). `peak`: signal peak of PSNR and the dynamic range L
// of SSIM's constants (1 for AO / LDR images).
ErrorMetrics compareImages(const FloatImage& test, const FloatImage& ref, int channels, double peak,
                           const std::vector<std::uint8_t>& mask = {});
double ssimLuminance(const FloatImage& a, const FloatImage& b, int channels, double dynamicRange);

// Pixels away from depth discontinuities: 1 where the pixel is not sky and
// every pixel of its 3×3 neighbourhood is neither sky nor differs from it in
// linear depth by more than `relativeJump` of the centre depth. `depth`:
// linear view depth in channel 0 (0 = sky). The AO error splits into this
// interior and the edge band, where half-resolution AO, the upsample and the
// depth buffer's missing thickness dominate (docs/ao.md).
std::vector<std::uint8_t> depthInteriorMask(const FloatImage& depth, double relativeJump);

// |luminance(test) − luminance(ref)| mapped from 0 (black) to `maxError`
// (yellow, larger errors saturate) through a perceptually ordered ramp, with a colour bar and its
// two end values printed on the right. Returns an RGBA image in [0,1].
FloatImage errorHeatmap(const FloatImage& test, const FloatImage& ref, int channels, double maxError);
// Quantile q in [0,1] of the per-pixel |Δ luminance| (q = 1: the largest).
// The heat maps use q = 0.99 so that a few fireflies do not darken the rest.
double errorQuantile(const FloatImage& test, const FloatImage& ref, int channels, double q);

// Root mean square of a reference's per-pixel standard error over the masked
// pixels (empty = all) and the first `channels` channels: the reference's own
// noise on the scale of the RMSE it is compared with (results.json
// error.reference.mean_stderr, rtgi-view's live comparison).
double rmsStandardError(const FloatImage& se, int channels, const std::vector<std::uint8_t>& mask);

// The RMSE against a noisy reference, corrected for the reference's noise,
// with a confidence interval (docs/reference.md, "Errors with their
// uncertainty"). Model: the reference pixel r̂ = r + e with e ~ N(0, σ²),
// σ = its standard error `se` (the mean of many independent samples), so
// with d = t − r the measured squared error (d − e)² has mean d² + σ² and
// variance 4d²σ² + 2σ⁴. Hence MSE_debiased = MSE − mean(σ²) (rmseDebiased =
// √max(0, ·)), and its variance is the sum of the per-pixel variances over
// M², M = pixels × channels; the channels of a pixel share their paths, so
// they are combined as fully correlated (the variances' square roots add:
// an upper bound). d² is estimated by max(0, d̂² − σ²). The interval is
// MSE_debiased ± z·sd mapped through √max(0, ·); it covers the reference's
// noise only (the tested frame is what it is), and the error of σ itself
// (relative 1/√(2(n−1)) for Gaussian samples, more with fireflies) is not in
// it. Pixels with a non-finite value in any input are left out, as in
// compareImages.
struct RmseUncertainty {
    double rmse = 0;          // as compareImages
    double rmseDebiased = 0;  // √max(0, MSE − mean(σ²))
    double low = 0, high = 0; // the interval of the true RMSE
    double noiseRms = 0;      // √mean(σ²): the reference's noise on the RMSE's scale
    double z = 1.959963984540054;  // two-sided 95 %
};
RmseUncertainty rmseUncertainty(const FloatImage& test, const FloatImage& ref, const FloatImage& se, int channels,
                                const std::vector<std::uint8_t>& mask = {}, double z = 1.959963984540054);

}  // namespace rtgi
