#pragma once
// Sweeps (--sweep FILE.json): many configurations in one process.
#include "app/cli.h"

namespace rtgi {
int runSweepCommand(const CommandLine& cl);
}  // namespace rtgi
