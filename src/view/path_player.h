#pragma once
// rtgi-view's path playback (issue 23, docs/viewer.md "Paths"), without a
// window: which path frame the viewer shows, play / pause / step / scrub, and
// whether the frame continues the previous one (temporal histories kept) or
// jumps (a cut). One path frame per rendered frame, as rtgi-bench renders
// frame i at t = i / fps however long frames take. Unit-tested in
// tests/unit/test_view_path.cpp.
#include "gl/image_io.h"

#include <optional>

namespace rtgi::view {

class PathPlayer {
public:
    // A path of `frames` frames (>= 1) at `fps` (> 0); starts paused at frame 0.
    PathPlayer(int frames, double fps);

    int frame() const { return frame_; }
    int frames() const { return frames_; }
    double time() const { return double(frame_) / fps_; }  // t = frame / fps
    bool playing() const { return playing_; }

    // Space: play / pause. Playing from the last frame starts again at frame 0.
    void togglePlay();
    // Left / right: pause and step by `delta` frames, clamped to [0, frames - 1].
    void step(int delta);
    // Home: pause at frame 0.
    void home() { scrub(0); }
    // The panel's slider: pause at `frame`, clamped to [0, frames - 1].
    void scrub(int frame);

    // Called once per rendered frame after it was drawn: while playing, the next
    // frame; at the last frame playback pauses there.
    void advance();

    // Whether the frame about to be rendered continues the last rendered one
    // (the next path frame, or the same one): its histories are kept. A jump
    // (scrub, a step back, a restart) must cut the histories. Also true before
    // the first frame (nothing to continue).
    bool jumped() const;
    // Records that the current frame was rendered (what jumped() compares with).
    void rendered() { last_ = frame_; }

private:
    int frames_;
    double fps_;
    int frame_ = 0;
    bool playing_ = false;
    std::optional<int> last_;
};

// Frame-to-frame change of an image: the RMS over pixels and the first
// `channels` channels of b − a, over pixels finite in both (nullopt when the
// sizes differ or no pixel is). With a still camera this is the image's flicker.
std::optional<double> rmsChange(const FloatImage& a, const FloatImage& b, int channels);

}  // namespace rtgi::view
