#pragma once
// The renderer shared by rtgi-bench, the tests and rtgi-view: owns the GPU
// scene, the program cache, the memory ledger and the frame (a list of
// passes built by the frame script in frame.cpp from scene + settings).
#include "render/lights.h"
#include "gl/profiler.h"
#include "gl/program.h"
#include "gl/resources.h"
#include "render/gpu_scene.h"
#include "render/frame_plan.h"
#include "render/pass.h"
#include "scene/enclosure.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rtgi {

// The frame script: every candidate pass in execution order, and the
// families that decide whether their passes run (frame.cpp).
std::vector<std::unique_ptr<Pass>> frameScript();
std::vector<Family> frameFamilies();

// Result of a finite check over one pass output (--check).
struct FiniteCount {
    std::string pass, resource;
    std::uint64_t nan = 0, inf = 0, negative = 0, fp16Saturated = 0;
};

class Renderer {
public:
    Renderer(const Scene& scene, const Settings& settings, gl::Profiler& profiler);
    ~Renderer();
    // Rebuilds the pass list for new settings (keeps the GPU scene unless a
    // setting baked into it changed).
    void configure(const Settings& settings);
    void render(const View& view);
    // A moving scene (issue 23): the scene's state at the next frame's time
    // (same vertex and light counts; vertices, lights and cameras may move).
    // Rewrites the vertex buffer when a vertex moved, the lights when one
    // changed; lastSceneUpdate() says what and how long it took (CPU + upload).
    // A state with rigid motions (Scene::motions, from evaluateScene) of this
    // renderer's rest scene moves its objects by transforms instead
    // (GpuScene::setTransforms): only their matrices are uploaded.
    void updateScene(const Scene& state);
    struct SceneUpdate {
        bool geometry = false, lights = false;
        bool transforms = false;  // the geometry moved by per-object transforms (no vertex upload)
        double ms = 0;
        std::int64_t uploadedBytes = 0;  // buffer uploads of this update (vertices, transforms, lights)
    };
    const SceneUpdate& lastSceneUpdate() const { return sceneUpdate_; }

    const std::vector<std::unique_ptr<Pass>>& passes() const { return plan_.passes(); }
    // The plan's skipped passes, then the local lights left out ("light:<name>").
    const std::vector<SkippedPass>& skipped() const { return skipped_; }
    const FramePlan& plan() const { return plan_; }
    const LocalLights& localLights() const { return localLights_; }
    // Of the last frame: local lights culled (outside the view / zero) and shadowed.
    int localLightsCulled() const { return localCulled_; }
    int localLightsShadowed() const { return localShadowed_; }
    // Hooks for dynamic scenes (the light budget's cache, render/lights.h
    // LightSchedule): a local light moved or changed (index into
    // localLights().lights; setLocalLight replaces it and calls lightChanged),
    // or the geometry moved (every cached shadow map and RSM becomes stale).
    void lightChanged(int light) { lightSchedule_.lightChanged(light); }
    void setLocalLight(int light, const LocalLight& l);
    void geometryChanged() { lightSchedule_.invalidateAll(); }
    // Configuration warnings (emissive.max_lights, the shadow array's layer
    // limit): rtgi-bench prints them and lists them in results.json "warnings".
    const std::vector<std::string>& warnings() const { return localLights_.warnings; }
    Pass* findPass(const std::string& name) const;
    // From the pass's declaration: its shared writes and private outputs
    // (--check), and its private debug images (made on request, outside the measured frame).
    struct Output {
        std::string name;  // "pass:resource"
        const gl::Texture* tex;
        Check check;
    };
    std::vector<Output> checkedOutputs(const Pass& pass) const;
    std::vector<DebugImage> debugImages(const Pass& pass) const;
    // The descriptor the renderer allocates shared resource r from for a view
    // of `viewSize` (the memory estimate counts the same descriptors).
    gl::TextureDesc sharedTextureDesc(Resource r, glm::ivec2 viewSize) const;
    FrameResources& resources() { return res_; }
    const FrameResources& resources() const { return res_; }
    const Scene& scene() const { return scene_; }
    const GpuScene& gpuScene() const { return *gpuScene_; }
    // The settings in effect: those given to configure() with lpv.coarse_iterations=auto resolved for
    // this scene (docs/lpv.md, "Closed scenes").
    const Settings& settings() const { return settings_; }
    // How closed the scene is (measured on the pose the renderer was built with, once, when
    // lpv.coarse_iterations=auto first needs it); nullopt while nothing asked.
    const std::optional<Enclosure>& enclosure() const { return enclosure_; }
    gl::MemoryLedger& ledger() { return ledger_; }
    gl::ProgramCache& programs() { return programs_; }
    gl::Profiler& profiler() { return profiler_; }

    // --check: count NaN/Inf/negative/fp16-saturated values in every pass's
    // written textures after each frame's pass (costly; off by default).
    void setCheck(bool on) { check_ = on; }
    const std::vector<FiniteCount>& finiteCounts() const { return finite_; }

private:
    void uploadFrameUniforms(const View& view);
    void resolveLights();
    void resolveSceneAutos();
    void allocateShared(const View& view);
    void checkOutputs(const Pass& pass);
    int indexOf(const Pass& pass) const;

    Scene scene_;
    Settings settings_;
    std::optional<Enclosure> enclosure_;
    gl::Profiler& profiler_;
    gl::MemoryLedger ledger_;
    gl::ProgramCache programs_;
    std::unique_ptr<GpuScene> gpuScene_;
    gl::Buffer frameUbo_;
    FrameResources res_;
    FramePlan plan_;
    std::vector<SkippedPass> skipped_;
    // Per shared resource: written in the previous frame / holds that value now.
    bool writtenLastFrame_[R::count] = {};
    bool previousValid_[R::count] = {};
    LocalLights localLights_;  // point/spot/area lights of the real-time path
    LightSchedule lightSchedule_;
    int localCulled_ = 0, localShadowed_ = 0;
    bool check_ = false;
    SceneUpdate sceneUpdate_;
    // The scene's vertices before its first geometry change (the rest pose the
    // transform path moves; empty in a static scene).
    std::vector<Vertex> restVertices_;
    std::vector<FiniteCount> finite_;
};

// Counts NaN, Inf, negative (unless allowed) and |x| >= 65504 values over all
// texels/channels of a float texture (the --check reduction).
FiniteCount countNonFinite(gl::ProgramCache& programs, gl::MemoryLedger& ledger, const gl::Texture& tex,
                           bool mayBeNegative);

// Every shared texture of FrameResources with its name (the viewer's image list).
std::vector<std::pair<std::string, const gl::Texture*>> namedResources(const FrameResources& res);

}  // namespace rtgi
