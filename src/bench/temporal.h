#pragma once
// Temporal error of a path against per-frame references (issue 23; the
// formulas are in docs/temporal.md): reprojection of a frame's pixels into
// the previous frame (visible in both / disoccluded), flicker, lag after a
// step event and summaries over the path. CPU, double; no GL.
#include "gl/image_io.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace rtgi {

// What reprojection needs of one frame: linear depth (channel 0: view-space
// distance along -z, > 0 on geometry) and the cameras of this and the
// previous frame.
struct FrameGeometry {
    FloatImage depth;
    glm::dmat4 view{1.0}, prevView{1.0}, prevProj{1.0};
    double tanHalfFovY = 1.0, aspect = 1.0;
};

// Relative depth tolerance of "the same surface" in two frames.
inline constexpr double kReprojectionDepthTolerance = 0.05;

// For every pixel of `cur`: the index of the pixel of the previous frame it
// came from (the nearest pixel to its surface point projected by the previous
// camera: reprojection by the camera matrices, independent of the G-buffer's
// velocity; a point on a moving object lands where the object is no longer,
// fails the depth test and counts as disoccluded), or -1 where it was not visible
// there (off screen, sky, or the previous depth differs from the point's
// depth in the previous view by more than the tolerance: disoccluded), or
// -2 for sky pixels of `cur` (not compared).
std::vector<std::int32_t> reprojectPixels(const FrameGeometry& cur, const FloatImage& prevDepth,
                                          double tolerance = kReprojectionDepthTolerance);

// Flicker: RMS over pixels p visible in both frames (prevPixel[p] >= 0) and
// channels of (I_t(p) − R_t(p)) − (I_{t−1}(q) − R_{t−1}(q)), q = prevPixel[p].
// Returns nullopt when no pixel is visible in both.
std::optional<double> flickerRms(const FloatImage& test, const FloatImage& ref, const FloatImage& prevTest,
                                 const FloatImage& prevRef, const std::vector<std::int32_t>& prevPixel, int channels);

// RMSE over the pixels with mask[p] != 0 (nullopt when there are none).
std::optional<double> maskedRmse(const FloatImage& test, const FloatImage& ref, const std::vector<std::uint8_t>& mask,
                                 int channels);

// Lag after a step event at frame `event`: the error level before it is
// error[event − 1]; the lag is the number of frames j >= 0 until
// error[event + j] <= (1 + tolerance) · level (nullopt: not within the
// frames with an error, or no level before the event). Frames without a
// reference (nullopt) are skipped, so the lag is exact only where every
// frame after the event has one.
struct Lag {
    std::optional<int> frames;
    double levelBefore = 0, peak = 0;
};
Lag lagAfter(const std::vector<std::optional<double>>& error, int event, double tolerance = 0.1);

// Mean, 95th percentile (nearest rank) and maximum of the values present.
struct Summary {
    double mean = 0, p95 = 0, max = 0;
    int count = 0;
};
Summary summarize(const std::vector<std::optional<double>>& values);

}  // namespace rtgi
