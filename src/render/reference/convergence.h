#pragma once
// When a progressive reference stops (reference.target_noise,
// reference.target_stderr, reference.time_budget, reference.max_spp) and how
// many samples the next batch adds: a pure function of what the last check
// measured, so the unit tests drive it with a synthetic noise model
// (docs/reference.md, "Converging to a noise target").
#include <string>

namespace rtgi {

struct ConvergenceTarget {
    double relative = 0;    // RMS standard error <= relative × (debiased) error; 0 = off
    double absolute = 0;    // RMS standard error <= absolute; 0 = off
    double timeBudget = 0;  // seconds of tracing; 0 = no limit
    int maxSpp = 65536;
    int firstSpp = 16;      // the first batch
};

// One check after a batch: the reference's RMS standard error over the
// compared pixels and channels, and the debiased RMSE of the compared image
// against the reference so far (what the relative target refers to).
struct ConvergenceCheck {
    int spp = 0;
    double seconds = 0;  // tracing time so far (all batches)
    double noise = 0;
    double error = 0;
};

enum class StopReason { None, Target, TimeBudget, MaxSpp };
const char* toString(StopReason r);

// The noise the target asks for at this error: the looser of the two
// targets that are set; 0 when neither can be met (no absolute target and a
// zero error).
double targetNoiseFor(const ConvergenceTarget& t, double error);

struct ConvergenceStep {
    StopReason stop = StopReason::None;
    int nextBatch = 0;  // samples per pixel to add when stop == None
};

// Stop when the target holds, when maxSpp is reached, or when the next batch
// could not finish within the time budget at the measured rate; otherwise
// add the samples that the 1/√n law predicts are missing (+10 %), at least a
// quarter and at most as many as there already are (so each check can still
// correct the prediction), capped by maxSpp and by the time left.
ConvergenceStep planConvergence(const ConvergenceTarget& t, const ConvergenceCheck& c);

}  // namespace rtgi
