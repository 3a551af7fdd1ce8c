#include "view/path_player.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rtgi::view {

PathPlayer::PathPlayer(int frames, double fps) : frames_(frames), fps_(fps) {
    if (frames < 1 || !(fps > 0)) throw std::invalid_argument("PathPlayer: a path needs frames >= 1 and fps > 0");
}

void PathPlayer::togglePlay() {
    if (!playing_ && frame_ == frames_ - 1) frame_ = 0;
    playing_ = !playing_;
}

void PathPlayer::step(int delta) {
    playing_ = false;
    frame_ = std::clamp(frame_ + delta, 0, frames_ - 1);
}

void PathPlayer::scrub(int frame) {
    playing_ = false;
    frame_ = std::clamp(frame, 0, frames_ - 1);
}

void PathPlayer::advance() {
    if (!playing_) return;
    if (frame_ + 1 >= frames_) {
        playing_ = false;
        return;
    }
    ++frame_;
}

bool PathPlayer::jumped() const { return !last_ || (frame_ != *last_ && frame_ != *last_ + 1); }

std::optional<double> rmsChange(const FloatImage& a, const FloatImage& b, int channels) {
    if (a.width != b.width || a.height != b.height || a.channels != b.channels || channels < 1 ||
        channels > a.channels)
        return std::nullopt;
    double sum = 0;
    long long n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            bool finite = true;
            for (int c = 0; c < channels; ++c) finite = finite && std::isfinite(a.at(x, y, c)) && std::isfinite(b.at(x, y, c));
            if (!finite) continue;
            for (int c = 0; c < channels; ++c) {
                const double d = double(b.at(x, y, c)) - double(a.at(x, y, c));
                sum += d * d;
            }
            n += channels;
        }
    if (n == 0) return std::nullopt;
    return std::sqrt(sum / double(n));
}

}  // namespace rtgi::view
