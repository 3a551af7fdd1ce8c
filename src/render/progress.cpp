#include "render/progress.h"

namespace rtgi::progress {

namespace {
Sink& sink() {
    static Sink s;
    return s;
}
bool steps = false;
}  // namespace

void setSink(Sink s, bool wantsStepsToo) {
    sink() = std::move(s);
    steps = wantsStepsToo;
}

void clearSink() {
    sink() = nullptr;
    steps = false;
}

void report(const std::string& phase, long done, long total) {
    if (sink()) sink()(phase, done, total);
}

bool wantsSteps() { return steps && sink(); }

}  // namespace rtgi::progress
