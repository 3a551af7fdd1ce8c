// The rtgi Python module's native part (_rtgi; docs/python.md). Everything it
// does goes through the library rtgi-bench is built from: loadScenes,
// effectiveSettings, runBenchmark, ReferenceTrace, compareImageData and
// SweepRunner. Results cross as JSON text (python/rtgi/__init__.py parses it)
// and images as float32 NumPy arrays, row 0 at the top. Errors are the CLI's
// exceptions, translated to Python ones with the same sentence; nothing here
// exits the process.
#include "app/cli.h"
#include "bench/reference_compare.h"
#include "bench/results_csv.h"
#include "bench/run.h"
#include "bench/sweep.h"
#include "gl/context.h"
#include "gl/image_io.h"
#include "gl/input_files.h"
#include "gl/output_files.h"
#include "gl/program.h"
#include "render/gpu_scene.h"
#include "render/lights.h"
#include "render/reference/reference_passes.h"
#include "render/renderer.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace py = pybind11;
using namespace rtgi;

namespace {

// One EGL context for the process, shared by every open Renderer and sweep
// (EGL displays are per device and eglTerminate would end every context on
// it): made by the first user, destroyed when the last one closes.
struct SharedContext {
    std::unique_ptr<gl::HeadlessContext> ctx;
    int device = -1;
    int users = 0;
};
SharedContext& sharedContext() {
    static auto* s = new SharedContext;  // never destroyed at exit: the driver may be gone by then
    return *s;
}

const gl::ContextInfo& acquireContext(int device, bool debug) {
    SharedContext& s = sharedContext();
    if (s.ctx && s.device != device)
        throw ConfigError("--device " + std::to_string(device) + ": a Renderer on EGL device " +
                          std::to_string(s.device) + " is open in this process; close it first");
    if (!s.ctx) {
        s.ctx = gl::HeadlessContext::create({device, debug});
        s.device = device;
    }
    ++s.users;
    return s.ctx->info();
}

void releaseContext() {
    SharedContext& s = sharedContext();
    if (s.users > 0 && --s.users == 0) s.ctx.reset();
}

// Holds one use of the shared context for an object's lifetime (or until release()).
class ContextUse {
public:
    ContextUse(int device, bool debug) : info_(acquireContext(device, debug)) {}
    ~ContextUse() { release(); }
    ContextUse(const ContextUse&) = delete;
    ContextUse& operator=(const ContextUse&) = delete;
    void release() {
        if (held_) releaseContext();
        held_ = false;
    }
    const gl::ContextInfo& info() const { return info_; }

private:
    gl::ContextInfo info_;
    bool held_ = true;
};

int channelsOf(GLenum f) {
    switch (f) {
        case GL_R8: case GL_R16: case GL_R16F: case GL_R32F: case GL_R8UI: case GL_R16UI: case GL_R32UI:
        case GL_R8I: case GL_R16I: case GL_R32I: case GL_DEPTH_COMPONENT16: case GL_DEPTH_COMPONENT24:
        case GL_DEPTH_COMPONENT32F:
            return 1;
        case GL_RG8: case GL_RG16: case GL_RG16F: case GL_RG32F: case GL_RG32UI: case GL_RG32I:
            return 2;
        case GL_RGB8: case GL_RGB16F: case GL_RGB32F: case GL_R11F_G11F_B10F:
            return 3;
        default:
            return 4;
    }
}

// A FloatImage (row 0 = bottom) as an H x W x C float32 array (row 0 = top)
// with its first `channels` channels.
py::array_t<float> toArray(const FloatImage& img, int channels) {
    channels = std::min(channels, img.channels);
    py::array_t<float> a({py::ssize_t(img.height), py::ssize_t(img.width), py::ssize_t(channels)});
    auto m = a.mutable_unchecked<3>();
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < channels; ++c) m(img.height - 1 - y, x, c) = img.at(x, y, c);
    return a;
}

// An H x W or H x W x C float array (row 0 = top) as a FloatImage (row 0 = bottom).
FloatImage fromArray(const py::array_t<float, py::array::c_style | py::array::forcecast>& a, const char* what) {
    if (a.ndim() != 2 && a.ndim() != 3)
        throw ConfigError(std::string(what) + ": expected an H x W or H x W x C array, got " + std::to_string(a.ndim()) +
                          " dimension(s)");
    FloatImage img;
    img.height = int(a.shape(0));
    img.width = int(a.shape(1));
    img.channels = a.ndim() == 3 ? int(a.shape(2)) : 1;
    if (img.width < 1 || img.height < 1 || img.channels < 1 || img.channels > 4)
        throw ConfigError(std::string(what) + ": expected H, W >= 1 and 1..4 channels");
    img.data.resize(std::size_t(img.width) * std::size_t(img.height) * std::size_t(img.channels));
    const float* src = a.data();
    const std::size_t row = std::size_t(img.width) * std::size_t(img.channels);
    for (int y = 0; y < img.height; ++y)
        std::copy(src + std::size_t(img.height - 1 - y) * row, src + std::size_t(img.height - y) * row,
                  img.data.begin() + std::ptrdiff_t(std::size_t(y) * row));
    return img;
}

