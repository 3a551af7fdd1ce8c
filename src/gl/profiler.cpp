#include "gl/profiler.h"

#include "gl/resources.h"

#include <algorithm>
#include <numeric>

namespace rtgi::gl {

Profiler* Profiler::active_ = nullptr;
bool Profiler::perDispatch_ = false;

TimingStats computeStats(std::vector<double> v) {
    TimingStats s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    s.samples = int(v.size());
    s.min = v.front();
    s.max = v.back();
    s.mean = std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
    std::size_t n = v.size();
    s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    return s;
}

Profiler::Profiler(bool timerQuerySupported) : mode_(timerQuerySupported ? Mode::Gpu : Mode::Cpu) {
    ring_.resize(kLatency + 1);
    if (mode_ == Mode::Gpu) {
        // Probe: some drivers expose GL_TIMESTAMP but return 0 (llvmpipe).
        // Time a clear of a 512x512 texture; a zero delta means no GPU timer.
        MemoryLedger scratch;
        Texture t(scratch, "profiler.probe", {GL_TEXTURE_2D, GL_RGBA32F, 512, 512});
        GLuint q[2];
        glGenQueries(2, q);
        glQueryCounter(q[0], GL_TIMESTAMP);
        t.clear(1, 2, 3, 4);
        glQueryCounter(q[1], GL_TIMESTAMP);
        glFinish();
        GLuint64 a = 0, b = 0;
        glGetQueryObjectui64v(q[0], GL_QUERY_RESULT, &a);
        glGetQueryObjectui64v(q[1], GL_QUERY_RESULT, &b);
        glDeleteQueries(2, q);
        if (a == 0 || b <= a) mode_ = Mode::Cpu;
    }
}

GLuint Profiler::nextQuery(FrameSlot& s) {
    if (s.used == int(s.queries.size())) {
        GLuint id = 0;
        glGenQueries(1, &id);
        s.queries.emplace_back(id);
    }
    return s.queries[std::size_t(s.used++)].id();
}

void Profiler::beginFrame() {
    FrameSlot& s = ring_[std::size_t(current_)];
    if (s.pending) resolve(s, true);  // ring is full: only after kLatency frames
    s.records.clear();
    s.used = 0;
    s.pending = true;
    s.measured = measuring_;
    active_ = this;
    if (mode_ == Mode::Gpu) {
        s.frameQ0 = nextQuery(s);
        glQueryCounter(s.frameQ0, GL_TIMESTAMP);
    } else {
        glFinish();
        frameCpuStart_ = std::chrono::steady_clock::now();
    }
}

void Profiler::endFrame() {
    FrameSlot& s = ring_[std::size_t(current_)];
    if (mode_ == Mode::Gpu) {
        s.frameQ1 = nextQuery(s);
        glQueryCounter(s.frameQ1, GL_TIMESTAMP);
    } else {
        glFinish();
        s.frameCpuMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frameCpuStart_).count();
    }
    current_ = (current_ + 1) % int(ring_.size());
    // Read back whatever has completed; never wait here.
    for (auto& slot : ring_)
        if (slot.pending && &slot != &ring_[std::size_t(current_)]) tryResolve(slot);
}

bool Profiler::tryResolve(FrameSlot& s) {
    if (mode_ == Mode::Gpu) {
        GLint available = 0;
        glGetQueryObjectiv(s.frameQ1, GL_QUERY_RESULT_AVAILABLE, &available);
        if (!available) return false;
    }
    resolve(s, false);
    return true;
}

void Profiler::resolve(FrameSlot& s, bool) {
    if (!s.pending) return;
    s.pending = false;
    auto gpuMs = [](GLuint a, GLuint b) {
        GLuint64 ta = 0, tb = 0;
        glGetQueryObjectui64v(a, GL_QUERY_RESULT, &ta);
        glGetQueryObjectui64v(b, GL_QUERY_RESULT, &tb);
        return tb > ta ? double(tb - ta) * 1e-6 : 0.0;
    };
    std::map<std::string, double> frameSums;
    std::map<std::string, int> frameDispatches;
    for (auto& r : s.records) {
        double ms = mode_ == Mode::Gpu ? gpuMs(r.q0, r.q1) : r.cpuMs;
        frameSums[r.name] += ms;  // a pass may open its scope more than once
        frameDispatches[r.name] += r.dispatches;
    }
    double frameMs = mode_ == Mode::Gpu ? gpuMs(s.frameQ0, s.frameQ1) : s.frameCpuMs;
    for (auto& [name, ms] : frameSums) latest_[name] = ms;
    latest_["frame"] = frameMs;
    if (!s.measured) return;
    ++measuredFrames_;
    for (auto& [name, ms] : frameSums) {
        samples_[name].push_back(ms);
        dispatchTotals_[name] += frameDispatches[name];
    }
    samples_["frame"].push_back(frameMs);
    frameSums["frame"] = frameMs;
    frameTimings_.push_back(std::move(frameSums));
}

