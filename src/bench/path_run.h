#pragma once
// rtgi-bench --path (issue 23, docs/temporal.md): deterministic playback of a
// camera/scene path (frame i at t = i / fps, however long frames take), the
// per-frame timings and scene-update cost, and with --reference the temporal
// error against per-frame references (results.json "temporal", temporal.csv).
#include "app/cli.h"
#include "scene/path.h"

#include <nlohmann/json.hpp>

namespace rtgi {

class Renderer;

// Renders opts.warmup frames at t = 0, then opts.frames path frames with the
// profiler measuring; restores the renderer's scene to the rest state at the
// end. Returns results.json's "path" object (and "temporal" inside it with
// opts.reference); writes <out>/temporal.csv. `lastCamera`: the camera of the
// last frame (results.json "camera").
nlohmann::json runPathFrames(Renderer& renderer, const Path& path, const RunOptions& opts, Camera& lastCamera);

// The reference frames of a path run (docs/temporal.md): every k-th frame and
// the one before it, and frames event-1 .. event+kEventWindow of each step event.
inline constexpr int kEventWindow = 16;
std::vector<bool> referenceFrames(int frames, int every, const std::vector<int>& eventFrames);

}  // namespace rtgi
