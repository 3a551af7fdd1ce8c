#pragma once
// Progress on stderr for single runs (issue 17): on a terminal a line that
// updates in place (phase, done/total, bar, elapsed, ETA); otherwise (a log
// file, CI) one summary line per finished phase.
#include <string>

namespace rtgi {

// Installs the printer as the progress sink (render/progress.h) until the
// returned guard is destroyed. `program` prefixes the lines ("rtgi-bench").
class ProgressPrinter {
public:
    explicit ProgressPrinter(std::string program);
    ~ProgressPrinter();
    ProgressPrinter(const ProgressPrinter&) = delete;
    ProgressPrinter& operator=(const ProgressPrinter&) = delete;
};

}  // namespace rtgi
