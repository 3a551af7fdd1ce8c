// The LPV passes (seed 000 sections 3, 5.2; SPEC 3): lpv.rsm -> lpv.visibility -> lpv.inject
// -> lpv.pack -> lpv.inject_geometry -> lpv.propagate -> lpv.temporal ->
// lpv.apply. They share one LpvState (volumes, uniform block, RSM); the
// kernels live in lpv_volumes.cpp, the pure math in lpv_math.cpp.
#include "render/lpv/lpv_passes.h"

#include "gl/profiler.h"
#include "render/gpu_scene.h"
#include "render/lights.h"
#include "render/lpv/lpv_math.h"
#include "render/lpv/lpv_probe.h"
#include "render/lpv/lpv_volumes.h"
#include "gl/image_io.h"
#include "render/passes/core_passes.h"
#include "render/visibility/visibility.h"
#include "compute/lib/raster_shared.h"
#include "compute/lib/visibility_shared.h"

#include <algorithm>

namespace rtgi {
namespace {

// One local-light RSM face: a layer of the local RSM arrays (LpvState::localArrays; docs/lpv.md
// "Injection"), its framebuffer on the hardware path and the view it was drawn with.
struct LocalRsm {
    gl::FramebufferHandle fbo;
    glm::mat4 viewProj{1.0f};      // the view it was drawn with (the light budget may reuse it for frames)
    std::uint64_t generation = 0;  // draws of this face so far (0: never drawn, the layer is empty)
};

// What a cascade's injection cache was filled for (docs/lpv.md "Injection cache"): the cascade's
// placement, the injection cell rule, the SH order, the local RSMs' side and storage, the geometry.
struct InjectCacheKey {
    glm::vec4 origin{0.0f};  // min corner, cell size
    glm::ivec4 grid{0};      // cells, local RSM side
    int injectSide = 0, shOrder = 0;
    std::uint64_t storage = 0, geometry = 0;
    bool operator==(const InjectCacheKey&) const = default;
};

// The local lights' injection cache of one cascade: the sum of the faces in `held`, each as drawn
// in its generation held[face] (0: not held).
struct InjectCacheState {
    lpv::InjectCache volume;
    bool valid = false;
    InjectCacheKey key;
    std::vector<std::uint64_t> held;  // by face index
    int heldCount = 0;
};

// One volume: the single LPV, or one cascade (docs/lpv.md, "Cascades").
struct LpvCascade {
    lpv::Volumes volumes;
    gl::Buffer ubo;
    gpu::LpvUniforms uniforms{};  // this frame's copy of the block in `ubo`
    lpv::Placement placement, previous;
    bool havePrevious = false;
    int historyTarget = 0;
    const lpv::Rgb* result = nullptr;  // volume read by lpv.apply
    const lpv::Hi* resultHi = nullptr; // its band-2 part (lpv.sh_order=2)
    const lpv::Rgb* nearResult = nullptr;  // cascades i > 0: the near part read by lpv.apply
    const lpv::Hi* nearResultHi = nullptr;
    int lastStep = 0;                  // step[lastStep] holds the last propagation iteration
    glm::vec4 visibilityFor{0.0f};     // origin (xyz) and cell size (w) the moments were traced for
    std::uint64_t visibilityGeometry = 0;  // GpuScene::geometryVersion they were traced against
    InjectCacheState cache;            // lpv.inject_cache=on with local lights (compute path)
};

struct LpvState {
    std::vector<LpvCascade> cascades;  // finest first; cascades[0] is the single volume when C = 1
    lpv::Rsm rsm;  // the sun's (orthographic, fitted to the coarsest cascade), when there is a sun
    gl::FramebufferHandle rsmFbo;
    bool sunRsm = false;
    // lpv.sun_cache (docs/lpv.md, "Sun injection cache"): what the sun's RSM and packed injection were made
    // from (SunCacheKey), whether `sunPacked` (per cascade) holds them, and whether this frame reuses them.
    struct SunCacheKey {
        glm::mat4 viewProj{0.0f};
        glm::vec3 irradiance{0.0f};
        std::uint64_t geometry = 0;
        int rsm = 0;
        GLenum format = 0;                   // of the volumes the kept copy was packed into
        std::vector<std::uint8_t> uniforms;  // every cascade's uniform block (placement, grid, injection switches)
        bool operator==(const SunCacheKey&) const = default;
    } sunKey;
    bool sunKeyValid = false, sunCached = false, sunCacheable = false;
    bool sunCacheDeclared = false;  // lpv.pack's declare: the scene's sun can be its only injection (no local lights)
    std::vector<lpv::Rgb> sunPacked;
    // Scene::focusBounds() walks every vertex: kept while the geometry stays (GpuScene::geometryVersion).
    Aabb focus;
    std::uint64_t focusGeometry = ~std::uint64_t(0);
    const Scene* focusScene = nullptr;
    // Local-light RSM faces, allocated when the first is drawn: face f is layer f % kRsmArrayLayers
    // of localArrays[f / kRsmArrayLayers] (lpv::rsmArrayDescs), local[f] its state.
    std::vector<lpv::Rsm> localArrays;
    std::vector<LocalRsm> local;  // by fixed face index (LocalLight::firstFace + k)
    std::uint64_t localStorage = 0;  // counts (re)allocations of localArrays (the injection cache's key)
    struct InjectFace {
        int face = 0;
        bool cacheable = false;  // up to date and not drawn this frame (lpv.inject_cache)
    };
    std::vector<InjectFace> injectFaces;  // this frame's injected faces (the lit lights', drawn now or cached)
    int localSize = 0;            // side of the local RSMs (FrameResources::localRsmSize)
    int localDrawn = 0;           // faces drawn this frame
    gl::Buffer faceList;          // lpv.inject's LpvRsmFace entries of this frame
    // lpv.inject's stats of the frame: faces injected (into a volume or a cache, summed over the
    // cascades), faces taken from a cascade's cache, caches rebuilt.
    int facesInjected = 0, facesFromCache = 0, cacheRebuilds = 0;
    VisibilityTarget rsmVis{"lpv.rsm"};  // raster.path=compute
    gl::Buffer stats;
    gl::Texture sumE, sumS;  // apply's running sums over cascades (C > 1)
    gl::Texture lowIndirect, lowSpecular, lowGeometry;  // lpv.apply_resolution=half
    gl::ProgramCache* programs = nullptr;  // for the debug slices made on request
    // Debug slices (made when a debug image is requested, outside the measured frame).
    mutable gl::Texture lightSlice, geometrySlice;
    gl::MemoryLedger* ledger = nullptr;
    lpv::JointVolumes joint;  // lpv.propagate_cascades=joint: the stacked propagation volumes
    lpv::ProbeTracer probe;  // lpv.source=probe (docs/lpv.md, "Stage attribution")
    lpv::SceneBvh visibilityBvh;  // lpv.lookup=visibility
    LpvCascade& first() { return cascades.front(); }
    const LpvCascade& first() const { return cascades.front(); }
};

bool geometryNeeded(const Settings& s) { return s.lpv.occlusion || s.lpv.bounce; }

// lpv.visibility's distance moments: for the lookup.
bool momentsNeeded(const Settings& s) { return s.lpv.lookup == LpvSettings::Lookup::Visibility; }

// lpv.visibility's face openness: for the propagation's blocking (compute path, with occlusion or bounce).
bool facesNeeded(const Settings& s) {
    return s.lpv.blocking == LpvSettings::Blocking::Visibility && s.lpv.path == LpvSettings::Path::Compute &&
           geometryNeeded(s);
}

// lpv.sky_bounce: the G-buffer's sky-lit surfels injected into the volume (compute path, with the
// cells' sky visibility, into a propagated volume; docs/lpv.md, "Sky bounce").
bool skyBounceNeeded(const Settings& s) {
    return s.lpv.skyBounce && s.lpv.sky == LpvSettings::Sky::Visibility && s.lpv.path == LpvSettings::Path::Compute &&
           s.lpv.source == LpvSettings::Source::Propagated;
}

// lpv.sun_cache applies to the frame (compute path, band 1, no sky bounce; whether the sun is its only
// injection is decided per frame by lpv.rsm).
bool sunCacheUsed(const Settings& s) {
    return s.lpv.sunCache && s.lpv.path == LpvSettings::Path::Compute && s.lpv.shOrder == 1 && !skyBounceNeeded(s);
}

// Every cascade's light volumes at its placement's grid (lpv.visibility, the first pass to use a
// cascade's grid, and lpv.inject; idempotent).
void ensureLightVolumes(LpvState& st, FrameContext& ctx) {
    const LpvSettings& ls = ctx.settings.lpv;
    const GLenum format = ls.format == LpvSettings::Format::Rgba32f ? GL_RGBA32F : GL_RGBA16F;
    for (LpvCascade& c : st.cascades) c.volumes.ensureLight(ctx.ledger, c.placement.grid, format, ls.shOrder);
}

// Cascades in use: the raster baseline is the seed's single volume.
int cascadeCount(const LpvSettings& s) { return s.path == LpvSettings::Path::Raster ? 1 : s.cascades; }

// --check entries of one R, G, B volume triple (SH coefficients: signed);
// `volume` picks the triple when the frame runs (it may alternate; nullptr
// before the first frame).
void outputRgb(PassDecl& d, const std::string& name, std::function<const lpv::Rgb*()> volume) {
    for (std::size_t c = 0; c < 3; ++c)
        d.output(name + "." + "rgb"[c], [volume, c]() -> const gl::Texture* {
            const lpv::Rgb* v = volume();
            return v ? &(*v)[c] : nullptr;
        }, Check::signedValues);
}

// lpv.sh_order=2: the band-2 part of a volume (hi r, g, b, last), as outputRgb.
void outputHi(PassDecl& d, const std::string& name, std::function<const lpv::Hi*()> volume) {
    for (std::size_t c = 0; c < 4; ++c)
        d.output(name + "." + (c < 3 ? std::string(1, "rgb"[c]) : std::string("last")),
                 [volume, c]() -> const gl::Texture* {
                     const lpv::Hi* v = volume();
                     return v && (*v)[c] ? &(*v)[c] : nullptr;
                 },
                 Check::signedValues);
}

void outputCascadesHi(PassDecl& d, const LpvState* st, const LpvSettings& s, const std::string& name,
                      std::function<const lpv::Hi*(const LpvCascade&)> pick, int first = 0) {
    if (s.shOrder != 2) return;
    for (int i = first; i < cascadeCount(s); ++i)
        outputHi(d, (i == 0 ? name : name + ".cascade" + std::to_string(i)) + ".hi", [st, i, pick]() -> const lpv::Hi* {
            return std::size_t(i) < st->cascades.size() ? pick(st->cascades[std::size_t(i)]) : nullptr;
        });
}

// The same triple of every cascade: cascade 0 keeps the single-volume name,
// cascade i > 0 adds ".cascade<i>". `pick` chooses the triple of a cascade.
void outputCascadesRgb(PassDecl& d, const LpvState* st, const LpvSettings& s, const std::string& name,
                       std::function<const lpv::Rgb*(const LpvCascade&)> pick, int first = 0) {
    for (int i = first; i < cascadeCount(s); ++i)
        outputRgb(d, i == 0 ? name : name + ".cascade" + std::to_string(i), [st, i, pick]() -> const lpv::Rgb* {
            return std::size_t(i) < st->cascades.size() ? pick(st->cascades[std::size_t(i)]) : nullptr;
        });
}

// The volumes' grid and format for the settings (lpv::placeVolume clamps the grid to >= 1).
glm::ivec3 volumeGrid(const Settings& s) { return glm::max(s.lpv.grid, glm::ivec3(1)); }
GLenum volumeFormat(const Settings& s) { return s.lpv.format == LpvSettings::Format::Rgba32f ? GL_RGBA32F : GL_RGBA16F; }
// `list` once per cascade in [first, cascades) (the memory estimate's privateTextures).
std::vector<gl::NamedTextureDesc> perCascade(const Settings& s, const std::vector<gl::NamedTextureDesc>& list, int first = 0) {
    std::vector<gl::NamedTextureDesc> t;
    for (int i = first; i < cascadeCount(s.lpv); ++i) t.insert(t.end(), list.begin(), list.end());
    return t;
}

class LpvPass : public Pass {
public:
    explicit LpvPass(std::shared_ptr<LpvState> st) : st_(std::move(st)) {}

protected:
    std::shared_ptr<LpvState> st_;
};

// lpv.rsm: places the volume, fills the uniform block, rasterizes the RSM.
class RsmPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.rsm"; }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        st.programs = &ctx.programs;
        st.ledger = &ctx.ledger;
        const LpvSettings& ls = ctx.settings.lpv;
        const int count = cascadeCount(ls);
        if (st.focusScene != &ctx.scene || st.focusGeometry != ctx.gpuScene.geometryVersion()) {
            st.focus = ctx.scene.focusBounds();
            st.focusScene = &ctx.scene;
            st.focusGeometry = ctx.gpuScene.geometryVersion();
        }
        std::vector<lpv::Placement> placements =
            lpv::placeCascades(ls, count, st.focus, ctx.view.position, ctx.view.forward());
        st.cascades.resize(std::size_t(count));
        auto sun = resolveSun(ctx.scene, ctx.settings);
        st.sunRsm = sun.has_value();
        // One sun RSM for every cascade, fitted to the coarsest (it holds the others).
        rsmViewProj_ = orthoLightViewProj(placements.back().box(), sun ? sun->towardSun : glm::vec3(0, 1, 0));
        for (int i = 0; i < count; ++i) {
            LpvCascade& c = st.cascades[std::size_t(i)];
            c.placement = placements[std::size_t(i)];
            lpv::UniformInputs in;
            in.placement = c.placement;
            in.rsmViewProj = rsmViewProj_;
            in.specular = lpvSpecularActive(ctx.scene, ctx.settings);
            in.cascade = i;
            if (count > 1) in.cascades = placements;
            bool compatible = c.havePrevious && lpv::historyCompatible(c.placement, c.previous);
            in.historyValid = compatible && !ctx.view.cut;
            in.shift = compatible ? lpv::temporalShift(c.placement, c.previous) : glm::ivec3(0);
            c.uniforms = lpv::makeUniforms(ls, in);
            if (!c.ubo)
                c.ubo = gl::Buffer(ctx.ledger, i == 0 ? std::string("lpv.uniforms")
                                                      : "lpv.uniforms.cascade" + std::to_string(i),
                                   sizeof(c.uniforms));
            c.ubo.upload(&c.uniforms, sizeof(c.uniforms));
            c.previous = c.placement;
            c.havePrevious = true;
        }