ReferenceSettings::Kind parseKind(const std::string& k) {
    using K = ReferenceSettings::Kind;
    if (k == "ao") return K::Ao;
    if (k == "indirect") return K::Indirect;
    if (k == "full") return K::Full;
    throw ConfigError("reference kind '" + k + "': expected ao|indirect|full");
}

// A renderer of one scene list in the shared context (rtgi.Renderer).
class PyRenderer {
public:
    PyRenderer(const std::vector<std::string>& scenes, int width, int height, const Assignments& assignments,
               int device, const std::string& maxMemory, bool debug) {
        for (int v : {width, height})  // the CLI's toInt("--res", ...) sentence
            if (v < 1 || v > 16384) throw ConfigError("--res '" + std::to_string(v) + "': expected an integer in 1..16384");
        CommandLine cl;  // the CLI's checks of the same options
        cl.run.scenes = scenes;
        cl.scenesGiven = true;
        checkCommandLine(cl);
        opts_.scenes = scenes;
        opts_.resolution = {width, height};
        opts_.writeImages = false;
        opts_.quiet = true;
        if (!maxMemory.empty()) opts_.maxMemory = parseByteSize("--max-memory", maxMemory);
        scene_ = std::make_unique<Scene>(loadScenes(scenes));
        const Settings settings = settingsWith(assignments);
        assignments_ = assignments;
        checkRadiometricRange(*scene_, settings);
        ctx_ = std::make_unique<ContextUse>(device, debug);
        profiler_ = std::make_unique<gl::Profiler>(ctx_->info().timerQuery);
        renderer_ = std::make_unique<Renderer>(*scene_, settings, *profiler_);
    }
    ~PyRenderer() { close(); }

    void close() {
        renderer_.reset();  // GL objects go while the context is current
        profiler_.reset();
        if (ctx_) ctx_->release();
        ctx_.reset();
    }
    bool closed() const { return !renderer_; }

    // Applies key=value pairs (validated as --set would) and reconfigures.
    void set(const Assignments& more) {
        open();
        Assignments all = assignments_;
        all.insert(all.end(), more.begin(), more.end());
        const Settings s = settingsWith(all);
        checkRadiometricRange(*scene_, s);
        try {
            renderer_->configure(s);
        } catch (...) {
            // Its state after a throw inside configure() is not trusted (as
            // in a sweep): a fresh renderer with the settings it had.
            renderer_.reset();
            renderer_ = std::make_unique<Renderer>(*scene_, settingsWith(assignments_), *profiler_);
            throw;
        }
        assignments_ = std::move(all);
    }
    std::string settingsJson() const {
        nlohmann::json cfg = nlohmann::json::object();
        for (auto& [k, v] : describe(open().settings())) cfg[k] = typedValue(v);
        return cfg.dump();
    }
    std::vector<std::string> warnings() const { return scene_->warnings; }
    std::string sceneName() const { return scene_->name; }
    std::vector<std::string> views() const { return namedViews(*scene_); }
    std::pair<int, int> resolution() const { return {opts_.resolution.x, opts_.resolution.y}; }
    std::string cameraJson() const {
        Camera c = resolveCamera(*scene_, open().settings());
        return nlohmann::json({{"position", {c.position.x, c.position.y, c.position.z}},
                               {"target", {c.target.x, c.target.y, c.target.z}},
                               {"fov", glm::degrees(c.fovY)}, {"near", c.near}, {"far", c.far}})
            .dump();
    }

    // runBenchmark (results.json as JSON text) and the frame's images.
    std::pair<std::string, py::dict> render(int frames, int warmup, bool debugImages, bool check, bool reference) {
        Renderer& r = open();
        if (frames < 1 || frames > 1000000) throw ConfigError("--frames '" + std::to_string(frames) + "': expected an integer in 1..1000000");
        if (warmup < 0 || warmup > 1000000) throw ConfigError("--warmup '" + std::to_string(warmup) + "': expected an integer in 0..1000000");
        RunOptions o = opts_;
        o.frames = frames;
        o.warmup = warmup;
        o.check = check;
        o.reference = reference;
        nlohmann::json j = runBenchmark(ctx_->info(), r, o);
        py::dict images;
        FrameResources& res = r.resources();
        auto add = [&](const char* name, const gl::Texture& t, int maxChannels) {
            if (t) images[name] = toArray(readTexture(t), std::min(maxChannels, channelsOf(t.format())));
        };
        add("final", res.ldr, 3);
        add("hdr", res.hdr, 3);
        add("direct", res.direct, 3);
        add("indirect", res.indirectDiffuse, 3);
        add("specular", res.specular, 3);
        add("ao", res.ao, 1);
        add("albedo", res.gbuffer.albedo, 3);
        add("normal", res.gbuffer.normal, 3);
        add("depth", res.gbuffer.linearDepth, 1);
        if (debugImages)
            for (auto& p : r.passes())
                for (auto& d : r.debugImages(*p))
                    if (d.tex && *d.tex) images[d.name.c_str()] = toArray(readTexture(*d.tex), channelsOf(d.tex->format()));
        return {j.dump(), images};
    }

