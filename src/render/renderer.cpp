#include "render/renderer.h"

#include "render/passes/core_passes.h"
#include "render/lpv/lpv_passes.h"
#include "compute/lib/post_shared.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <stdexcept>

namespace rtgi {

namespace {
// RTGI_TRACE=1: every pass is finished (glFinish) and its end printed with the
// seconds since the process's first traced step, to find a stall or a hang
// on a driver where nothing else says where the time goes.
bool traceSteps() {
    static const bool on = [] {
        const char* v = std::getenv("RTGI_TRACE");
        return v && *v && std::string(v) != "0";
    }();
    return on;
}
void traceStep(const std::string& what) {
    if (!traceSteps()) return;
    static const auto t0 = std::chrono::steady_clock::now();
    glFinish();
    std::fprintf(stderr, "trace %9.3f s  %s\n",
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), what.c_str());
}
}  // namespace

std::vector<std::pair<std::string, const gl::Texture*>> namedResources(const FrameResources& r) {
    std::vector<std::pair<std::string, const gl::Texture*>> out;
    for (int i = 0; i < R::count; ++i) out.push_back({resourceDesc({i}).name, &r[{i}]});
    return out;
}

Renderer::Renderer(const Scene& scene, const Settings& settings, gl::Profiler& profiler)
    : scene_(scene), profiler_(profiler) {
    traceStep("renderer: construction begins");
    frameUbo_ = gl::Buffer(ledger_, "frame.uniforms", sizeof(gpu::FrameUniforms), nullptr, GL_DYNAMIC_STORAGE_BIT);
    configure(settings);
    traceStep("renderer: constructed");
}

Renderer::~Renderer() = default;

Pass* Renderer::findPass(const std::string& name) const {
    for (auto& p : passes())
        if (p->name() == name) return p.get();
    return nullptr;
}

int Renderer::indexOf(const Pass& pass) const {
    for (std::size_t i = 0; i < passes().size(); ++i)
        if (passes()[i].get() == &pass) return int(i);
    throw std::logic_error("pass '" + pass.name() + "' is not in the frame");
}

std::vector<Renderer::Output> Renderer::checkedOutputs(const Pass& pass) const {
    const PassDecl& d = plan_.decl(indexOf(pass));
    std::vector<Output> out;
    for (auto& u : d.uses())
        if (u.access == PassDecl::Access::write || u.access == PassDecl::Access::accumulate) {
            const ResourceDesc& desc = resourceDesc(u.resource);
            if (desc.check != Check::none && res_[u.resource])
                out.push_back({pass.name() + ":" + desc.name, &res_[u.resource], desc.check});
        }
    for (auto& o : d.outputs()) {
        const gl::Texture* t = o.tex();
        if (t && *t && o.check != Check::none) out.push_back({pass.name() + ":" + o.name, t, o.check});
    }
    return out;
}

std::vector<DebugImage> Renderer::debugImages(const Pass& pass) const {
    std::vector<DebugImage> out;
    for (auto& d : plan_.decl(indexOf(pass)).debugImages()) {
        DebugImage img = d.make();
        if (img.tex && *img.tex) out.push_back(img);
    }
    return out;
}

void Renderer::configure(const Settings& settings) {
    checkRadiometricRange(scene_, settings);  // before any product becomes a float (render/lights.h)
    bool sceneChanged = !gpuScene_ || settings.light.emissiveScale != settings_.light.emissiveScale ||
                        settings.floorRoughness != settings_.floorRoughness;
    settings_ = settings;
    resolveSceneAutos();
    plan_ = FramePlan{};
    finite_.clear();  // --check counts belong to one configuration
    res_ = FrameResources{};  // release everything; the new frame allocates what it writes
    for (bool& b : writtenLastFrame_) b = false;
    if (sceneChanged) gpuScene_ = std::make_unique<GpuScene>(ledger_, scene_, settings_, restVertices_.empty());
    plan_ = FramePlan::build(frameScript(), frameFamilies(), scene_, settings_);
    resolveLights();
}

