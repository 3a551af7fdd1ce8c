#include "render/lpv/lpv_probe.h"

#include "compute/lib/bvh_shared.h"
#include "render/lpv/lpv_math.h"  // lpv_shared.h with the GLSL types
#include "render/gpu_scene.h"
#include "render/gpu_types.h"
#include "render/reference/reference_passes.h"
#include "render/renderer.h"
#include "scene/bvh.h"

#include <algorithm>

namespace rtgi::lpv {

static_assert(RTGI_LPV_PROBE_IMG_ACCUM_B == RTGI_LPV_PROBE_IMG_ACCUM_R + 2 &&
              RTGI_LPV_PROBE_IMG_ACCUM_G == RTGI_LPV_PROBE_IMG_ACCUM_R + 1 &&
              RTGI_LPV_PROBE_IMG_ACCUM_LAST == RTGI_LPV_PROBE_IMG_ACCUM_HI_R + 3);

ProbeParams probeParams(const Settings& s) {
    ProbeParams p;
    p.directions = s.lpv.probeDirections;
    p.bounces = s.lpv.bounce ? 2 : 1;  // as compareWithReference's matching-bounce reference
    p.seed = unsigned(s.reference.seed);
    return p;
}

void SceneBvh::ensure(FrameContext& ctx, const std::string& label) {
    if (nodes && geometryVersion == ctx.gpuScene.geometryVersion()) return;
    geometryVersion = ctx.gpuScene.geometryVersion();
    Bvh bvh = buildBvh(sceneTriangles(ctx.scene));
    if (bvh.triangles.empty()) {  // an empty scene: one leaf with an empty box, never hit
        bvh.nodes.assign(1, gpu::BvhNode{glm::vec3(1e30f), 0, glm::vec3(-1e30f), 0});
        bvh.triangles.assign(1, gpu::BvhTriangle{});
    }
    nodes = gl::Buffer(ctx.ledger, label + ".nodes", std::int64_t(bvh.nodes.size() * sizeof(gpu::BvhNode)),
                       bvh.nodes.data(), 0);
    triangles = gl::Buffer(ctx.ledger, label + ".triangles", std::int64_t(bvh.triangles.size() * sizeof(gpu::BvhTriangle)),
                           bvh.triangles.data(), 0);
}

void SceneBvh::bind(FrameContext& ctx) const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_BVH_NODES, nodes.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_BVH_TRIS, triangles.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_REF_VERTICES, ctx.gpuScene.vertices().id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_REF_INDICES, ctx.gpuScene.indices().id());
}

void visibilityMoments(FrameContext& ctx, const gl::Buffer& ubo, const SceneBvh& bvh, Volumes& v) {
    const gl::Program& prog = ctx.programs.compute("lpv/visibility.comp");
    glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, ubo.id());
    bvh.bind(ctx);
    glBindImageTexture(RTGI_LPV_VIS_IMG_MOMENTS, v.visibility.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RG16F);
    // Producer: the previous lpv.apply's texture fetches of the same image (a new placement).
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    gl::dispatch(prog, v.grid.x * RTGI_LPV_VIS_RES, v.grid.y * RTGI_LPV_VIS_RES, v.grid.z);
    // Consumer: lpv.apply's texture fetches.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
}

void skyVisibility(FrameContext& ctx, const gl::Buffer& ubo, const SceneBvh& bvh, Volumes& v) {
    const gl::Program& prog = ctx.programs.compute("lpv/visibility.comp", {{"RTGI_LPV_VIS_SKY", ""}});
    glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, ubo.id());
    bvh.bind(ctx);
    glBindImageTexture(RTGI_LPV_VIS_IMG_SKY, v.sky.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);  // producer: the previous lpv.apply's fetches
    gl::dispatch(prog, v.grid.x, v.grid.y, v.grid.z);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);  // consumer: lpv.apply
}