    // The ray-traced reference of the current settings and camera.
    py::tuple reference(const std::string& kindName, const Assignments& overrides) {
        Renderer& r = open();
        const ReferenceSettings::Kind kind = parseKind(kindName);
        ReferenceTrace trace(r, kind, overrides);
        Camera cam = resolveCamera(*scene_, r.settings());
        trace.renderer().render(makeView(cam, opts_.resolution, nullptr, 0));
        FloatImage mean = readTexture(trace.output().mean()), se = readTexture(trace.output().standardError());
        const int channels = kind == ReferenceSettings::Kind::Ao ? 1 : 3;
        nlohmann::json info = trace.info(se, channels, {});
        return py::make_tuple(toArray(mean, channels), toArray(se, channels), info.dump());
    }

private:
    Renderer& open() const {
        if (!renderer_) throw std::logic_error("this Renderer is closed");
        return *renderer_;
    }
    // Defaults, the scene's suggestions, then `a` (the CLI's settingsFor);
    // each assignment is checked alone first so that the error is --set's.
    Settings settingsWith(const Assignments& a) const {
        Settings probe;
        for (auto& [k, v] : a) applySetting(probe, k, v);
        Settings s = effectiveSettings(scene_->suggestedSettings, a, scene_->name);
        (void)resolveCamera(*scene_, s);  // an unknown view: the run's sentence, at set() rather than at render()
        return s;
    }

    RunOptions opts_;
    Assignments assignments_;
    std::unique_ptr<Scene> scene_;
    std::unique_ptr<ContextUse> ctx_;
    std::unique_ptr<gl::Profiler> profiler_;
    std::unique_ptr<Renderer> renderer_;
};

// rtgi.sweep's engine: the configurations of a sweep (one shard), run one at
// a time by the same SweepRunner as --sweep.
class PySweep {
public:
    PySweep(const std::string& source, bool isPath, int shardIndex, int shardCount, int device, bool check,
            const std::string& outDir) {
        if (shardCount < 1 || shardIndex < 0 || shardIndex >= shardCount)
            throw ConfigError("--shard '" + std::to_string(shardIndex) + "/" + std::to_string(shardCount) +
                              "': i must be below n");
        spec_ = isPath ? readSweepFile(source) : parseSweep(source, "sweep");
        mine_ = shardOf(spec_.configs, shardIndex, shardCount);
        shard_ = std::to_string(shardIndex) + "/" + std::to_string(shardCount);
        base_.check = check;
        base_.writeImages = !outDir.empty();
        outDir_ = outDir;
        device_ = device;
    }
    ~PySweep() { close(); }
    void close() {
        runner_.reset();
        if (ctx_) ctx_->release();
        ctx_.reset();
    }
    std::size_t size() const { return mine_.size(); }
    std::string name() const { return spec_.name; }
    std::string label(std::size_t i) const { return at(i).label(); }
    std::string id(std::size_t i) const { return at(i).id; }
    std::string run(std::size_t i) {
        const SweepConfig& c = at(i);
        if (!runner_) {
            ctx_ = std::make_unique<ContextUse>(device_, false);
            runner_ = std::make_unique<SweepRunner>(ctx_->info(), base_);
        }
        return runner_->run(spec_, c, shard_, outDir_.empty() ? std::string() : outDir_ + "/images/" + c.id).dump();
    }

private:
    const SweepConfig& at(std::size_t i) const {
        if (i >= mine_.size()) throw py::index_error("sweep configuration index out of range");
        return mine_[i];
    }
    SweepSpec spec_;
    std::vector<SweepConfig> mine_;
    std::string shard_, outDir_;
    RunOptions base_;
    int device_ = -1;
    std::unique_ptr<ContextUse> ctx_;
    std::unique_ptr<SweepRunner> runner_;
};