// lpv.coarse_iterations=auto: the open scene's value (the setting's default) unless less than
// lpv.closed_escape of the light scattered by the scene's surfaces leaves it (docs/lpv.md, "Closed
// scenes"); settings() then shows the value in effect.
void Renderer::resolveSceneAutos() {
    LpvSettings& l = settings_.lpv;
    if (!l.coarseIterationsAuto) return;
    // No measure (a BVH build) where the count is not used: LPV off or without light, one cascade, raster path.
    if (lpvCoarseStepsUsed(scene_, settings_)) {
        if (!enclosure_) {
            traceStep("renderer: measuring the scene's enclosure");
            enclosure_ = measureEnclosure(restVertices_.empty() ? scene_ : [&] {
                Scene rest = scene_;
                rest.vertices = restVertices_;
                return rest;
            }());
        }
        if (enclosure_->rays > 0 && enclosure_->escaped < double(l.closedEscape))
            l.coarseIterations = LpvSettings::kClosedCoarseIterations;
    }
    l.coarseIterationsAuto = false;
}

// Local lights: the per-frame list and the shadow matrices live as long as
// this configuration (or until a moving scene changes its lights).
void Renderer::resolveLights() {
    skipped_ = plan_.skipped();
    localLights_ = resolveLocalLights(scene_, settings_);
    // emissive.split=auto: settings() (and results.json "config") show the value in effect, which also
    // keeps the light count fixed while a moving scene re-resolves its lights.
    if (settings_.light.emissiveSplit == 0) settings_.light.emissiveSplit = localLights_.emissiveSplit;
    for (auto& [light, reason] : localLights_.leftOut) skipped_.push_back({"light:" + light, reason});
    res_.localShadowLayers = std::max(1, localLights_.shadowLayers);
    res_.localRsmSize = localRsmSize(settings_, localLights_.faces);
    res_.localRsmFaces = localLights_.faces;
    lightSchedule_.reset(localLights_);
    res_.localLights = gl::Buffer(ledger_, "lights.local",
                                  std::int64_t(std::max<std::size_t>(1, localLights_.lights.size()) * sizeof(gpu::GpuLight)));
    res_.localLightShapes = gl::Buffer(ledger_, "lights.local.shapes",
                                       std::int64_t(std::max<std::size_t>(1, localLights_.lights.size()) * sizeof(gpu::GpuLightShape)));
    res_.localShadowMatrices = gl::Buffer(ledger_, "shadow.local.matrices",
                                          std::int64_t(res_.localShadowLayers * sizeof(glm::mat4)));
}

void Renderer::updateScene(const Scene& state) {
    if (state.vertices.size() != scene_.vertices.size() || state.lights.size() != scene_.lights.size())
        throw std::logic_error("Renderer::updateScene: a scene state must keep the vertex and light counts");
    sceneUpdate_ = {};
    const auto t0 = std::chrono::steady_clock::now();
    const std::int64_t bytes0 = gpuScene_->uploadedBytes();
    static_assert(sizeof(Vertex) == 32, "Vertex is compared bytewise");
    if (!state.vertices.empty() &&
        std::memcmp(state.vertices.data(), scene_.vertices.data(), state.vertices.size() * sizeof(Vertex)) != 0) {
        if (restVertices_.empty()) restVertices_ = scene_.vertices;  // the pose this renderer was built with
        scene_.vertices = state.vertices;
        scene_.motions = state.motions;
        // Moved by transforms: a state of rigid motions, or the rest pose again (no motions).
        const bool atRest = state.motions.empty() && std::memcmp(state.vertices.data(), restVertices_.data(),
                                                                  state.vertices.size() * sizeof(Vertex)) == 0;
        sceneUpdate_.transforms = (!state.motions.empty() || atRest) && gpuScene_->setTransforms(scene_, restVertices_);
        if (!sceneUpdate_.transforms) gpuScene_->updateVertices(scene_);
        sceneUpdate_.geometry = true;
        geometryChanged();  // the light budget's cached local maps show the old geometry
    }
    bool lightsChanged = false;
    for (std::size_t i = 0; i < state.lights.size(); ++i) {
        const Light &a = state.lights[i], &b = scene_.lights[i];
        lightsChanged = lightsChanged || a.position != b.position || a.direction != b.direction ||
                        a.color != b.color || a.intensity != b.intensity;
    }
    if (lightsChanged) {
        scene_.lights = state.lights;
        checkRadiometricRange(scene_, settings_);
        gpuScene_->updateLights(scene_);
        std::vector<std::string> before;
        for (auto& l : localLights_.lights) before.push_back(l.name);
        LocalLights now = resolveLocalLights(scene_, settings_);
        std::vector<std::string> after;
        for (auto& l : now.lights) after.push_back(l.name);
        if (before == after) {  // the same list: new positions, colours; redraw the maps of those that moved
            for (std::size_t i = 0; i < now.lights.size(); ++i)
                if (std::memcmp(&now.lights[i].gpu, &localLights_.lights[i].gpu, sizeof(gpu::GpuLight)) != 0)
                    lightChanged(int(i));
            localLights_ = std::move(now);
        } else {
            resolveLights();  // a light switched on or off: new buffers (and shadow layers)
        }
        sceneUpdate_.lights = true;
    }
    scene_.cameras = state.cameras;
    // CPU time only: no glFinish here (a stall on every moving frame); the GPU
    // side of the upload lands in the next frame's first pass.
    sceneUpdate_.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    sceneUpdate_.uploadedBytes = gpuScene_->uploadedBytes() - bytes0;
}