void Profiler::flush() {
    glFinish();
    for (int k = 1; k <= int(ring_.size()); ++k) {
        FrameSlot& s = ring_[std::size_t((current_ + k) % int(ring_.size()))];
        if (s.pending) resolve(s, true);
    }
}

void Profiler::reset() {
    flush();
    samples_.clear();
    frameTimings_.clear();
    dispatchTotals_.clear();
    order_.clear();
    measuredFrames_ = 0;
}

Profiler::Scope::Scope(Profiler* p, const char* name) : p_(p), index_(-1) {
    if (!p_) return;
    FrameSlot& s = p_->ring_[std::size_t(p_->current_)];
    Record r;
    r.name = name;
    r.depth = int(p_->open_.size());
    if (std::find(p_->order_.begin(), p_->order_.end(), r.name) == p_->order_.end()) p_->order_.push_back(r.name);
    glPushDebugGroup(GL_DEBUG_SOURCE_APPLICATION, 0, -1, name);
    if (p_->mode_ == Mode::Gpu) {
        r.q0 = p_->nextQuery(s);
        glQueryCounter(r.q0, GL_TIMESTAMP);
    } else {
        glFinish();
        p_->openCpu_.push_back(std::chrono::steady_clock::now());
    }
    index_ = int(s.records.size());
    s.records.push_back(std::move(r));
    p_->open_.push_back(index_);
}

Profiler::Scope::~Scope() {
    if (!p_) return;
    FrameSlot& s = p_->ring_[std::size_t(p_->current_)];
    Record& r = s.records[std::size_t(index_)];
    if (p_->mode_ == Mode::Gpu) {
        r.q1 = p_->nextQuery(s);
        glQueryCounter(r.q1, GL_TIMESTAMP);
    } else {
        glFinish();
        r.cpuMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - p_->openCpu_.back()).count();
        p_->openCpu_.pop_back();
    }
    glPopDebugGroup();
    p_->open_.pop_back();
}

void Profiler::noteDispatch() {
    if (!active_ || active_->open_.empty()) return;
    FrameSlot& s = active_->ring_[std::size_t(active_->current_)];
    s.records[std::size_t(active_->open_.back())].dispatches++;
}

std::optional<Profiler::Scope> Profiler::dispatchScope(const std::string& program) {
    if (!perDispatch_ || !active_ || active_->open_.empty()) return std::nullopt;
    const FrameSlot& s = active_->ring_[std::size_t(active_->current_)];
    std::string outer = s.records[std::size_t(active_->open_.back())].name;
    std::string path = program.substr(0, program.find(' '));  // the name without its defines
    std::string shader = path.substr(path.find_last_of('/') + 1);
    std::optional<Scope> scope;
    scope.emplace(active_, (outer + "/" + shader.substr(0, shader.find('.'))).c_str());
    noteDispatch();
    return scope;
}

std::vector<Profiler::PassTiming> Profiler::results() const {
    std::vector<PassTiming> out;
    auto add = [&](const std::string& name) {
        auto it = samples_.find(name);
        if (it == samples_.end()) return;
        PassTiming t;
        t.name = name;
        t.ms = computeStats(it->second);
        auto d = dispatchTotals_.find(name);
        t.dispatchesPerFrame =
            (d != dispatchTotals_.end() && measuredFrames_ > 0) ? double(d->second) / measuredFrames_ : 0;
        out.push_back(t);
    };
    for (auto& n : order_) add(n);
    add("frame");
    return out;
}

}  // namespace rtgi::gl