        int n = ls.rsm;
        const bool rsmNew = st.sunRsm && ensureTargets(ctx, st.rsm, st.rsmFbo, "lpv.rsm", n);
        // lpv.sun_cache: the sun is the frame's only injection (no local-light face drawn or injected, no sky
        // bounce); reused when everything the RSM and the packed volume depend on is as when they were made.
        st.sunCacheable = st.sunCacheDeclared && st.sunRsm && ctx.res.localRsmViews.empty() &&
                          ctx.res.localRsmInject.empty();
        LpvState::SunCacheKey key;
        if (st.sunCacheable) {
            key.viewProj = rsmViewProj_;
            key.irradiance = sun->irradiance;
            key.geometry = ctx.gpuScene.geometryVersion();
            key.rsm = n;
            key.format = volumeFormat(ctx.settings);
            for (const LpvCascade& c : st.cascades) {
                gpu::LpvUniforms u = c.uniforms;
                u.temporalShift = glm::ivec4(0);  // the history's re-indexing: the injection does not read it
                const auto* b = reinterpret_cast<const std::uint8_t*>(&u);
                key.uniforms.insert(key.uniforms.end(), b, b + sizeof(u));
            }
        }
        st.sunCached = st.sunCacheable && !rsmNew && st.sunKeyValid && key == st.sunKey;
        if (!st.sunCached) {
            st.sunKeyValid = false;  // valid again once lpv.pack has kept this frame's volume
            st.sunKey = key;
        }
        if (st.sunCached) {
            // The RSM holds this frame's sun view already.
        } else if (st.sunRsm && useComputeRasterLightViews(ctx.settings)) {
            glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, st.first().ubo.id());
            rsmCompute(ctx, rsmViewProj_, n, st.rsm, -1, nullptr, 0.0f);
        } else if (st.sunRsm) {
            const gl::Program& prog =
                ctx.programs.raster("raster/scene.vert", "lpv/rsm.frag", {{"RTGI_LIGHT_VIEW", ""}});
            prog.set(RTGI_RASTER_LOC_LIGHT_VIEW_PROJ, rsmViewProj_);
            glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, st.first().ubo.id());
            rasterizeScene(ctx, prog, st.rsmFbo.id(), {n, n}, 2);
        }
        // Local lights: one perspective RSM per spot light, six per point /
        // area light, at FrameResources::localRsmSize, each a layer of the
        // local RSM arrays; the light budget (render/lights.h LightSchedule)
        // picks the faces drawn this frame, the others keep theirs. lpv.inject
        // injects every face of a lit light into every cascade (issue 13: "and
        // its cascades"), all faces of an array in one dispatch.
        const int ln = ctx.res.localRsmSize;
        st.localSize = ln;
        const auto& draws = ctx.res.localRsmViews;
        const auto& injects = ctx.res.localRsmInject;
        if (!draws.empty()) ensureLocalArrays(ctx, ln, ctx.res.localRsmFaces);
        const gl::Program& local = ctx.programs.raster("raster/scene.vert", "lpv/rsm.frag",
                                                       {{"RTGI_LIGHT_VIEW", ""}, {"RTGI_RSM_LOCAL", ""}});
        for (auto& v : draws) {
            if (std::size_t(v.face) >= st.local.size()) throw std::logic_error("lpv.rsm: local face out of range");
            LocalRsm& r = st.local[std::size_t(v.face)];
            const int layer = v.face % lpv::kRsmArrayLayers;
            lpv::Rsm& array = st.localArrays[std::size_t(v.face / lpv::kRsmArrayLayers)];
            r.viewProj = v.viewProj;
            ++r.generation;
            const gpu::GpuLight& g = ctx.res.localLightsCpu[std::size_t(v.light)];
            glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, st.first().ubo.id());
            if (useComputeRasterLightViews(ctx.settings)) {
                rsmCompute(ctx, v.viewProj, ln, array, layer, &g, v.tanHalfFov);
            } else {
                if (!r.fbo) r.fbo = layerFbo(array, layer, "lpv.rsm.local" + std::to_string(v.face) + ".fbo");
                local.set(RTGI_RASTER_LOC_LIGHT_VIEW_PROJ, v.viewProj);
                glProgramUniform4fv(local.id(), RTGI_LPV_RSM_LOC_LIGHT, 4, &g.positionRange.x);
                local.set(RTGI_LPV_RSM_LOC_FACE, glm::vec2(v.tanHalfFov, float(ln)));
                rasterizeScene(ctx, local, r.fbo.id(), {ln, ln}, 2);
            }
        }
        st.localDrawn = int(draws.size());
        st.injectFaces.clear();
        for (auto& v : injects) {
            if (std::size_t(v.face) >= st.local.size() || st.local[std::size_t(v.face)].generation == 0) continue;
            bool drawnNow = false;
            for (auto& d : draws) drawnNow = drawnNow || d.face == v.face;
            st.injectFaces.push_back({v.face, v.valid && !drawnNow});
        }
        glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, st.first().ubo.id());
    }
    std::vector<std::pair<std::string, double>> stats() override {
        return {{"rsms", double(st_->localDrawn + (st_->sunRsm ? 1 : 0))},
                {"local_injected", double(st_->injectFaces.size())}};
    }
    void declare(PassDecl& d, const Scene& scene, const Settings& s) const override {
        d.output("lpv.rsm.flux", &st_->rsm.flux).output("lpv.rsm.normal", &st_->rsm.normal, Check::signedValues);
        // The local-light faces' flux arrays (every layer; the frame renders the kept lights' faces,
        // the others stay zero).
        const int faces = maxShadowLayers(resolveLocalLights(scene, s));
        for (int c = 0; c * lpv::kRsmArrayLayers < faces; ++c)
            d.output(localArrayLabel(c) + ".flux", [st = st_, c]() -> const gl::Texture* {
                return std::size_t(c) < st->localArrays.size() ? &st->localArrays[std::size_t(c)].flux : nullptr;
            });
        d.debugImage("lpv.rsm.flux", [this] {
            return DebugImage{"lpv.rsm.flux", &st_->rsm.flux, 1.0f / std::max(maxFlux(), 1e-30f)};
        });
        d.debugImage("lpv.rsm.normal", &st_->rsm.normal);
    }