// Every shared resource a pass of the frame writes, from its descriptor (by
// handle, so two passes can never allocate one resource under two labels).
gl::TextureDesc Renderer::sharedTextureDesc(Resource r, glm::ivec2 s) const {
    const glm::ivec2 aoSize = settings_.ao.halfResolution ? glm::max((s + 1) / 2, glm::ivec2(1)) : s;
    const ResourceDesc& d = resourceDesc(r);
    glm::ivec2 size = d.extent == Extent::view          ? s
                      : d.extent == Extent::ao          ? aoSize
                      : d.extent == Extent::shadow      ? glm::ivec2(settings_.light.shadowSize)
                      : d.extent == Extent::localShadow ? glm::ivec2(settings_.light.localShadowSize)
                                                        : glm::ivec2(kBrdfLutSize);
    const bool layered = d.extent == Extent::localShadow;
    return {layered ? GLenum(GL_TEXTURE_2D_ARRAY) : GLenum(GL_TEXTURE_2D), d.format, size.x, size.y,
            layered ? res_.localShadowLayers : 1};
}

// Every shared resource a pass of the frame writes, from its descriptor (by
// handle, so two passes can never allocate one resource under two labels).
void Renderer::allocateShared(const View& view) {
    for (int i = 0; i < R::count; ++i) {
        const Resource r{i};
        if (!plan_.written(r)) continue;
        const ResourceDesc& d = resourceDesc(r);
        if (res_[r].ensure(ledger_, d.name, sharedTextureDesc(r, view.size))) {
            res_[r].setSampling(d.filter, d.filter);
            ++res_.allocationEpoch;
            if (r == R::localShadowMaps) lightSchedule_.shadowStorageLost();
            writtenLastFrame_[i] = false;
        }
    }
}

