#include "bench/sweep.h"

namespace rtgi {
int runSweepCommand(const CommandLine& cl) {
    throw ConfigError("--sweep " + cl.sweep + ": sweeps are not available in this build yet");
}
}  // namespace rtgi