private:
    glm::mat4 rsmViewProj_{1.0f};
    // Label of local RSM array c (the first keeps the short name).
    static std::string localArrayLabel(int c) {
        return c == 0 ? std::string("lpv.rsm.local") : "lpv.rsm.local.array" + std::to_string(c);
    }
    // The local RSM arrays for `faces` faces of side n; on (re)allocation every layer is cleared
    // (an empty texel injects nothing) and every face counts as never drawn.
    void ensureLocalArrays(FrameContext& ctx, int n, int faces) {
        LpvState& st = *st_;
        const int arrays = (faces + lpv::kRsmArrayLayers - 1) / lpv::kRsmArrayLayers;
        bool changed = int(st.localArrays.size()) != arrays;
        st.localArrays.resize(std::size_t(arrays));
        for (int c = 0; c < arrays; ++c) {
            const lpv::RsmDescs d = lpv::rsmArrayDescs(n, std::min(lpv::kRsmArrayLayers, faces - c * lpv::kRsmArrayLayers));
            lpv::Rsm& a = st.localArrays[std::size_t(c)];
            const std::string label = localArrayLabel(c);
            bool fresh = a.flux.ensure(ctx.ledger, label + ".flux", d.flux);
            fresh |= a.normal.ensure(ctx.ledger, label + ".normal", d.normal);
            fresh |= a.depth.ensure(ctx.ledger, label + ".depth", d.depth);
            if (fresh) {
                a.flux.clear();
                a.normal.clear();
                a.depth.clear(1.0f);
            }
            changed |= fresh;
        }
        if (!changed) return;
        st.local.clear();
        st.local.resize(std::size_t(faces));
        ++st.localStorage;
    }
    // Hardware path: a framebuffer drawing into one layer of a local RSM array.
    static gl::FramebufferHandle layerFbo(const lpv::Rsm& a, int layer, const std::string& label) {
        GLuint f = 0;
        glCreateFramebuffers(1, &f);
        gl::FramebufferHandle fbo(f);
        fbo.label(label.c_str());
        glNamedFramebufferTextureLayer(f, GL_COLOR_ATTACHMENT0, a.flux.id(), 0, layer);
        glNamedFramebufferTextureLayer(f, GL_COLOR_ATTACHMENT1, a.normal.id(), 0, layer);
        glNamedFramebufferTextureLayer(f, GL_DEPTH_ATTACHMENT, a.depth.id(), 0, layer);
        const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        glNamedFramebufferDrawBuffers(f, 2, bufs);
        if (glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw std::runtime_error("lpv.rsm: local face framebuffer incomplete");
        return fbo;
    }
    // Compute rasterizer: the light view's visibility buffer (one target for
    // every RSM; rasterizeVisibility orders its clear after the previous
    // reads), a resolve into flux/normal (lpv/rsm.glsl: the sun's texel, or
    // with `local` a spot/point/area face of field tan(half fov)) and the depth
    // copy; `layer` >= 0: into that layer of the arrays of `rsm`.
    void rsmCompute(FrameContext& ctx, const glm::mat4& viewProj, int n, lpv::Rsm& rsm, int layer,
                    const gpu::GpuLight* local, float tanHalfFov) {
        VisibilityTarget& t = st_->rsmVis;
        rasterizeVisibility(ctx.programs, ctx.ledger, ctx.gpuScene, viewProj, {n, n}, t, visibilityOptions(ctx.settings));
        if (!t.checked) {
            t.checkOverflow(name());
            t.checked = true;
        }
        gl::Defines defs = visibilityDefines(t);
        if (local) defs.push_back({"RTGI_RSM_LOCAL", ""});
        const gl::Program& resolve = ctx.programs.compute("visibility/rsm_resolve.comp", defs);
        bindVisibility(resolve, ctx.gpuScene, viewProj, t);
        if (local) {
            glProgramUniform4fv(resolve.id(), RTGI_VISIBILITY_LOC_RSM_LIGHT, 4, &local->positionRange.x);
            resolve.set(RTGI_VISIBILITY_LOC_RSM_FACE, glm::vec2(tanHalfFov, float(n)));
        }
        const GLint l = std::max(layer, 0);  // a single layer (layered = false) of an array
        glBindImageTexture(RTGI_VISIBILITY_IMG_RSM_FLUX, rsm.flux.id(), 0, GL_FALSE, l, GL_WRITE_ONLY, GL_RGBA32F);
        glBindImageTexture(RTGI_VISIBILITY_IMG_RSM_NORMAL, rsm.normal.id(), 0, GL_FALSE, l, GL_WRITE_ONLY, GL_RGBA16F);
        gl::dispatch(resolve, n, n);
        copyVisibilityDepth(ctx.programs, t, rsm.depth, layer);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    // Returns true when a target was (re)allocated.
    static bool ensureTargets(FrameContext& ctx, lpv::Rsm& rsm, gl::FramebufferHandle& fbo, const std::string& label,
                              int n) {
        const lpv::RsmDescs d = lpv::rsmDescs(n);
        bool changed = rsm.flux.ensure(ctx.ledger, label + ".flux", d.flux);
        changed |= rsm.normal.ensure(ctx.ledger, label + ".normal", d.normal);
        changed |= rsm.depth.ensure(ctx.ledger, label + ".depth", d.depth);
        if (!changed && fbo) return changed;
        GLuint f = 0;
        glCreateFramebuffers(1, &f);
        fbo = gl::FramebufferHandle(f);
        fbo.label((label + ".fbo").c_str());
        glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT0, rsm.flux.id(), 0);
        glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT1, rsm.normal.id(), 0);
        glNamedFramebufferTexture(f, GL_DEPTH_ATTACHMENT, rsm.depth.id(), 0);
        const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        glNamedFramebufferDrawBuffers(f, 2, bufs);
        if (glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw std::runtime_error("lpv.rsm: framebuffer incomplete");
        return true;
    }
    float maxFlux() const {
        if (!st_->rsm.flux) return 0.0f;
        FloatImage img = readTexture(st_->rsm.flux);
        float m = 0;
        for (std::size_t i = 0; i < img.data.size(); i += 4)
            m = std::max({m, img.data[i], img.data[i + 1], img.data[i + 2]});
        return m;
    }
};