void Renderer::uploadFrameUniforms(const View& v) {
    gpu::FrameUniforms u{};
    u.view = v.view;
    u.proj = v.proj;
    u.viewProj = v.viewProj();
    u.invView = glm::inverse(v.view);
    u.invProj = glm::inverse(v.proj);
    u.prevViewProj = v.prevViewProj();
    u.prevView = v.prevView;
    u.cameraPos = glm::vec4(v.position, 1.0f);
    Aabb box = scene_.bounds();
    float sceneRadius = 0.5f * glm::length(box.extent());
    if (auto sun = resolveSun(scene_, settings_)) {
        res_.shadowViewProj = orthoLightViewProj(box, sun->towardSun);
        u.shadowViewProj = res_.shadowViewProj;
        u.sunDirection = glm::vec4(sun->towardSun, 1.0f);
        // Normal-offset bias: ~1.5 shadow texels in world units.
        float texelWorld = 2.0f * sceneRadius / float(settings_.light.shadowSize);
        u.sunIrradiance = glm::vec4(sun->irradiance, 1.5f * texelWorld);
    }
    u.sky = glm::vec4(resolveSky(scene_, settings_), settings_.post.exposure);
    u.projParams = glm::vec4(v.nearPlane, v.farPlane, std::tan(0.5f * v.fovY), float(v.size.x) / float(v.size.y));
    u.size = glm::ivec4(v.size, int(v.frame), v.cut ? 1 : 0);
    // Local lights: culling, then the light budget picks the faces drawn now.
    const bool shadows = findPass("shadow.local") != nullptr;
    FrameLights fl = frameLights(localLights_, u.viewProj, box, shadows, settings_.light.localShadowSize);
    std::optional<FrameLights> rl;  // the same culling and frusta at the RSM's size
    if (findPass("lpv.rsm")) rl = frameLights(localLights_, u.viewProj, box, true, res_.localRsmSize);
    LightSchedule::Frame plan =
        lightSchedule_.plan(localLights_, fl, rl ? &*rl : nullptr, shadows, settings_.light.budget, v.position);
    if (!fl.gpu.empty()) res_.localLights.upload(fl.gpu.data(), std::int64_t(fl.gpu.size() * sizeof(gpu::GpuLight)));
    if (!fl.shapes.empty())
        res_.localLightShapes.upload(fl.shapes.data(), std::int64_t(fl.shapes.size() * sizeof(gpu::GpuLightShape)));
    res_.localLightCount = int(fl.gpu.size());
    auto local = [](const ShadowView& sv) {
        return FrameResources::LocalShadowView{sv.viewProj, sv.light, sv.layer, sv.tanHalfFov, sv.face, sv.valid};
    };
    res_.localShadowViews.clear();
    for (auto& sv : plan.drawShadows) res_.localShadowViews.push_back(local(sv));
    res_.localRsmViews.clear();
    for (auto& sv : plan.drawRsms) res_.localRsmViews.push_back(local(sv));
    res_.localRsmInject.clear();
    for (auto& sv : plan.injectRsms) res_.localRsmInject.push_back(local(sv));
    res_.localLightsCpu = fl.gpu;
    if (shadows && localLights_.shadowLayers > 0) {  // every layer: the view its map was drawn with
        std::vector<glm::mat4> mats(std::size_t(localLights_.shadowLayers), glm::mat4(1.0f));
        for (auto& L : localLights_.lights)
            for (int k = 0; L.firstLayer >= 0 && k < L.faces; ++k)
                mats[std::size_t(L.firstLayer + k)] = lightSchedule_.shadowViewProj(L.firstFace + k);
        res_.localShadowMatrices.upload(mats.data(), std::int64_t(mats.size() * sizeof(glm::mat4)));
    }
    localCulled_ = fl.culled;
    res_.localLightsCulled = fl.culled;
    res_.localLightsWaiting = plan.waiting;
    res_.localFacesCached = plan.cachedFaces;
    localShadowed_ = fl.shadowed - plan.waiting;
    u.counts = glm::ivec4(gpuScene_->punctualLightCount(), gpuScene_->materialCount(), 0, res_.localLightCount);
    frameUbo_.upload(&u, sizeof(u));
}

void Renderer::setLocalLight(int light, const LocalLight& l) {
    if (light < 0 || std::size_t(light) >= localLights_.lights.size())
        throw std::out_of_range("setLocalLight: no local light " + std::to_string(light));
    LocalLight& L = localLights_.lights[std::size_t(light)];
    // The faces and layers are the configuration's (the shadow array's layout).
    const int faces = L.faces, firstFace = L.firstFace, firstLayer = L.firstLayer;
    L = l;
    L.faces = faces, L.firstFace = firstFace, L.firstLayer = firstLayer;
    lightSchedule_.lightChanged(light);
}