void faceVisibility(FrameContext& ctx, const gl::Buffer& ubo, const SceneBvh& bvh, Volumes& v) {
    const gl::Program& prog = ctx.programs.compute("lpv/visibility.comp", {{"RTGI_LPV_VIS_FACES", ""}});
    glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, ubo.id());
    bvh.bind(ctx);
    glBindImageTexture(RTGI_LPV_VIS_IMG_FACES, v.faces.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);  // producer: the previous lpv.propagate's fetches
    gl::dispatch(prog, v.grid.x, v.grid.y, v.grid.z);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);  // consumer: lpv.propagate
}

void ProbeTracer::fill(FrameContext& ctx, const gl::Buffer& ubo, Volumes& v, bool near) {
    bvh_.ensure(ctx, "lpv.probe.bvh");
    const ProbeParams p = probeParams(ctx.settings);
    // Lambert only, as the matching-bounce reference (reference.specular=off).
    gl::Defines defines = formatDefines(v.format, v.shOrder);
    defines.push_back({"RTGI_REF_DIFFUSE_ONLY", ""});
    // Emission hit from the cell is the emitter's direct light when emitters
    // are lights (emissive.lights=on), as in the indirect reference.
    if (ctx.settings.light.emissiveLights) defines.push_back({"RTGI_REF_EMISSION_IS_DIRECT", ""});
    const gl::Program& prog = ctx.programs.compute("lpv/probe.comp", defines);
    glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, ubo.id());
    bvh_.bind(ctx);
    ctx.gpuScene.bindTables();
    for (GLuint c = 0; c < 3; ++c)
        glBindImageTexture(RTGI_LPV_PROBE_IMG_ACCUM_R + c, v.accum[c].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, v.format);
    if (v.shOrder == 2)  // bands 0-2 (docs/lpv.md, "Second-order SH")
        for (GLuint c = 0; c < 4; ++c)
            glBindImageTexture(RTGI_LPV_PROBE_IMG_ACCUM_HI_R + c, v.accumHi[c].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY,
                               v.format);
    // Producer: lpv.propagate's image stores into accum (overwritten here).
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    // Slabs of one workgroup depth: short dispatches however many directions.
    for (int z = 0; z < v.grid.z; z += RTGI_LPV_LOCAL_3D) {
        glProgramUniform4ui(prog.id(), RTGI_LPV_PROBE_LOC_PARAMS, GLuint(p.directions), GLuint(p.bounces), p.seed,
                            GLuint(z));
        gl::dispatch(prog, v.grid.x, v.grid.y, std::min(RTGI_LPV_LOCAL_3D, v.grid.z - z));
    }
    // Consumers: the copy below and lpv.apply's texture fetches.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    if (near && v.near[0])
        for (std::size_t c = 0; c < 3; ++c)
            glCopyImageSubData(v.accum[c].id(), GL_TEXTURE_3D, 0, 0, 0, 0, v.near[c].id(), GL_TEXTURE_3D, 0, 0, 0, 0,
                               v.grid.x, v.grid.y, v.grid.z);
    if (near && v.shOrder == 2 && v.nearHi[0])
        for (std::size_t c = 0; c < 4; ++c)
            glCopyImageSubData(v.accumHi[c].id(), GL_TEXTURE_3D, 0, 0, 0, 0, v.nearHi[c].id(), GL_TEXTURE_3D, 0, 0, 0,
                               0, v.grid.x, v.grid.y, v.grid.z);
}

FloatImage renderProbeIndirect(const Renderer& run, const View& view) {
    Settings ps = run.settings();
    ps.lpv.source = LpvSettings::Source::Probe;
    ps.reference.kind = ReferenceSettings::Kind::Off;  // the caller has its reference
    gl::Profiler profiler(false);
    Renderer r(run.scene(), ps, profiler);
    r.render(view);
    return readTexture(r.resources().indirectDiffuse);
}

}  // namespace rtgi::lpv
