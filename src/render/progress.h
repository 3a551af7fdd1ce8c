#pragma once
// Progress of long operations (warm-up and measured frames, reference
// samples) for whoever wants to show it: rtgi-bench installs a sink for single
// runs (app/progress_printer.h); sweeps and tests install none, and then
// report() costs a branch.
#include <functional>
#include <string>

namespace rtgi::progress {

// done/total of `phase`; called with done = 0 when a phase starts and
// done = total when it ends.
using Sink = std::function<void(const std::string& phase, long done, long total)>;

void setSink(Sink sink, bool wantsSteps);
void clearSink();
void report(const std::string& phase, long done, long total);
// Whether the sink shows intermediate steps (a terminal): a producer may then
// wait for the GPU between steps so that the numbers are honest.
bool wantsSteps();

}  // namespace rtgi::progress