std::string compareArrays(const py::array_t<float, py::array::c_style | py::array::forcecast>& image,
                          const py::array_t<float, py::array::c_style | py::array::forcecast>& reference,
                          std::optional<py::array_t<float, py::array::c_style | py::array::forcecast>> mask,
                          const std::string& quantity, std::optional<double> background) {
    CompareOptions opts;
    opts.quantity = parseCompareQuantity(quantity);
    opts.background = background;
    if (mask && background) throw ConfigError("--compare: --mask and --background exclude each other");
    FloatImage t = fromArray(image, "image"), r = fromArray(reference, "reference");
    CompareData d;
    d.imageName = "image";
    d.referenceName = "reference";
    FloatImage m;
    if (mask) {
        m = fromArray(*mask, "mask");
        d.mask = &m;
        d.maskName = "array";
    }
    const int need = opts.quantity == CompareOptions::Quantity::Ao ? 1 : 3;
    for (const FloatImage* x : {&t, &r})
        if (x->channels < need)
            throw ConfigError(std::string(x == &t ? "image" : "reference") + ": " + std::to_string(x->channels) +
                              " channel(s), the quantity compares " + std::to_string(need));
    return compareImageData(t, r, d, opts).json.dump();
}

}  // namespace

PYBIND11_MODULE(_rtgi, m) {
    m.doc() = "rtgi's renderer, measurements and comparisons (native part; use the rtgi package)";
    // Exceptions: the CLI's classes and sentences (its exit codes 2, 3, 4, 6).
    static py::exception<ConfigError> configError(m, "ConfigError", PyExc_ValueError);
    static py::exception<SceneError> sceneError(m, "SceneError", PyExc_ValueError);
    static py::exception<std::runtime_error> glError(m, "GLError", PyExc_RuntimeError);
    static py::exception<OutputError> outputError(m, "OutputError", PyExc_OSError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const py::error_already_set&) {
            throw;
        } catch (const py::builtin_exception&) {
            throw;
        } catch (const ConfigError& e) {
            configError(escapeControl(e.what()).c_str());
        } catch (const SceneError& e) {
            sceneError(escapeControl(e.what()).c_str());
        } catch (const InputError& e) {
            sceneError(escapeControl(e.what()).c_str());
        } catch (const OutputError& e) {
            outputError(escapeControl(e.what()).c_str());
        } catch (const std::logic_error& e) {
            PyErr_SetString(PyExc_RuntimeError, e.what());
        } catch (const std::exception& e) {  // gl::ShaderError, GL errors, out of GPU memory
            glError(escapeControl(e.what()).c_str());
        }
    });

    py::class_<PyRenderer>(m, "Renderer")
        .def(py::init<const std::vector<std::string>&, int, int, const Assignments&, int, const std::string&, bool>(),
             py::arg("scenes"), py::arg("width"), py::arg("height"), py::arg("assignments"), py::arg("device"),
             py::arg("max_memory"), py::arg("debug"))
        .def("close", &PyRenderer::close)
        .def_property_readonly("closed", &PyRenderer::closed)
        .def("set", &PyRenderer::set, py::arg("assignments"))
        .def("settings_json", &PyRenderer::settingsJson)
        .def("camera_json", &PyRenderer::cameraJson)
        .def_property_readonly("warnings", &PyRenderer::warnings)
        .def_property_readonly("scene", &PyRenderer::sceneName)
        .def_property_readonly("views", &PyRenderer::views)
        .def_property_readonly("resolution", &PyRenderer::resolution)
        .def("render", &PyRenderer::render, py::arg("frames"), py::arg("warmup"), py::arg("debug_images"),
             py::arg("check"), py::arg("reference"))
        .def("reference", &PyRenderer::reference, py::arg("kind"), py::arg("overrides"));

    py::class_<PySweep>(m, "Sweep")
        .def(py::init<const std::string&, bool, int, int, int, bool, const std::string&>(), py::arg("source"),
             py::arg("is_path"), py::arg("shard_index"), py::arg("shard_count"), py::arg("device"), py::arg("check"),
             py::arg("out"))
        .def("__len__", &PySweep::size)
        .def_property_readonly("name", &PySweep::name)
        .def("label", &PySweep::label)
        .def("id", &PySweep::id)
        .def("run", &PySweep::run)
        .def("close", &PySweep::close);

    m.def("compare", &compareArrays, py::arg("image"), py::arg("reference"), py::arg("mask"), py::arg("quantity"),
          py::arg("background"));
    m.def("flatten_settings", &flattenJsonConfig, py::arg("json_text"), py::arg("source"));
    m.def("version", &versionString);
    m.def("context_users", [] { return sharedContext().users; },
          "Open renderers and sweeps holding the process's GL context (0: none, the context is released)");
    m.def("list_devices", &gl::HeadlessContext::listDevices);
    m.def("settings_help", &settingsHelp);
}
