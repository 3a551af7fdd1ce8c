#pragma once
// Per-pass GPU profiler. One RAII scope per pass (and a debug group with the
// pass name); GL_TIMESTAMP query pairs live in a ring and are read back
// kLatency frames later, so timing never stalls the pipeline. Where timer
// queries are unsupported or read 0 (Mesa llvmpipe) it falls back to
// glFinish + CPU clock around each scope and says so (timer() == "cpu").
#include "gl/handles.h"

#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rtgi::gl {

struct TimingStats {
    double median = 0, min = 0, max = 0, mean = 0;
    int samples = 0;
};
TimingStats computeStats(std::vector<double> v);

class Profiler {
public:
    static constexpr int kLatency = 4;  // frames between issue and read-back

    enum class Mode { Gpu, Cpu };
    // Probes the timer (a timestamp pair around real work); pass Mode::Cpu to force.
    explicit Profiler(bool timerQuerySupported);
    ~Profiler() { if (active_ == this) active_ = nullptr; }  // no dangling active profiler for dispatch()
    Mode mode() const { return mode_; }
    const char* timer() const { return mode_ == Mode::Gpu ? "gpu" : "cpu"; }

    // Samples are recorded only while measuring (after warm-up).
    void setMeasuring(bool on) { measuring_ = on; }
    void beginFrame();
    void endFrame();
    // Waits for everything in flight and reads it back.
    void flush();
    void reset();

    class Scope {
    public:
        Scope(Profiler* p, const char* name);
        ~Scope();
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;
        Scope(Scope&& o) noexcept : p_(o.p_), index_(o.index_) { o.p_ = nullptr; }
        Scope& operator=(Scope&&) = delete;

    private:
        Profiler* p_;
        int index_;
    };
    Scope scope(const char* name) { return Scope(this, name); }

    // Counts a dispatch/draw in the innermost open scope (called by dispatch()).
    static void noteDispatch();
    // profile.dispatches=on: every dispatch() gets its own nested scope
    // "<pass>/<program>" (sub-step timings; a timestamp pair per dispatch).
    static void setPerDispatch(bool on) { perDispatch_ = on; }
    // The nested scope of one dispatch when per-dispatch timing is on, else none.
    static std::optional<Scope> dispatchScope(const std::string& program);

    struct PassTiming {
        std::string name;
        TimingStats ms;
        double dispatchesPerFrame = 0;
    };
    // In first-seen order; includes "frame" (whole frame) last.
    std::vector<PassTiming> results() const;
    // Per measured frame, in frame order: milliseconds per pass and "frame"
    // (rtgi-bench --path writes them per frame).
    const std::vector<std::map<std::string, double>>& frameTimings() const { return frameTimings_; }
    // Most recent resolved per-pass milliseconds (viewer overlay).
    const std::map<std::string, double>& latest() const { return latest_; }

private:
    struct Record {
        std::string name;
        GLuint q0 = 0, q1 = 0;
        double cpuMs = 0;
        int dispatches = 0;
        int depth = 0;
    };
    struct FrameSlot {
        std::vector<Record> records;
        std::vector<QueryHandle> queries;
        int used = 0;
        bool pending = false;
        bool measured = false;
        GLuint frameQ0 = 0, frameQ1 = 0;
        double frameCpuMs = 0;
    };
    GLuint nextQuery(FrameSlot& s);
    void resolve(FrameSlot& s, bool wait);
    bool tryResolve(FrameSlot& s);

    Mode mode_;
    bool measuring_ = false;
    int current_ = 0;
    std::vector<FrameSlot> ring_;
    std::vector<int> open_;
    std::vector<std::chrono::steady_clock::time_point> openCpu_;
    std::chrono::steady_clock::time_point frameCpuStart_;
    std::vector<std::string> order_;
    std::map<std::string, std::vector<double>> samples_;
    std::map<std::string, long> dispatchTotals_;
    std::map<std::string, double> latest_;
    int measuredFrames_ = 0;
    std::vector<std::map<std::string, double>> frameTimings_;
    static Profiler* active_;
    static bool perDispatch_;
};

}  // namespace rtgi::gl