// lpv.inject: compute injection (fp32 atomics) or the seed's raster method.
class InjectPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.inject"; }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2) const override {
        auto t = perCascade(s, lpv::lightTextures(volumeGrid(s), volumeFormat(s), s.lpv.shOrder));
        if (cacheFor_) {
            auto c = perCascade(s, lpv::injectCacheTextures(volumeGrid(s), s.lpv.shOrder));
            t.insert(t.end(), c.begin(), c.end());
        }
        return t;
    }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        const LpvSettings& ls = ctx.settings.lpv;
        if (!st.stats) {
            st.stats = gl::Buffer(ctx.ledger, "lpv.stats", 2 * sizeof(std::uint32_t));
            st.stats.clearZero();
        }
        st.facesInjected = st.facesFromCache = st.cacheRebuilds = 0;
        // Every RSM of the frame (the sun's and each local-light face) adds
        // into the same accumulation of every cascade.
        ensureLightVolumes(st, ctx);
        if (ls.path == LpvSettings::Path::Raster) {
            injectRasterFrame(ctx);
        } else if (st.sunCached) {
            // lpv.sun_cache: lpv.pack restores the kept volume; the accumulation stays zero, the dropped-texel
            // counter keeps the count of the injection it holds.
        } else {
            const std::uint32_t zero = 0;  // this frame's counter; [1] belongs to the injection cache
            glClearNamedBufferSubData(st.stats.id(), GL_R32UI, 0, sizeof(zero), GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
            injectComputeFrame(ctx);
        }
        glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, st.first().ubo.id());
    }
    std::vector<std::pair<std::string, double>> stats() override {
        if (!st_->stats) return {};
        std::uint32_t dropped[2] = {0, 0};
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // producer: lpv.inject atomics
        st_->stats.download(dropped, sizeof(dropped));
        return {{"dropped_texels", double(dropped[0]) + double(dropped[1])},
                {"local_faces_injected", double(st_->facesInjected)},
                {"local_faces_from_cache", double(st_->facesFromCache)},
                {"cache_rebuilds", double(st_->cacheRebuilds)}};
    }
    // Compute path: the fp32 accumulation (lpv.pack converts it); raster path: step[0] and accum.
    void declare(PassDecl& d, const Scene& scene, const Settings& s) const override {
        const LpvState* st = st_.get();
        if (skyBounceNeeded(s)) d.read(R::linearDepth).read(R::normal).read(R::albedo).read(R::material);
        cacheFor_ = cacheUsed(s, resolveLocalLights(scene, s).faces);
        if (cacheFor_)
            outputCascadesRgb(d, st, s.lpv, "lpv.inject_cache", [](const LpvCascade& c) -> const lpv::Rgb* {
                return c.cache.volume ? &c.cache.volume.rgb : nullptr;
            });
        if (s.lpv.path == LpvSettings::Path::Raster) {
            outputCascadesRgb(d, st, s.lpv, "lpv.step0", [](const LpvCascade& c) { return &c.volumes.step[0]; });
            outputCascadesRgb(d, st, s.lpv, "lpv.accum", [](const LpvCascade& c) { return &c.volumes.accum; });
        } else {
            outputCascadesRgb(d, st, s.lpv, "lpv.inject", [](const LpvCascade& c) { return &c.volumes.inject; });
            if (s.lpv.shOrder == 2)
                for (int i = 0; i < cascadeCount(s.lpv); ++i) {
                    std::string suffix = i == 0 ? "" : ".cascade" + std::to_string(i);
                    outputRgb(d, "lpv.inject_hi" + suffix, [st, i]() -> const lpv::Rgb* {
                        return std::size_t(i) < st->cascades.size() ? &st->cascades[std::size_t(i)].volumes.injectHi
                                                                    : nullptr;
                    });
                    d.output("lpv.inject_last" + suffix, [st, i]() -> const gl::Texture* {
                        return std::size_t(i) < st->cascades.size() ? &st->cascades[std::size_t(i)].volumes.injectLast
                                                                    : nullptr;
                    }, Check::signedValues);
                }
        }
    }