void Renderer::render(const View& view) {
    traceStep("frame begins");
    allocateShared(view);
    for (int i = 0; i < R::count; ++i) previousValid_[i] = writtenLastFrame_[i] && !view.cut;
    uploadFrameUniforms(view);
    gpuScene_->beginFrame();
    FrameContext ctx{programs_, ledger_, profiler_, scene_, *gpuScene_, settings_, res_, view, frameUbo_.id(),
                     &plan_, 0, previousValid_};
    gl::Profiler::setPerDispatch(settings_.post.profileDispatches);
    profiler_.beginFrame();
    if (gpuScene_->transformsPending()) {  // objects moved by transforms (a static scene never sees this)
        auto scope = profiler_.scope("scene.transform");
        gpuScene_->applyTransforms(programs_);
        traceStep("scene.transform");
    }
    for (std::size_t i = 0; i < passes().size(); ++i) {
        Pass& pass = *passes()[i];
        ctx.passIndex = int(i);
        {
            auto scope = profiler_.scope(pass.name().c_str());
            // Every pass sets the state it relies on; the frame block is the
            // one binding all passes share.
            glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_FRAME, frameUbo_.id());
            pass.execute(ctx);
        }
        traceStep(pass.name());
        if (check_) checkOutputs(pass);
    }
    profiler_.endFrame();
    gpuScene_->endFrame();
    for (int i = 0; i < R::count; ++i) writtenLastFrame_[i] = plan_.written({i});
}

FiniteCount countNonFinite(gl::ProgramCache& programs, gl::MemoryLedger& ledger, const gl::Texture& t,
                           bool mayBeNegative) {
    FiniteCount fc;
    int channels = 4;
    switch (t.format()) {
        case GL_R32F: case GL_R16F: case GL_R8: channels = 1; break;
        case GL_RG16F: case GL_RG32F: case GL_RG8: channels = 2; break;
        case GL_R11F_G11F_B10F: channels = 3; break;
        case GL_RGBA16F: case GL_RGBA32F: case GL_RGBA8: channels = 4; break;
        default: return fc;  // integer / depth formats cannot hold non-finite values
    }
    const bool volume = t.desc().target == GL_TEXTURE_3D, array = t.desc().target == GL_TEXTURE_2D_ARRAY;
    const gl::Program& prog = programs.compute(
        "post/finite_check.comp",
        volume ? gl::Defines{{"RTGI_VOLUME", ""}} : array ? gl::Defines{{"RTGI_ARRAY", ""}} : gl::Defines{});
    gl::Buffer counts(ledger, "check.counts", 16);
    counts.clearZero();
    glMemoryBarrier(GL_ALL_BARRIER_BITS);  // producer: whichever pass wrote t just before
    glUseProgram(prog.id());
    glBindTextureUnit(RTGI_POST_TEX_SOURCE, t.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_POST_SSBO_COUNTS, counts.id());
    prog.set(RTGI_POST_LOC_CHANNELS, channels);
    prog.set(RTGI_POST_LOC_MAY_BE_NEGATIVE, mayBeNegative ? 1 : 0);
    glDispatchCompute(gl::groupCount(t.width(), 8), gl::groupCount(t.height(), 8), GLuint(volume || array ? t.depth() : 1));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::uint32_t c[4];
    counts.download(c, 16);
    fc.nan = c[0];
    fc.inf = c[1];
    fc.negative = c[2];
    fc.fp16Saturated = c[3];
    return fc;
}

void Renderer::checkOutputs(const Pass& pass) {
    for (auto& out : checkedOutputs(pass)) {
        FiniteCount c = countNonFinite(programs_, ledger_, *out.tex, out.check == Check::signedValues);
        FiniteCount* fc = nullptr;
        for (auto& f : finite_)
            if (f.pass == pass.name() && f.resource == out.name) fc = &f;
        if (!fc) {
            finite_.push_back({pass.name(), out.name});
            fc = &finite_.back();
        }
        fc->nan += c.nan;
        fc->inf += c.inf;
        fc->negative += c.negative;
        fc->fp16Saturated += c.fp16Saturated;
    }
}

}  // namespace rtgi
