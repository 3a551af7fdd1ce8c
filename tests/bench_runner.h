#pragma once
// Runs the rtgi-bench binary of this build (both test tiers) under
// timeout(1), so that a regression that hangs (a FIFO opened for reading)
// fails the test instead of blocking it, and returns exit code, stderr and
// wall time.
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace rtgi::test {

struct BenchRun {
    int rc = -1;
    std::string err;
    double seconds = 0;
};

// `args` is passed to the shell as written (quote paths with spaces).
inline BenchRun runBench(const std::string& args, int timeoutSeconds = 20) {
    namespace fs = std::filesystem;
    static int n = 0;
    fs::path log = fs::temp_directory_path() / ("rtgi-bench-run-" + std::to_string(getpid()) + "-" + std::to_string(n++) + ".log");
    auto t0 = std::chrono::steady_clock::now();
    int rc = std::system(("timeout -s KILL " + std::to_string(timeoutSeconds) + " " + std::string(RTGI_BENCH_EXE) + " " +
                          args + " > /dev/null 2> " + log.string())
                             .c_str());
    BenchRun r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.rc = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
    std::ifstream in(log);
    r.err.assign(std::istreambuf_iterator<char>(in), {});
    fs::remove(log);
    return r;
}

// Single-quoted for the shell (a ' inside becomes '\'').
inline std::string shellQuote(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

}  // namespace rtgi::test