private:
    mutable bool cacheFor_ = false;  // set by declare (the scene's local lights decide)

    // lpv.inject_cache=on, the compute path, local lights and a light budget (with light.budget=0
    // every face is redrawn every frame, so none is ever cacheable).
    static bool cacheUsed(const Settings& s, int localFaces) {
        return s.lpv.injectCache && s.lpv.path == LpvSettings::Path::Compute && localFaces > 0 && s.light.budget > 0;
    }

    // The seed's raster baseline: one draw per RSM and cascade (no batching, no cache).
    void injectRasterFrame(FrameContext& ctx) {
        LpvState& st = *st_;
        const LpvSettings& ls = ctx.settings.lpv;
        for (LpvCascade& c : st.cascades) {
            bool first = true;
            if (st.sunRsm) lpv::injectRaster(ctx.programs, c.ubo, st.rsm, ls.rsm, c.volumes, first), first = false;
            for (const auto& f : st.injectFaces) {
                const LocalRsm& r = st.local[std::size_t(f.face)];
                lpv::injectRasterLayer(ctx.programs, c.ubo, st.localArrays[std::size_t(f.face / lpv::kRsmArrayLayers)],
                                       f.face % lpv::kRsmArrayLayers, glm::inverse(r.viewProj), c.volumes, first);
                first = false;
            }
            if (first) lpv::injectRaster(ctx.programs, c.ubo, st.rsm, 0, c.volumes, true);  // clears only
            st.facesInjected += int(st.injectFaces.size());
        }
    }

    // A run of face-list entries of one RSM array: one dispatch.
    struct Batch {
        int array = 0, first = 0, count = 0;
    };
    // Appends the faces (sorted by array) to `entries`, one batch per array.
    std::vector<Batch> appendBatches(std::vector<gpu::LpvRsmFace>& entries, std::vector<int> faces) const {
        const LpvState& st = *st_;
        std::sort(faces.begin(), faces.end());
        std::vector<Batch> out;
        for (int f : faces) {
            const int array = f / lpv::kRsmArrayLayers;
            if (out.empty() || out.back().array != array) out.push_back({array, int(entries.size()), 0});
            gpu::LpvRsmFace e{};
            e.invViewProj = glm::inverse(st.local[std::size_t(f)].viewProj);
            e.layer = glm::ivec4(f % lpv::kRsmArrayLayers, 0, 0, 0);
            entries.push_back(e);
            ++out.back().count;
        }
        return out;
    }

    // Compute path (docs/lpv.md "Injection", "Injection cache"): per cascade, the local faces
    // that are up to date go through the cascade's cache (added to it once, or all of them again
    // when it no longer matches), the cache is copied into the accumulation, and the sun's RSM and
    // the other local faces (drawn this frame, or stale) are injected on top, one dispatch per RSM
    // array for each list.
    void injectComputeFrame(FrameContext& ctx) {
        LpvState& st = *st_;
        const LpvSettings& ls = ctx.settings.lpv;
        const int faces = int(st.local.size());
        const bool useCache = cacheUsed(ctx.settings, faces);
        std::vector<gpu::LpvRsmFace> entries;
        std::vector<int> dynamicFaces, wanted;
        for (const auto& f : st.injectFaces) (useCache && f.cacheable ? wanted : dynamicFaces).push_back(f.face);
        const std::vector<Batch> dynamic = appendBatches(entries, dynamicFaces);
        // Per cascade: what its cache must add (all wanted faces after a rebuild).
        std::vector<std::vector<Batch>> adds(st.cascades.size());
        std::vector<bool> rebuild(st.cascades.size(), false), cached(st.cascades.size(), false);
        for (std::size_t k = 0; k < st.cascades.size(); ++k) {
            LpvCascade& c = st.cascades[k];
            InjectCacheState& cs = c.cache;
            if (!useCache) {
                cs.volume.reset();
                cs.valid = false;
                continue;
            }
            // Allocated from the first frame with local lights (what the memory estimate counts).
            if (cs.volume.ensure(ctx.ledger, c.placement.grid, ls.shOrder)) cs.valid = false;
            if (wanted.empty()) {  // nothing to keep: the cache is dropped
                cs.valid = false;
                continue;
            }
            InjectCacheKey key;
            key.origin = c.uniforms.origin;
            key.grid = glm::ivec4(glm::ivec3(c.uniforms.grid), st.localSize);
            key.injectSide = c.uniforms.leak.x;
            key.shOrder = ls.shOrder;
            key.storage = st.localStorage;
            key.geometry = ctx.gpuScene.geometryVersion();
            bool again = !cs.valid || !(key == cs.key) || cs.held.size() != std::size_t(faces);
            if (!again) {  // a held face that is no longer wanted, or was drawn again since
                std::vector<char> isWanted(std::size_t(faces), 0);
                for (int f : wanted) isWanted[std::size_t(f)] = 1;
                for (int f = 0; f < faces && !again; ++f)
                    again = cs.held[std::size_t(f)] != 0 &&
                            (!isWanted[std::size_t(f)] || cs.held[std::size_t(f)] != st.local[std::size_t(f)].generation);
            }
            if (again) {
                cs.held.assign(std::size_t(faces), 0);
                cs.heldCount = 0;
                rebuild[k] = true;
                ++st.cacheRebuilds;
            }
            std::vector<int> add;
            for (int f : wanted)
                if (cs.held[std::size_t(f)] == 0) {
                    add.push_back(f);
                    cs.held[std::size_t(f)] = st.local[std::size_t(f)].generation;
                }
            st.facesFromCache += cs.heldCount;
            cs.heldCount += int(add.size());
            cs.key = key;
            cs.valid = true;
            cached[k] = true;
            adds[k] = appendBatches(entries, add);
        }
        if (!entries.empty()) {
            const std::int64_t bytes = std::int64_t(entries.size() * sizeof(gpu::LpvRsmFace));
            const std::int64_t capacity =
                std::int64_t(std::max(1, faces) * (1 + int(st.cascades.size())) * sizeof(gpu::LpvRsmFace));
            st.faceList.ensure(ctx.ledger, "lpv.rsm.local.faces", std::max(capacity, bytes));
            st.faceList.upload(entries.data(), bytes);
        }
        const std::uint32_t zero = 0;
        for (std::size_t k = 0; k < st.cascades.size(); ++k) {
            LpvCascade& c = st.cascades[k];
            const bool coarsest = c.uniforms.cascade.z != 0;  // the cascade that counts dropped texels
            if (cached[k]) {
                if (rebuild[k]) {
                    c.cache.volume.clear();
                    if (coarsest)
                        glClearNamedBufferSubData(st.stats.id(), GL_R32UI, sizeof(zero), sizeof(zero), GL_RED_INTEGER,
                                                  GL_UNSIGNED_INT, &zero);
                }
                for (const Batch& b : adds[k]) {
                    lpv::injectFaces(ctx.programs, c.ubo, st.localArrays[std::size_t(b.array)], st.faceList, b.first,
                                     b.count, c.cache.volume.target(), ls.shOrder, st.stats, 1);
                    st.facesInjected += b.count;
                }
                lpv::copyInjectCache(ctx.programs, c.cache.volume, c.volumes);
            } else if (coarsest) {
                glClearNamedBufferSubData(st.stats.id(), GL_R32UI, sizeof(zero), sizeof(zero), GL_RED_INTEGER,
                                          GL_UNSIGNED_INT, &zero);
            }
            if (st.sunRsm) lpv::injectCompute(ctx.programs, c.ubo, st.rsm, ls.rsm, c.volumes, st.stats);
            if (skyBounceNeeded(ctx.settings)) {
                const GBuffer& g = ctx.res.gbuffer;
                lpv::GBufferView gb{&g.linearDepth, &g.normal, &g.albedo, &g.material, ctx.view.size, ls.geometryStride};
                lpv::injectSky(ctx.programs, c.ubo, gb, c.volumes, momentsNeeded(ctx.settings), ls.visibilityExponent,
                               ls.visibilityViewBias);
            }
            for (const Batch& b : dynamic) {
                lpv::injectFaces(ctx.programs, c.ubo, st.localArrays[std::size_t(b.array)], st.faceList, b.first,
                                 b.count, lpv::injectTarget(c.volumes), ls.shOrder, st.stats, 0);
                st.facesInjected += b.count;
            }
        }
    }
};

// lpv.pack: fp32 accumulation -> propagation format (compute path only).
class PackPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.pack"; }
    void declare(PassDecl& d, const Scene& scene, const Settings& s) const override {
        st_->sunCacheDeclared = false;
        if (s.lpv.path == LpvSettings::Path::Raster)
            return d.skip("lpv.path=raster injects straight into the propagation format");
        st_->sunCacheDeclared =
            sunCacheUsed(s) && resolveSun(scene, s).has_value() && resolveLocalLights(scene, s).faces == 0;
        // pack writes step 0 only; accum is first written by lpv.propagate.
        outputCascadesRgb(d, st_.get(), s.lpv, "lpv.step0", [](const LpvCascade& c) { return &c.volumes.step[0]; });
        outputCascadesHi(d, st_.get(), s.lpv, "lpv.step0", [](const LpvCascade& c) { return &c.volumes.stepHi[0]; });
    }
    // The kept sun volumes, when the scene's sun can be the only injection (declare decides: no local lights).
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2) const override {
        return st_->sunCacheDeclared ? perCascade(s, lpv::sunCacheTextures(volumeGrid(s), volumeFormat(s)))
                            : std::vector<gl::NamedTextureDesc>{};
    }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        st.sunPacked.resize(st.sunCacheable ? st.cascades.size() : 0);  // not cacheable: the kept volumes are freed
        for (std::size_t k = 0; k < st.cascades.size(); ++k) {
            LpvCascade& c = st.cascades[k];
            if (st.sunCached) {
                // Producer: an earlier frame's copy (image stores; barriers since).
                glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
                lpv::copyVolumes(ctx.programs, st.sunPacked[k], c.volumes.step[0], c.placement.grid, c.volumes.format);
                continue;
            }
            lpv::packLight(ctx.programs, c.ubo, c.volumes);
            if (!st.sunCacheable) continue;
            lpv::ensureSunCache(ctx.ledger, st.sunPacked[k], c.placement.grid, c.volumes.format);
            // Producer: lpv.pack's image stores into step 0, read as a texture here.
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
            lpv::copyVolumes(ctx.programs, c.volumes.step[0], st.sunPacked[k], c.placement.grid, c.volumes.format);
        }
        if (st.sunCacheable) st.sunKeyValid = true;
    }
    std::vector<std::pair<std::string, double>> stats() override { return {{"sun_cached", st_->sunCached ? 1.0 : 0.0}}; }
};

