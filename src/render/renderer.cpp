#include "render/renderer.h"

#include "render/passes/core_passes.h"
#include "compute/lib/post_shared.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <set>
#include <sstream>

namespace rtgi {

std::vector<std::pair<std::string, const gl::Texture*>> namedResources(const FrameResources& r) {
    const GBuffer& g = r.gbuffer;
    return {
        {"gbuffer.depth", &g.depth},       {"gbuffer.linearDepth", &g.linearDepth},
        {"gbuffer.normal", &g.normal},     {"gbuffer.albedo", &g.albedo},
        {"gbuffer.material", &g.material}, {"gbuffer.emissive", &g.emissive},
        {"gbuffer.velocity", &g.velocity}, {"shadowMap", &r.shadowMap},
        {"direct", &r.direct},             {"indirectDiffuse", &r.indirectDiffuse},
        {"specular", &r.specular},         {"ao", &r.ao},
        {"bentNormal", &r.bentNormal},     {"s3ho", &r.s3ho},
        {"specularOcclusion", &r.specularOcclusion},
        {"hdr", &r.hdr},                   {"ldr", &r.ldr},
        {"history", &r.history},           {"diffuseHistory", &r.diffuseHistory},
    };
}

const gl::Texture* findResource(const FrameResources& r, const std::string& n) {
    for (auto& [name, tex] : namedResources(r))
        if (n == name) return tex;
    return nullptr;
}

std::vector<Pass::Output> Pass::checkedOutputs(const FrameResources& res) const {
    std::vector<Output> out;
    for (auto& w : writes()) {
        const gl::Texture* t = findResource(res, w);
        if (!t || !*t) continue;
        if (w == "gbuffer.depth" || w == "shadowMap" || w == "ldr") continue;  // depth / unorm: cannot be non-finite
        bool signedData = w == "gbuffer.normal" || w == "gbuffer.velocity" || w == "bentNormal" || w == "s3ho";
        out.push_back({name() + ":" + w, t, signedData});
    }
    return out;
}

Renderer::Renderer(const Scene& scene, const Settings& settings, gl::Profiler& profiler)
    : scene_(scene), profiler_(profiler) {
    frameUbo_ = gl::Buffer(ledger_, "frame.uniforms", sizeof(gpu::FrameUniforms), nullptr, GL_DYNAMIC_STORAGE_BIT);
    configure(settings);
}

Renderer::~Renderer() = default;

Pass* Renderer::findPass(const std::string& name) const {
    for (auto& p : passes_)
        if (p->name() == name) return p.get();
    return nullptr;
}

void Renderer::configure(const Settings& settings) {
    bool sceneChanged = !gpuScene_ || settings.light.emissiveScale != settings_.light.emissiveScale ||
                        settings.floorRoughness != settings_.floorRoughness;
    settings_ = settings;
    passes_.clear();
    skipped_.clear();
    finite_.clear();  // --check counts belong to one configuration
    res_ = FrameResources{};  // release everything; passes re-create what they need
    if (sceneChanged) gpuScene_ = std::make_unique<GpuScene>(ledger_, scene_, settings_);

    std::set<std::string> forcedOff;
    {
        std::stringstream ss(settings_.post.passesOff);
        std::string n;
        while (std::getline(ss, n, ','))
            if (!n.empty()) forcedOff.insert(n);
    }
    std::set<std::string> written, knownNames;
    for (auto& pass : frameScript()) {
        std::string n = pass->name();
        knownNames.insert(n);
        if (forcedOff.count(n)) {
            skipped_.push_back({n, "forced off by passes.off"});
            continue;
        }
        Need need = pass->needed(scene_, settings_);
        if (!need.needed) {
            skipped_.push_back({n, need.reason});
            continue;
        }
        for (auto& r : pass->reads())
            if (!written.count(r) && r != "history")
                throw ConfigError("pass '" + n + "' reads '" + r +
                                  "', which no earlier pass in this frame writes (is its producer forced off?)");
        for (auto& w : pass->writes()) written.insert(w);
        passes_.push_back(std::move(pass));
    }
    for (auto& n : forcedOff)
        if (!knownNames.count(n)) throw ConfigError("setting 'passes.off': there is no pass named '" + n + "'");

    // A technique the user asked for explicitly must run, or say why not.
    auto requireFamily = [&](bool requested, const std::string& family, const std::string& key) {
        if (!requested) return;
        for (auto& p : passes_)
            if (p->name().rfind(family, 0) == 0) return;
        std::string why;
        for (auto& s : skipped_)
            if (s.name.rfind(family, 0) == 0) {
                why = s.reason;
                break;
            }
        throw ConfigError("setting '" + key + "': requested, but " +
                          (why.empty() ? std::string("this build has no such passes") : why));
    };
    requireFamily(settings_.lpv.mode == Toggle::On, "lpv.", "lpv");
    requireFamily(settings_.ao.variant != AoSettings::Variant::Off, "ao.", "ao");
    requireFamily(settings_.ssr.tracer != SsrSettings::Tracer::Auto && settings_.ssr.tracer != SsrSettings::Tracer::Off,
                  "ssr.", "ssr");
    requireFamily(settings_.reference.kind != ReferenceSettings::Kind::Off, "ref.", "reference");
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
    u.counts = glm::ivec4(gpuScene_->punctualLightCount(), gpuScene_->materialCount(), 0, 0);
    frameUbo_.upload(&u, sizeof(u));
}

void Renderer::render(const View& view) {
    if (view.cut) res_.historyValid = false;
    uploadFrameUniforms(view);
    FrameContext ctx{programs_, ledger_, profiler_, scene_, *gpuScene_, settings_, res_, view, frameUbo_.id()};
    profiler_.beginFrame();
    for (auto& pass : passes_) {
        {
            auto scope = profiler_.scope(pass->name().c_str());
            // Every pass sets the state it relies on; the frame block is the
            // one binding all passes share.
            glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_FRAME, frameUbo_.id());
            pass->execute(ctx);
        }
        if (check_) checkOutputs(*pass);
    }
    profiler_.endFrame();
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
    bool volume = t.desc().target == GL_TEXTURE_3D;
    const gl::Program& prog =
        programs.compute("post/finite_check.comp", volume ? gl::Defines{{"RTGI_VOLUME", ""}} : gl::Defines{});
    gl::Buffer counts(ledger, "check.counts", 16);
    counts.clearZero();
    glMemoryBarrier(GL_ALL_BARRIER_BITS);  // producer: whichever pass wrote t just before
    glUseProgram(prog.id());
    glBindTextureUnit(RTGI_POST_TEX_SOURCE, t.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_POST_SSBO_COUNTS, counts.id());
    prog.set(RTGI_POST_LOC_CHANNELS, channels);
    prog.set(RTGI_POST_LOC_MAY_BE_NEGATIVE, mayBeNegative ? 1 : 0);
    glDispatchCompute(gl::groupCount(t.width(), 8), gl::groupCount(t.height(), 8), GLuint(volume ? t.depth() : 1));
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
    for (auto& out : pass.checkedOutputs(res_)) {
        FiniteCount c = countNonFinite(programs_, ledger_, *out.tex, out.mayBeNegative);
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
