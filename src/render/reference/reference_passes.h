#pragma once
// In-framework ray-traced reference (SPEC 7): ref.bvh_upload builds the BVH
// over the scene, ref.ao traces AO rays and ref.path traces paths from the
// G-buffer surface, progressively, until reference.spp samples per pixel.
// A finished reference is cached on disk (reference_cache.h) and traced
// again only when the view changes.
#include "gl/image_io.h"
#include "gl/program.h"
#include "render/pass.h"
#include "render/reference/convergence.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <vector>

namespace rtgi {

void appendReferencePasses(std::vector<std::unique_ptr<Pass>>& frame);
// Whether the ref.* passes run (reference != off).
Need referenceFamily(const Scene& scene, const Settings& settings);

// GPU constants of the reference (the one pure function of this family).
struct ReferenceConstants {
    ReferenceSettings::Kind kind = ReferenceSettings::Kind::Off;
    int spp = 256;
    int samplesPerDispatch = 16;  // progressive chunks keep every dispatch short (no GPU watchdog)
    unsigned seed = 1;
    int bounces = 4;              // bounces after the G-buffer surface
    float rayLength = 0.5f;       // AO: maximum ray length = ao.radius of the compared configuration
    bool diffuseOnly = false;     // reference.specular=off
    bool lightSampling = true;    // reference.light_sampling: emitter NEE + MIS (when the scene has emitters)
    bool emissionIsDirect = true; // emissive.lights: emission seen from x1 belongs to the direct pass
    ReferenceSettings::Caustics caustics = ReferenceSettings::Caustics::Regularized;
    float causticRoughness = 0.3f;
    bool converging = false;      // traced to a noise target: spp is what it took, not part of the cache key
    // RTGI_REF_FULL / RTGI_REF_DIFFUSE_ONLY / RTGI_REF_EMITTER_NEE /
    // RTGI_REF_CAUSTICS_* for ref/path.comp (emitter NEE only when `haveEmitters`).
    gl::Defines defines(bool haveEmitters = false) const;
};
ReferenceConstants referenceConstants(const Settings& settings, const Aabb& sceneBounds);

// What a tracing pass exposes to the benchmark driver and the tests.
class ReferenceOutput {
public:
    virtual ~ReferenceOutput() = default;
    virtual const gl::Texture& mean() const = 0;           // RGBA32F: AO in rgb, or radiance
    virtual const gl::Texture& standardError() const = 0;  // RGBA32F: per-channel standard error of the mean
    virtual bool fromCache() const = 0;
    virtual std::string cacheKey() const = 0;
    // Progressive mode (rtgi-view's live comparison): each frame adds
    // `samplesPerFrame` samples (up to reference.spp) to the running
    // accumulation and resolves mean and standard error of what it has; a new
    // view or size restarts it. No cache. 0 = the normal all-at-once trace.
    virtual void setProgressive(int samplesPerFrame) = 0;
    virtual int samplesDone() const = 0;
    // Converging mode (reference.target_noise / target_stderr): after each
    // batch `measure` gets the reference so far (mean, standard error) and
    // returns the check's noise and error (ConvergenceCheck: spp and seconds
    // are filled in by the pass); planConvergence decides whether to stop and
    // how many samples to add. A cached reference of the same scene, view and
    // settings is resumed (its samples kept) or, when it meets the target,
    // used as it is. Set before the first render.
    using Measure = std::function<ConvergenceCheck(const FloatImage& mean, const FloatImage& standardError)>;
    virtual void setConvergence(Measure measure) = 0;
    // What the converging trace did (spp, seconds, noise, target, stop reason,
    // checks); empty when it did not converge to a target.
    virtual nlohmann::json convergenceInfo() const = 0;
};

}  // namespace rtgi