// lpv.inject_geometry: blocking potential from the RSM and the G-buffer.
class GeometryPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.inject_geometry"; }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2) const override {
        return perCascade(s, lpv::geometryTextures(volumeGrid(s), volumeFormat(s), s.lpv.blocking == LpvSettings::Blocking::TwoSided));
    }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (!geometryNeeded(s)) return d.skip("lpv.occlusion and lpv.bounce are off");
        d.read(R::linearDepth).read(R::normal).read(R::albedo).read(R::material);
        const LpvState* st = st_.get();
        for (int i = 0; i < cascadeCount(s.lpv); ++i) {
            std::string suffix = i == 0 ? "" : ".cascade" + std::to_string(i);
            auto volumes = [st, i]() -> const lpv::Volumes* {
                return std::size_t(i) < st->cascades.size() ? &st->cascades[std::size_t(i)].volumes : nullptr;
            };
            d.output("lpv.geometry" + suffix, [volumes] { auto v = volumes(); return v ? &v->geometry : nullptr; },
                     Check::signedValues);
            d.output("lpv.geometry_albedo" + suffix,
                     [volumes] { auto v = volumes(); return v ? &v->geometryAlbedo : nullptr; });
        }
        d.debugImage("lpv.geometry.slice", [this] { return geometrySlice(); });
    }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        const GBuffer& g = ctx.res.gbuffer;
        lpv::GBufferView gb{&g.linearDepth, &g.normal, &g.albedo, &g.material, ctx.view.size,
                            ctx.settings.lpv.geometryStride};
        // Blocking potential from the sun's orthographic RSM (its texel areas)
        // and the G-buffer; local lights' perspective RSMs are not used here.
        for (LpvCascade& c : st.cascades) {
            c.volumes.ensureGeometry(ctx.ledger, ctx.settings.lpv.blocking == LpvSettings::Blocking::TwoSided);
            lpv::injectGeometry(ctx.programs, c.ubo, st.rsm, st.sunRsm ? ctx.settings.lpv.rsm : 0, gb, c.volumes);
        }
    }
    DebugImage geometrySlice() const {
        if (st_->cascades.empty()) return {"lpv.geometry.slice", nullptr};
        const lpv::Volumes& v = st_->first().volumes;
        if (!v.geometry || !st_->programs) return {"lpv.geometry.slice", nullptr};
        glm::ivec3 d = v.grid + 1;
        st_->geometrySlice.ensure(*st_->ledger, "lpv.debug.geometry_slice", {GL_TEXTURE_2D, GL_RGBA32F, d.x, d.y});
        const gl::Program& prog = st_->programs->compute("lpv/slice.comp", {{"RTGI_LPV_SLICE_GEOMETRY", ""}});
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);  // producer: lpv.pack (geometry)
        glBindTextureUnit(RTGI_LPV_SLICE_TEX_A, v.geometry.id());
        glBindTextureUnit(RTGI_LPV_SLICE_TEX_B, v.geometryAlbedo.id());
        glBindImageTexture(RTGI_LPV_IMG_SLICE, st_->geometrySlice.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        prog.set(RTGI_LPV_LOC_Z, d.z / 2);
        gl::dispatch(prog, d.x, d.y);
        return {"lpv.geometry.slice", &st_->geometrySlice, 1.0f};
    }
};

// lpv.propagate: all iterations inside one pass scope.
class PropagatePass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.propagate"; }
    // Cascades i > 0 keep their near part (compute path; the raster path has one volume).
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2) const override {
        std::vector<gl::NamedTextureDesc> t = perCascade(s, lpv::nearTextures(volumeGrid(s), volumeFormat(s), s.lpv.shOrder), 1);
        if (joint(s)) {
            auto j = lpv::jointTextures(volumeGrid(s), volumeFormat(s));
            t.insert(t.end(), j.begin(), j.end());
        }
        return t;
    }
    // lpv.propagate_cascades=joint and a configuration it covers (docs/lpv.md, "Joint cascade propagation").
    static bool joint(const Settings& s) {
        // Joint propagation steps every cascade alike: not with lpv.coarse_iterations.
        return s.lpv.jointCascades && s.lpv.path == LpvSettings::Path::Compute &&
               (s.lpv.coarseIterations == 0 || s.lpv.coarseIterations == s.lpv.iterations) &&
               lpv::jointPropagationApplies(cascadeCount(s.lpv), s.lpv.shOrder, s.lpv.fuse, facesNeeded(s));
    }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        const LpvSettings& ls = ctx.settings.lpv;
        // Joint: cascades in groups of kJointCascades, one dispatch per iteration and group
        // (a last group of one cascade propagates alone).
        std::size_t jointEnd = 0;
        if (joint(ctx.settings)) {
            const std::size_t n = st.cascades.size();
            jointEnd = n - n % std::size_t(lpv::kJointCascades);
            if (jointEnd > 0) st.joint.ensure(ctx.ledger, st.first().volumes.grid, st.first().volumes.format);
            for (std::size_t i0 = 0; i0 < jointEnd; i0 += lpv::kJointCascades) {
                std::vector<lpv::Volumes*> vs;
                std::vector<bool> near;
                for (std::size_t i = i0; i < i0 + lpv::kJointCascades; ++i) {
                    if (i > 0) st.cascades[i].volumes.ensureNear(ctx.ledger);
                    vs.push_back(&st.cascades[i].volumes);
                    near.push_back(i > 0);
                }
                const int last = lpv::propagateJoint(ctx.programs, st.cascades[i0].ubo, vs, near, st.joint, ls.iterations);
                for (std::size_t i = i0; i < i0 + lpv::kJointCascades; ++i) st.cascades[i].lastStep = last;
            }
        }
        // The compute cascades propagate interleaved: each round steps every cascade once with one
        // barrier, so the small dispatches of independent volumes can overlap (docs/lpv.md,
        // "Interleaved cascades").
        std::vector<std::pair<std::size_t, lpv::ComputePropagation>> compute;
        compute.reserve(st.cascades.size());
        for (std::size_t i = jointEnd; i < st.cascades.size(); ++i) {
            LpvCascade& c = st.cascades[i];
            if (ls.path == LpvSettings::Path::Raster) {
                c.lastStep = lpv::propagateRaster(ctx.programs, c.ubo, c.volumes, ls.iterations);
            } else {
                // Cascades i > 0 also keep their near part (docs/lpv.md, "Cascades").
                if (i > 0) c.volumes.ensureNear(ctx.ledger);
                const int steps = lpv::cascadeSteps(ls, int(i), int(st.cascades.size()));
                compute.emplace_back(i, lpv::ComputePropagation(ctx.programs, c.ubo, c.volumes, steps, i > 0,
                                                                facesNeeded(ctx.settings), ls.fuse, ls.iterations,
                                                                ls.faceKernel));
            }
        }
        for (bool more = !compute.empty(); more;) {
            more = false;
            bool first = true;
            for (auto& [i, p] : compute) {
                if (p.done()) continue;
                p.step(first);
                first = false;
                more = more || !p.done();
            }
        }
        for (auto& [i, p] : compute) st.cascades[i].lastStep = p.last();
        for (std::size_t i = 0; i < st.cascades.size(); ++i) {
            LpvCascade& c = st.cascades[i];
            c.result = &c.volumes.accum;
            c.resultHi = ls.shOrder == 2 ? &c.volumes.accumHi : nullptr;
            c.nearResult = i > 0 ? &c.volumes.near : nullptr;
            c.nearResultHi = i > 0 && ls.shOrder == 2 ? &c.volumes.nearHi : nullptr;
            // Stage attribution: the path-traced probe volume replaces the propagated one.
            if (ls.source == LpvSettings::Source::Probe) st.probe.fill(ctx, c.ubo, c.volumes, i > 0);
        }
    }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        const LpvState* st = st_.get();
        outputCascadesRgb(d, st, s.lpv, "lpv.accum", [](const LpvCascade& c) { return &c.volumes.accum; });
        outputCascadesRgb(d, st, s.lpv, "lpv.last_step",
                          [](const LpvCascade& c) { return &c.volumes.step[std::size_t(c.lastStep)]; });
        // Cascades i > 0 keep their near part (compute path; docs/lpv.md, "Cascades").
        if (s.lpv.path == LpvSettings::Path::Compute)
            outputCascadesRgb(d, st, s.lpv, "lpv.near", [](const LpvCascade& c) { return &c.volumes.near; }, 1);
        outputCascadesHi(d, st, s.lpv, "lpv.accum", [](const LpvCascade& c) { return &c.volumes.accumHi; });
        outputCascadesHi(d, st, s.lpv, "lpv.last_step",
                         [](const LpvCascade& c) { return &c.volumes.stepHi[std::size_t(c.lastStep)]; });
        outputCascadesHi(d, st, s.lpv, "lpv.near", [](const LpvCascade& c) { return &c.volumes.nearHi; }, 1);
        d.debugImage("lpv.volume.slice", [this] { return lightSlice(); });
    }
    DebugImage lightSlice() const {
        if (st_->cascades.empty()) return {"lpv.volume.slice", nullptr};
        const lpv::Volumes& v = st_->first().volumes;
        if (!st_->first().result || !st_->programs) return {"lpv.volume.slice", nullptr};
        st_->lightSlice.ensure(*st_->ledger, "lpv.debug.light_slice", {GL_TEXTURE_2D, GL_RGBA32F, v.grid.x, v.grid.y});
        const gl::Program& prog = st_->programs->compute("lpv/slice.comp");
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);  // producer: lpv.propagate / lpv.temporal
        const lpv::Rgb& r = *st_->first().result;
        for (GLuint c = 0; c < 3; ++c) glBindTextureUnit(RTGI_LPV_SLICE_TEX_A + c, r[c].id());
        glBindImageTexture(RTGI_LPV_IMG_SLICE, st_->lightSlice.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        prog.set(RTGI_LPV_LOC_Z, v.grid.z / 2);
        gl::dispatch(prog, v.grid.x, v.grid.y);
        FloatImage img = readTexture(st_->lightSlice);
        float m = 0;
        for (std::size_t i = 0; i < img.data.size(); i += 4)
            m = std::max({m, img.data[i], img.data[i + 1], img.data[i + 2]});
        return {"lpv.volume.slice", &st_->lightSlice, m > 0 ? 1.0f / m : 1.0f};
    }
};

