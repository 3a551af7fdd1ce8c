#include "render/reference/convergence.h"

#include <algorithm>
#include <cmath>

namespace rtgi {

const char* toString(StopReason r) {
    switch (r) {
        case StopReason::Target: return "target";
        case StopReason::TimeBudget: return "time_budget";
        case StopReason::MaxSpp: return "max_spp";
        default: return "none";
    }
}

double targetNoiseFor(const ConvergenceTarget& t, double error) {
    double goal = 0;
    if (t.relative > 0 && error > 0) goal = t.relative * error;
    if (t.absolute > 0) goal = std::max(goal, t.absolute);
    return goal;
}

ConvergenceStep planConvergence(const ConvergenceTarget& t, const ConvergenceCheck& c) {
    const double goal = targetNoiseFor(t, c.error);
    if (goal > 0 && c.noise <= goal) return {StopReason::Target, 0};
    if (c.spp >= t.maxSpp) return {StopReason::MaxSpp, 0};
    const double n = double(std::max(c.spp, 1));
    // Samples still missing by the 1/√n law; a zero goal (exact agreement
    // so far, no absolute floor) can only be approached: double.
    double want = goal > 0 ? n * (c.noise / goal) * (c.noise / goal) * 1.1 - n : n;
    want = std::clamp(want, std::max(1.0, std::floor(n / 4)), n);
    want = std::min(want, double(t.maxSpp - c.spp));
    if (t.timeBudget > 0) {
        const double perSample = c.seconds / n;
        const double left = t.timeBudget - c.seconds;
        const double fits = perSample > 0 ? std::floor(left / perSample) : want;
        if (fits < 1) return {StopReason::TimeBudget, 0};
        want = std::min(want, fits);
    }
    return {StopReason::None, int(want)};
}

}  // namespace rtgi
