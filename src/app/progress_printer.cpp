#include "app/progress_printer.h"

#include "render/progress.h"

#include <unistd.h>

#include <chrono>
#include <memory>
#include <cstdio>

namespace rtgi {

namespace {

struct State {
    std::string program, phase;
    std::chrono::steady_clock::time_point start;
    bool tty = false;
    bool lineOpen = false;
    std::chrono::steady_clock::time_point lastDraw;
};

void print(State& st, const std::string& phase, long done, long total) {
    using Clock = std::chrono::steady_clock;
    const auto now = Clock::now();
    if (phase != st.phase || done == 0) {
        st.phase = phase;
        st.start = now;
    }
    const double elapsed = std::chrono::duration<double>(now - st.start).count();
    const bool finished = done >= total;
    if (!st.tty) {
        if (finished && total > 0)
            std::fprintf(stderr, "%s: %s: %ld in %.1f s\n", st.program.c_str(), phase.c_str(), total, elapsed);
        return;
    }
    // A terminal: redraw at most 20 times a second, and always the last step.
    if (!finished && done > 0 && std::chrono::duration<double>(now - st.lastDraw).count() < 0.05) return;
    st.lastDraw = now;
    const int width = 24;
    const int fill = total > 0 ? int(double(width) * double(done) / double(total)) : 0;
    std::string bar(std::size_t(fill), '=');
    bar.resize(std::size_t(width), ' ');
    char eta[32] = "";
    if (done > 0 && !finished) std::snprintf(eta, sizeof eta, ", ETA %.0f s", elapsed / double(done) * double(total - done));
    std::fprintf(stderr, "\r\033[K%s: %-16s %6ld/%-6ld [%s] %.1f s%s", st.program.c_str(), phase.c_str(), done, total,
                 bar.c_str(), elapsed, eta);
    st.lineOpen = !finished;
    if (finished) std::fprintf(stderr, "\n");
    std::fflush(stderr);
}

}  // namespace

ProgressPrinter::ProgressPrinter(std::string program) {
    auto st = std::make_shared<State>();
    st->program = std::move(program);
    st->tty = isatty(fileno(stderr)) != 0;
    progress::setSink([st](const std::string& phase, long done, long total) { print(*st, phase, done, total); },
                      st->tty);
}

ProgressPrinter::~ProgressPrinter() { progress::clearSink(); }

}  // namespace rtgi