// lpv.temporal: blend with the previous volume, re-indexed by the cell shift.
class TemporalPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.temporal"; }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2) const override {
        auto t = perCascade(s, lpv::historyTextures(volumeGrid(s), volumeFormat(s), s.lpv.shOrder, false));
        auto near = perCascade(s, lpv::historyTextures(volumeGrid(s), volumeFormat(s), s.lpv.shOrder, true), 1);
        t.insert(t.end(), near.begin(), near.end());
        return t;
    }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        if (s.lpv.temporal <= 0.0f) return d.skip("lpv.temporal = 0");
        const LpvState* st = st_.get();
        outputRgb(d, "lpv.history", [st]() -> const lpv::Rgb* {
            if (st->cascades.empty()) return nullptr;
            const LpvCascade& c = st->cascades.front();
            return &c.volumes.history[std::size_t(c.historyTarget)];
        });
        if (s.lpv.shOrder == 2)
            outputHi(d, "lpv.history.hi", [st]() -> const lpv::Hi* {
                if (st->cascades.empty()) return nullptr;
                const LpvCascade& c = st->cascades.front();
                return &c.volumes.historyHi[std::size_t(c.historyTarget)];
            });
    }
    // Every cascade blends its whole volume with its own history, re-indexed by
    // its own cell shift (each cascade snaps to its own cells); cascades i > 0
    // blend their near part the same way, so the apply's near / far split is a
    // split of the blended volume.
    void execute(FrameContext& ctx) override {
        for (std::size_t i = 0; i < st_->cascades.size(); ++i) {
            LpvCascade& c = st_->cascades[i];
            c.volumes.ensureHistory(ctx.ledger);
            c.historyTarget = 1 - c.historyTarget;
            const auto t = std::size_t(c.historyTarget);
            lpv::temporalBlend(ctx.programs, c.ubo, c.volumes, c.historyTarget);
            c.result = &c.volumes.history[t];
            if (c.resultHi) c.resultHi = &c.volumes.historyHi[t];
            if (i > 0) {
                c.volumes.ensureNearHistory(ctx.ledger);
                lpv::temporalBlendNear(ctx.programs, c.ubo, c.volumes, c.historyTarget);
                c.nearResult = &c.volumes.nearHistory[t];
                if (c.nearResultHi) c.nearResultHi = &c.volumes.nearHistoryHi[t];
            }
        }
    }
};

// lpv.visibility (lpv.lookup=visibility, lpv.sky=visibility; docs/lpv.md, "Visibility moments",
// "Sky visibility"): each cascade's per-cell distance moments and sky visibility, traced against the
// scene's BVH when the cascade was placed elsewhere, first allocated or the geometry moved (issue 23);
// otherwise nothing runs.
class VisibilityPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.visibility"; }
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2) const override {
        std::vector<gl::NamedTextureDesc> t;
        if (momentsNeeded(s)) t.push_back(lpv::visibilityTexture(volumeGrid(s)));
        if (s.lpv.sky == LpvSettings::Sky::Visibility) t.push_back(lpv::skyTexture(volumeGrid(s)));
        if (facesNeeded(s)) t.push_back(lpv::faceTexture(volumeGrid(s)));
        return perCascade(s, t);
    }
    void declare(PassDecl& d, const Scene&, const Settings& s) const override {
        const bool moments = momentsNeeded(s), sky = s.lpv.sky == LpvSettings::Sky::Visibility, faces = facesNeeded(s);
        if (!moments && !sky && !faces) return d.skip("neither lpv.lookup, lpv.blocking nor lpv.sky is visibility");
        const LpvState* st = st_.get();
        for (int i = 0; i < cascadeCount(s.lpv); ++i) {
            const std::string suffix = i == 0 ? "" : ".cascade" + std::to_string(i);
            if (moments)
                d.output("lpv.visibility" + suffix, [st, i]() -> const gl::Texture* {
                    return std::size_t(i) < st->cascades.size() ? &st->cascades[std::size_t(i)].volumes.visibility : nullptr;
                });
            if (faces)
                d.output("lpv.face_visibility" + suffix, [st, i]() -> const gl::Texture* {
                    return std::size_t(i) < st->cascades.size() ? &st->cascades[std::size_t(i)].volumes.faces : nullptr;
                });
            if (sky)
                d.output("lpv.sky_visibility" + suffix, [st, i]() -> const gl::Texture* {
                    return std::size_t(i) < st->cascades.size() ? &st->cascades[std::size_t(i)].volumes.sky : nullptr;
                }, Check::signedValues);
        }
    }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        const bool moments = momentsNeeded(ctx.settings);
        const bool sky = ctx.settings.lpv.sky == LpvSettings::Sky::Visibility;
        const bool faces = facesNeeded(ctx.settings);
        ensureLightVolumes(st, ctx);
        for (LpvCascade& c : st.cascades) {
            const glm::vec4 placed = c.uniforms.origin;
            bool fresh = moments && c.volumes.ensureVisibility(ctx.ledger);
            fresh = (sky && c.volumes.ensureSky(ctx.ledger)) || fresh;
            fresh = (faces && c.volumes.ensureFaces(ctx.ledger)) || fresh;
            const std::uint64_t geometry = ctx.gpuScene.geometryVersion();
            if (!fresh && placed == c.visibilityFor && geometry == c.visibilityGeometry) continue;
            st.visibilityBvh.ensure(ctx, "lpv.visibility.bvh");
            if (moments) lpv::visibilityMoments(ctx, c.ubo, st.visibilityBvh, c.volumes);
            if (sky) lpv::skyVisibility(ctx, c.ubo, st.visibilityBvh, c.volumes);
            if (faces) lpv::faceVisibility(ctx, c.ubo, st.visibilityBvh, c.volumes);
            c.visibilityFor = placed;
            c.visibilityGeometry = geometry;
        }
    }
};

// lpv.apply: indirect diffuse (+ specular) radiance from the volume.
class ApplyPass final : public LpvPass {
public:
    using LpvPass::LpvPass;
    std::string name() const override { return "lpv.apply"; }
    // The running sums over cascades (C > 1).
    std::vector<gl::NamedTextureDesc> privateTextures(const Settings& s, glm::ivec2 view) const override {
        std::vector<gl::NamedTextureDesc> t;
        const bool half = s.lpv.halfApply;
        const glm::ivec2 applySize = half ? lpv::applyHalfSize(view) : view;
        if (half) {
            t.push_back({"lpv.apply.low_indirect", lpv::applyLowDesc(view)});
            if (specularFor_) t.push_back({"lpv.apply.low_specular", lpv::applyLowDesc(view)});
            t.push_back({"lpv.apply.low_geometry", lpv::applyLowGeometryDesc(view)});
        }
        if (cascadeCount(s.lpv) > 1) {
            t.push_back({"lpv.apply.sum_irradiance", lpv::applySumDesc(applySize)});
            t.push_back({"lpv.apply.sum_specular", lpv::applySumDesc(applySize)});
        }
        return t;
    }
    void declare(PassDecl& d, const Scene& scene, const Settings& s) const override {
        d.read(R::linearDepth).read(R::normal).read(R::albedo).read(R::material);
        d.readIfWritten(R::bentNormal).readIfWritten(R::s3ho);  // directional occlusion of the lookup
        d.write(R::indirectDiffuse);
        specularFor_ = lpvSpecularActive(scene, s);  // privateTextures' low specular target
        if (specularFor_) d.read(R::brdfLut).write(R::specular);
    }
    void execute(FrameContext& ctx) override {
        LpvState& st = *st_;
        FrameResources& r = ctx.res;
        const glm::ivec2 s = ctx.view.size;
        bool specular = lpvSpecularActive(ctx.scene, ctx.settings);
        const int count = int(st.cascades.size());
        // lpv.apply_resolution=half: the cascades' dispatches run at half resolution into the
        // low targets, lpv/upsample.comp writes the frame's outputs.
        const bool half = ctx.settings.lpv.halfApply;
        const glm::ivec2 applySize = half ? lpv::applyHalfSize(s) : s;
        if (half) {
            st.lowIndirect.ensure(ctx.ledger, "lpv.apply.low_indirect", lpv::applyLowDesc(s));
            if (specular) st.lowSpecular.ensure(ctx.ledger, "lpv.apply.low_specular", lpv::applyLowDesc(s));
            st.lowGeometry.ensure(ctx.ledger, "lpv.apply.low_geometry", lpv::applyLowGeometryDesc(s));
        }
        if (count > 1) {
            st.sumE.ensure(ctx.ledger, "lpv.apply.sum_irradiance", lpv::applySumDesc(applySize));
            st.sumS.ensure(ctx.ledger, "lpv.apply.sum_specular", lpv::applySumDesc(applySize));
        }
        for (int i = 0; i < count; ++i) {
            const LpvCascade& c = st.cascades[std::size_t(i)];
            lpv::ApplyInputs in;
            in.gbuffer = {&r.gbuffer.linearDepth, &r.gbuffer.normal, &r.gbuffer.albedo, &r.gbuffer.material, s};
            in.volume = c.result;
            in.volumeHi = c.resultHi;
            in.nearHi = i > 0 && c.resultHi ? c.nearResultHi : nullptr;
            in.brdfLut = specular ? &r.brdfLut : nullptr;
            in.s3ho = ctx.has(R::s3ho) ? &r.s3ho : nullptr;
            in.bentNormal = ctx.has(R::bentNormal) ? &r.bentNormal : nullptr;
            in.indirect = half ? &st.lowIndirect : &r.indirectDiffuse;
            in.specular = specular ? (half ? &st.lowSpecular : &r.specular) : nullptr;
            in.lowGeometry = half ? &st.lowGeometry : nullptr;
            in.cascade = i;
            in.cascades = count;
            in.near = i > 0 ? c.nearResult : nullptr;
            // The self-illumination correction undoes an artefact of the propagation;
            // a probe volume (lpv.source=probe) has none to undo.
            // Without a sun there is no orthographic RSM to read the exitance from.
            in.rsm = ctx.settings.lpv.selfCorrection && st.sunRsm &&
                             ctx.settings.lpv.source == LpvSettings::Source::Propagated
                         ? &st.rsm
                         : nullptr;
            in.sumE = &st.sumE;
            in.sumS = &st.sumS;
            // The geometry volume exists only with occlusion or bounce: without it lpv.lookup=geometry
            // is the plain trilinear lookup (docs/lpv.md, "Leaks"). It also applies to lpv.source=probe.
            in.geometry = ctx.settings.lpv.lookup == LpvSettings::Lookup::Geometry && geometryNeeded(ctx.settings)
                              ? &c.volumes.geometry
                              : nullptr;
            in.geometryAxes = in.geometry && c.volumes.geometryAxes ? &c.volumes.geometryAxes : nullptr;
            in.visibility =
                ctx.settings.lpv.lookup == LpvSettings::Lookup::Visibility ? &c.volumes.visibility : nullptr;
            in.sky = ctx.settings.lpv.sky == LpvSettings::Sky::Visibility ? &c.volumes.sky : nullptr;
            in.skySelf = skyBounceNeeded(ctx.settings) && ctx.settings.lpv.selfCorrection;
            in.visibilityExponent = ctx.settings.lpv.visibilityExponent;
            in.visibilityViewBias = ctx.settings.lpv.visibilityViewBias;
            in.damping = ctx.settings.lpv.damping;
            lpv::applyCompute(ctx.programs, c.ubo, in);
        }
        if (half) {
            lpv::UpsampleInputs up;
            up.gbuffer = {&r.gbuffer.linearDepth, &r.gbuffer.normal, &r.gbuffer.albedo, &r.gbuffer.material, s};
            up.lowIndirect = &st.lowIndirect;
            up.lowSpecular = specular ? &st.lowSpecular : nullptr;
            up.lowGeometry = &st.lowGeometry;
            up.brdfLut = specular ? &r.brdfLut : nullptr;
            up.indirect = &r.indirectDiffuse;
            up.specular = specular ? &r.specular : nullptr;
            lpv::applyUpsample(ctx.programs, st.first().ubo, up);
        }
    }

private:
    mutable bool specularFor_ = false;  // set by declare (the scene decides)
};

}  // namespace

void appendLpvPasses(std::vector<std::unique_ptr<Pass>>& f) {
    auto st = std::make_shared<LpvState>();
    f.push_back(std::make_unique<RsmPass>(st));        // reflective shadow map fitted to the volume
    f.push_back(std::make_unique<VisibilityPass>(st)); // per-cell distance moments and sky visibility (BVH rays)
    f.push_back(std::make_unique<InjectPass>(st));     // RSM texels (and sky-lit G-buffer surfels) -> SH
    f.push_back(std::make_unique<PackPass>(st));       // fp32 -> lpv.format (compute path)
    f.push_back(std::make_unique<GeometryPass>(st));   // blocking potential (occlusion, bounce)
    f.push_back(std::make_unique<PropagatePass>(st));  // iterations, fused accumulation
    f.push_back(std::make_unique<TemporalPass>(st));   // blend with the re-indexed previous volume
    f.push_back(std::make_unique<ApplyPass>(st));      // indirect diffuse + specular radiance
}

void validateLpvSettings(const Scene&, const Settings& s) {
    if (s.lpv.shOrder == 2 && s.lpv.path == LpvSettings::Path::Raster)
        throw ConfigError("lpv.sh_order=2 needs lpv.path=compute: the raster baseline is the seed's band-1 method");
}

Need lpvFamily(const Scene& scene, const Settings& s) {
    if (s.lpv.mode == Toggle::Off) return Need::no("lpv=off");
    if (!lpvActive(scene, s))
        return Need::no("the scene has no light: no sun, no point, spot or emissive-region light and no sky with "
                        "lpv.sky_bounce (no RSM, no LPV)");
    return Need::yes();
}

bool lpvActive(const Scene& scene, const Settings& s) {
    if (s.lpv.mode == Toggle::Off) return false;
    if (resolveSun(scene, s).has_value() || hasLocalLights(scene, s)) return true;
    // The sky alone, reflected into the volume (lpv.sky_bounce), is light to propagate too.
    const glm::vec3 sky = resolveSky(scene, s);
    return skyBounceNeeded(s) && std::max({sky.x, sky.y, sky.z}) > 0.0f;
}

bool lpvCoarseStepsUsed(const Scene& scene, const Settings& s) {
    return cascadeCount(s.lpv) > 1 && lpvActive(scene, s);
}

bool lpvSpecularActive(const Scene& scene, const Settings& s) {
    if (!lpvActive(scene, s) || s.lpv.specular == Toggle::Off) return false;
    if (s.lpv.specular == Toggle::On) return true;
    return resolveMaterials(scene, s).size() && scene.minRoughness() <= s.ssr.roughnessCutoff;
}

}  // namespace rtgi
