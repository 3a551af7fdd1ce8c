#include "render/lpv/lpv_volumes.h"

#include "gl/bindings.h"
#include "gl/profiler.h"
#include "render/lpv/lpv_math.h"

#include <stdexcept>
#include <string>

namespace rtgi::lpv {
namespace {

const char* kChannel[3] = {"r", "g", "b"};

// The descriptors the ensure functions allocate from (and the *Textures lists below name).
gl::TextureDesc volumeDesc(glm::ivec3 g, GLenum fmt) { return {GL_TEXTURE_3D, fmt, g.x, g.y, g.z}; }
gl::TextureDesc injectDesc(glm::ivec3 g) { return {GL_TEXTURE_3D, GL_R32F, 4 * g.x, g.y, g.z}; }      // coefficient k at 4x + k
gl::TextureDesc injectLastDesc(glm::ivec3 g) { return {GL_TEXTURE_3D, GL_R32F, 3 * g.x, g.y, g.z}; }  // colour c at 3x + c
gl::TextureDesc geometryAccumDesc(glm::ivec3 g, bool twoSided) {
    const int channels = twoSided ? RTGI_LPV_GV_CHANNELS_TWO_SIDED : RTGI_LPV_GV_CHANNELS_ORIENTED;
    return {GL_TEXTURE_3D, GL_R32F, channels * (g.x + 1), g.y + 1, g.z + 1};
}
gl::TextureDesc cornerDesc(glm::ivec3 g, GLenum fmt) { return volumeDesc(g + 1, fmt); }  // the (grid + 1)^3 corner lattice

void addRgb(std::vector<gl::NamedTextureDesc>& t, const std::string& label, const gl::TextureDesc& d) {
    for (const char* c : kChannel) t.push_back({label + "." + c, d});
}
void addHi(std::vector<gl::NamedTextureDesc>& t, const std::string& label, glm::ivec3 g, GLenum fmt) {
    addRgb(t, label, volumeDesc(g, fmt));
    t.push_back({label + ".last", volumeDesc(g, fmt)});
}

// Returns true when a texture was (re)allocated.
bool ensureRgb(gl::MemoryLedger& ledger, Rgb& t, const std::string& label, const gl::TextureDesc& d, bool linear) {
    bool changed = false;
    for (int c = 0; c < 3; ++c) {
        changed |= t[std::size_t(c)].ensure(ledger, label + "." + kChannel[c], d);
        t[std::size_t(c)].setSampling(linear ? GL_LINEAR : GL_NEAREST, linear ? GL_LINEAR : GL_NEAREST);
    }
    return changed;
}

// The r, g, b volumes of a pass sit at consecutive slots (compute/lib/lpv_shared.h).
static_assert(RTGI_LPV_TEX_SRC_B == RTGI_LPV_TEX_SRC_R + 2 && RTGI_LPV_TEX_CUR_B == RTGI_LPV_TEX_CUR_R + 2 &&
              RTGI_LPV_TEX_PREV_B == RTGI_LPV_TEX_PREV_R + 2 && RTGI_LPV_TEX_LIGHT_B == RTGI_LPV_TEX_LIGHT_R + 2 &&
              RTGI_LPV_IMG_DST_B == RTGI_LPV_IMG_DST_R + 2 && RTGI_LPV_IMG_ACCUM_B == RTGI_LPV_IMG_ACCUM_R + 2 &&
              RTGI_LPV_IMG_OUT_B == RTGI_LPV_IMG_OUT_R + 2 && RTGI_LPV_IMG_VOL_B == RTGI_LPV_IMG_VOL_R + 2 &&
              RTGI_LPV_INJECT_IMG_INJECT_B == RTGI_LPV_INJECT_IMG_INJECT_R + 2 &&
              RTGI_LPV_PACK_IMG_INJECT_B == RTGI_LPV_PACK_IMG_INJECT_R + 2);

static_assert(RTGI_LPV_INJECT_IMG_INJECT_HI_B == RTGI_LPV_INJECT_IMG_INJECT_HI_R + 2 &&
              RTGI_LPV_PACK_IMG_INJECT_HI_B == RTGI_LPV_PACK_IMG_INJECT_HI_R + 2 &&
              RTGI_LPV_PACK_IMG_VOL_LAST == RTGI_LPV_PACK_IMG_VOL_HI_R + 3 &&
              RTGI_LPV_TEX_SRC_LAST == RTGI_LPV_TEX_SRC_HI_R + 3 && RTGI_LPV_IMG_DST_LAST == RTGI_LPV_IMG_DST_HI_R + 3 &&
              RTGI_LPV_ACC_TEX_STEP_LAST == RTGI_LPV_ACC_TEX_STEP_HI_R + 3 &&
              RTGI_LPV_ACC_TEX_STEP_HI_R == RTGI_LPV_ACC_TEX_STEP_R + 3 &&
              RTGI_LPV_ACC_IMG_ACCUM_LAST == RTGI_LPV_ACC_IMG_ACCUM_HI_R + 3 &&
              RTGI_LPV_ACC_IMG_ACCUM_HI_R == RTGI_LPV_ACC_IMG_ACCUM_R + 3 &&
              RTGI_LPV_TEX_SOURCE_LAST == RTGI_LPV_TEX_SOURCE_HI_R + 3 &&
              RTGI_LPV_IMG_NEAR_LAST == RTGI_LPV_IMG_NEAR_HI_R + 3 &&
              RTGI_LPV_TEX_LIGHT_LAST == RTGI_LPV_TEX_LIGHT_HI_R + 3 &&
              RTGI_LPV_TEX_APPLY_NEAR_LAST == RTGI_LPV_TEX_APPLY_NEAR_HI_R + 3 &&
              RTGI_LPV_PROBE_IMG_ACCUM_LAST == RTGI_LPV_PROBE_IMG_ACCUM_HI_R + 3 &&
              RTGI_LPV_TEX_CUR_LAST == RTGI_LPV_TEX_CUR_HI_R + 3 && RTGI_LPV_TEX_PREV_LAST == RTGI_LPV_TEX_PREV_HI_R + 3 &&
              RTGI_LPV_IMG_OUT_LAST == RTGI_LPV_IMG_OUT_HI_R + 3);

bool ensureHi(gl::MemoryLedger& ledger, Hi& t, const std::string& label, glm::ivec3 g, GLenum fmt, bool linear) {
    bool changed = false;
    for (int c = 0; c < 4; ++c) {
        changed |= t[std::size_t(c)].ensure(ledger, label + "." + (c < 3 ? kChannel[c] : "last"), volumeDesc(g, fmt));
        t[std::size_t(c)].setSampling(linear ? GL_LINEAR : GL_NEAREST, linear ? GL_LINEAR : GL_NEAREST);
    }
    return changed;
}

void bindHiTextures(const Hi& t, GLuint firstUnit) {
    for (GLuint c = 0; c < 4; ++c) glBindTextureUnit(firstUnit + c, t[c].id());
}

void bindHiImages(const Hi& t, GLuint firstUnit, GLenum access, GLenum format) {
    for (GLuint c = 0; c < 4; ++c) glBindImageTexture(firstUnit + c, t[c].id(), 0, GL_TRUE, 0, access, format);
}

void bindRgbTextures(const Rgb& t, GLuint firstUnit) {
    for (GLuint c = 0; c < 3; ++c) glBindTextureUnit(firstUnit + c, t[c].id());
}

void bindRgbImages(const Rgb& t, GLuint firstUnit, GLenum access, GLenum format) {
    for (GLuint c = 0; c < 3; ++c) glBindImageTexture(firstUnit + c, t[c].id(), 0, GL_TRUE, 0, access, format);
}

void bindUbo(const gl::Buffer& ubo) { glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_LPV, ubo.id()); }

gl::FramebufferHandle layeredFbo(const std::string& label, const Rgb& a, const Rgb& b) {
    GLuint f = 0;
    glCreateFramebuffers(1, &f);
    gl::FramebufferHandle fbo(f);
    fbo.label(label);
    GLenum bufs[6];
    for (int i = 0; i < 6; ++i) {
        const gl::Texture& t = (i < 3 ? a : b)[std::size_t(i % 3)];
        glNamedFramebufferTexture(f, GLenum(GL_COLOR_ATTACHMENT0 + i), t.id(), 0);  // 3D: layered
        bufs[i] = GLenum(GL_COLOR_ATTACHMENT0 + i);
    }
    glNamedFramebufferDrawBuffers(f, 6, bufs);
    if (glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error(label + ": layered framebuffer incomplete");
    return fbo;
}

// Raster state of the seed baseline: blending on the attachments in `blended`.
void rasterState(const Volumes& v, GLuint fbo, bool blendSteps) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, v.grid.x, v.grid.y);
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    for (GLuint i = 0; i < 6; ++i) {
        if (i >= 3 || blendSteps) {
            glEnablei(GL_BLEND, i);
            glBlendFunci(i, GL_ONE, GL_ONE);
            glBlendEquationi(i, GL_FUNC_ADD);
        } else {
            glDisablei(GL_BLEND, i);
        }
    }
}

void endRaster() {
    for (GLuint i = 0; i < 6; ++i) glDisablei(GL_BLEND, i);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace

bool Volumes::ensureLight(gl::MemoryLedger& ledger, glm::ivec3 g, GLenum fmt, int order) {
    bool changed = g != grid || fmt != format || !accum[0] || order != shOrder;
    grid = g;
    format = fmt;
    shOrder = order;
    if (order == 2) {
        if (ensureRgb(ledger, injectHi, "lpv.inject_hi", injectDesc(g), false))
            for (auto& t : injectHi) t.clear();
        if (injectLast.ensure(ledger, "lpv.inject_last", injectLastDesc(g))) injectLast.clear();
        for (int k = 0; k < 2; ++k) ensureHi(ledger, stepHi[std::size_t(k)], "lpv.step" + std::to_string(k) + ".hi", g, fmt, false);
        ensureHi(ledger, accumHi, "lpv.accum.hi", g, fmt, true);
    } else {  // band 1: no band-2 memory
        for (auto& t : injectHi) t.reset();
        injectLast.reset();
        for (Hi* h : {&stepHi[0], &stepHi[1], &accumHi, &nearHi, &historyHi[0], &historyHi[1]})
            for (auto& t : *h) t.reset();
    }
    // The fp32 accumulation is zero between frames (lpv.pack zeroes what it consumes): cleared
    // once here, when allocated.
    if (ensureRgb(ledger, inject, "lpv.inject", injectDesc(g), false))
        for (auto& t : inject) t.clear();
    for (int k = 0; k < 2; ++k)
        ensureRgb(ledger, step[std::size_t(k)], "lpv.step" + std::to_string(k), volumeDesc(g, fmt), false);
    ensureRgb(ledger, accum, "lpv.accum", volumeDesc(g, fmt), true);
    if (changed) {
        injectFbo = {};
        propagateFbo = {};
    }
    return changed;
}

void Volumes::ensureNear(gl::MemoryLedger& ledger) {
    ensureRgb(ledger, near, "lpv.near", volumeDesc(grid, format), true);
    if (shOrder == 2) ensureHi(ledger, nearHi, "lpv.near.hi", grid, format, true);
}

void Volumes::ensureGeometry(gl::MemoryLedger& ledger, bool twoSided) {
    // Zero between frames (the geometry pack zeroes what it consumes): cleared once, when allocated.
    if (geometryAccum.ensure(ledger, "lpv.geometry_accum", geometryAccumDesc(grid, twoSided)))
        geometryAccum.clear();
    // Linear: lpv.lookup=geometry samples it between corners (the propagation uses texelFetch).
    if (geometry.ensure(ledger, "lpv.geometry", cornerDesc(grid, format)))
        geometry.setSampling(GL_LINEAR, GL_LINEAR);
    geometryAlbedo.ensure(ledger, "lpv.geometry_albedo", cornerDesc(grid, GL_RGBA16F));
    if (!twoSided) geometryAxes = gl::Texture();
    else if (geometryAxes.ensure(ledger, "lpv.geometry_axes", cornerDesc(grid, GL_RGBA16F)))
        geometryAxes.setSampling(GL_LINEAR, GL_LINEAR);
}

bool Volumes::ensureVisibility(gl::MemoryLedger& ledger) {
    // Linear within a cell's tile (lib/lpv_lookup.glsl keeps the lookup half a texel inside it).
    const gl::NamedTextureDesc t = visibilityTexture(grid);
    if (!visibility.ensure(ledger, t.label, t.desc)) return false;
    visibility.setSampling(GL_LINEAR, GL_LINEAR);
    return true;
}

bool Volumes::ensureFaces(gl::MemoryLedger& ledger) {
    // Read with texelFetch only (lpv/propagate.glsl).
    const gl::NamedTextureDesc t = faceTexture(grid);
    return faces.ensure(ledger, t.label, t.desc);
}

bool Volumes::ensureSky(gl::MemoryLedger& ledger) {
    const gl::NamedTextureDesc t = skyTexture(grid);
    if (!sky.ensure(ledger, t.label, t.desc)) return false;
    sky.setSampling(GL_LINEAR, GL_LINEAR);  // trilinear, as the light volumes
    return true;
}

namespace {
// Two temporal blend targets (ping-pong) of a volume, band 2 included.
void ensureHistoryPair(gl::MemoryLedger& ledger, const Volumes& v, std::array<Rgb, 2>& rgb, std::array<Hi, 2>& hi,
                       const std::string& label) {
    for (int k = 0; k < 2; ++k) {
        ensureRgb(ledger, rgb[std::size_t(k)], label + std::to_string(k), volumeDesc(v.grid, v.format), true);
        if (v.shOrder == 2) ensureHi(ledger, hi[std::size_t(k)], label + std::to_string(k) + ".hi", v.grid, v.format, true);
    }
}
}  // namespace

void Volumes::ensureHistory(gl::MemoryLedger& ledger) { ensureHistoryPair(ledger, *this, history, historyHi, "lpv.history"); }

void Volumes::ensureNearHistory(gl::MemoryLedger& ledger) {
    ensureHistoryPair(ledger, *this, nearHistory, nearHistoryHi, "lpv.near_history");  // label: historyTextures(near)
}

std::vector<gl::NamedTextureDesc> lightTextures(glm::ivec3 g, GLenum format, int shOrder) {
    std::vector<gl::NamedTextureDesc> t;
    if (shOrder == 2) {
        addRgb(t, "lpv.inject_hi", injectDesc(g));
        t.push_back({"lpv.inject_last", injectLastDesc(g)});
        for (int k = 0; k < 2; ++k) addHi(t, "lpv.step" + std::to_string(k) + ".hi", g, format);
        addHi(t, "lpv.accum.hi", g, format);
    }
    addRgb(t, "lpv.inject", injectDesc(g));
    for (int k = 0; k < 2; ++k) addRgb(t, "lpv.step" + std::to_string(k), volumeDesc(g, format));
    addRgb(t, "lpv.accum", volumeDesc(g, format));
    return t;
}

std::vector<gl::NamedTextureDesc> nearTextures(glm::ivec3 g, GLenum format, int shOrder) {
    std::vector<gl::NamedTextureDesc> t;
    addRgb(t, "lpv.near", volumeDesc(g, format));
    if (shOrder == 2) addHi(t, "lpv.near.hi", g, format);
    return t;
}

std::vector<gl::NamedTextureDesc> geometryTextures(glm::ivec3 g, GLenum format, bool twoSided) {
    std::vector<gl::NamedTextureDesc> t{{"lpv.geometry_accum", geometryAccumDesc(g, twoSided)},
                                        {"lpv.geometry", cornerDesc(g, format)},
                                        {"lpv.geometry_albedo", cornerDesc(g, GL_RGBA16F)}};
    if (twoSided) t.push_back({"lpv.geometry_axes", cornerDesc(g, GL_RGBA16F)});
    return t;
}

gl::NamedTextureDesc visibilityTexture(glm::ivec3 g) {
    const int n = RTGI_LPV_VIS_RES;  // an N x N tile of moments per cell
    return {"lpv.visibility", {GL_TEXTURE_3D, GL_RG16F, n * g.x, n * g.y, g.z}};
}

gl::NamedTextureDesc skyTexture(glm::ivec3 g) { return {"lpv.sky_visibility", volumeDesc(g, GL_RGBA16F)}; }
gl::NamedTextureDesc faceTexture(glm::ivec3 g) { return {"lpv.face_visibility", volumeDesc(g, GL_RGBA8)}; }

std::vector<gl::NamedTextureDesc> historyTextures(glm::ivec3 g, GLenum format, int shOrder, bool near) {
    std::vector<gl::NamedTextureDesc> t;
    const std::string label = near ? "lpv.near_history" : "lpv.history";
    for (int k = 0; k < 2; ++k) {
        addRgb(t, label + std::to_string(k), volumeDesc(g, format));
        if (shOrder == 2) addHi(t, label + std::to_string(k) + ".hi", g, format);
    }
    return t;
}

std::vector<gl::NamedTextureDesc> sunCacheTextures(glm::ivec3 g, GLenum format) {
    std::vector<gl::NamedTextureDesc> t;
    addRgb(t, "lpv.sun_cache", volumeDesc(g, format));
    return t;
}

bool ensureSunCache(gl::MemoryLedger& ledger, Rgb& cache, glm::ivec3 g, GLenum format) {
    return ensureRgb(ledger, cache, "lpv.sun_cache", volumeDesc(g, format), false);
}

void copyVolumes(gl::ProgramCache& programs, const Rgb& from, Rgb& to, glm::ivec3 g, GLenum format) {
    const gl::Program& prog = programs.compute("lpv/copy.comp", formatDefines(format));
    bindRgbTextures(from, RTGI_LPV_TEX_SRC_R);
    bindRgbImages(to, RTGI_LPV_IMG_DST_R, GL_WRITE_ONLY, format);
    gl::dispatch(prog, g.x, g.y, g.z);
}

void copyVolumes(gl::ProgramCache& programs, const Hi& from, Hi& to, glm::ivec3 g, GLenum format) {
    gl::Defines d = formatDefines(format);
    d.push_back({"RTGI_LPV_COPY_HI", ""});
    const gl::Program& prog = programs.compute("lpv/copy.comp", d);
    bindHiTextures(from, RTGI_LPV_TEX_SRC_HI_R);
    bindHiImages(to, RTGI_LPV_IMG_DST_HI_R, GL_WRITE_ONLY, format);
    gl::dispatch(prog, g.x, g.y, g.z);
}

void Volumes::ensureRasterTargets() {
    if (!emptyVao) {
        GLuint vao = 0;
        glCreateVertexArrays(1, &vao);
        emptyVao = gl::VertexArrayHandle(vao);
        emptyVao.label("lpv.empty_vao");
    }
    if (!injectFbo) injectFbo = layeredFbo("lpv.inject.fbo", step[0], accum);
    for (int k = 0; k < 2; ++k)
        if (!propagateFbo[std::size_t(k)])
            propagateFbo[std::size_t(k)] =
                layeredFbo("lpv.propagate.fbo" + std::to_string(k), step[std::size_t(k)], accum);
}

gl::Defines formatDefines(GLenum format, int shOrder) {
    gl::Defines d;
    if (format == GL_RGBA32F) d = {{"RTGI_LPV_FORMAT", "rgba32f"}};
    else if (format == GL_R32F) d = {{"RTGI_LPV_FORMAT", "r32f"}};  // the fp32 accumulation volumes (lpv::copyInjectCache)
    else d = {{"RTGI_LPV_FORMAT", "rgba16f"}, {"RTGI_LPV_HALF", ""}};
    if (shOrder == 2) d.push_back({"RTGI_LPV_SH2", ""});
    return d;
}

InjectTarget injectTarget(Volumes& v) {
    if (v.shOrder == 2) return {&v.inject, &v.injectHi, &v.injectLast};
    return {&v.inject, nullptr, nullptr};
}

namespace {
// The RSM textures and the accumulation of an injection dispatch (lpv/inject.comp).
void bindInjection(const Rsm& rsm, const InjectTarget& t, const gl::Buffer& stats) {
    // Producers: lpv.rsm (framebuffer writes, or the compute resolve's image stores); the zeroing
    // of the accumulation by the previous lpv.pack (image stores), its clear at allocation or a
    // copy of the injection cache.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindTextureUnit(RTGI_LPV_TEX_FLUX, rsm.flux.id());
    glBindTextureUnit(RTGI_LPV_TEX_NORMAL, rsm.normal.id());
    glBindTextureUnit(RTGI_LPV_TEX_DEPTH, rsm.depth.id());
    bindRgbImages(*t.rgb, RTGI_LPV_INJECT_IMG_INJECT_R, GL_READ_WRITE, GL_R32F);
    if (t.hi) {
        bindRgbImages(*t.hi, RTGI_LPV_INJECT_IMG_INJECT_HI_R, GL_READ_WRITE, GL_R32F);
        glBindImageTexture(RTGI_LPV_INJECT_IMG_INJECT_LAST, t.last->id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32F);
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_LPV_STATS, stats.id());
}
}  // namespace

void injectCompute(gl::ProgramCache& programs, const gl::Buffer& ubo, const Rsm& rsm, int rsmSize, Volumes& v,
                   const gl::Buffer& stats) {
    const gl::Program& prog = programs.compute("lpv/inject.comp", v.shOrder == 2 ? gl::Defines{{"RTGI_LPV_SH2", ""}}
                                                                                 : gl::Defines{});
    bindUbo(ubo);
    bindInjection(rsm, injectTarget(v), stats);
    gl::dispatch(prog, rsmSize, rsmSize);
}

namespace {
// lpv.lookup=visibility's receiver test, shared by lpv.apply and the sky bounce's injection.
void appendVisibilityDefines(gl::Defines& d, int exponent, float viewBias) {
    d.push_back({"RTGI_LPV_LOOKUP_VISIBILITY", ""});
    d.push_back({"RTGI_LPV_VIS_EXPONENT", std::to_string(exponent)});
    d.push_back(gl::floatDefine("RTGI_LPV_VIS_VIEW_BIAS", viewBias));
}
}  // namespace

void injectSky(gl::ProgramCache& programs, const gl::Buffer& ubo, const GBufferView& gb, Volumes& v, bool moments,
               int visibilityExponent, float visibilityViewBias) {
    gl::Defines d{{"RTGI_LPV_INJECT_SKY", ""}};
    if (v.shOrder == 2) d.push_back({"RTGI_LPV_SH2", ""});
    if (gb.stride != 2) d.push_back({"RTGI_LPV_GV_STRIDE", std::to_string(gb.stride)});
    if (moments) appendVisibilityDefines(d, visibilityExponent, visibilityViewBias);
    const gl::Program& prog = programs.compute("lpv/inject.comp", d);
    bindUbo(ubo);
    // Producers: gbuffer (framebuffer writes or the compute resolve), lpv.visibility (image
    // stores), the zeroing of the accumulation by the previous lpv.pack (image stores).
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    gl::ScopedBindings b;
    b.texture(RTGI_LPV_TEX_LINEAR_DEPTH, gb.linearDepth)
        .texture(RTGI_LPV_TEX_VIEW_NORMAL, gb.normal)
        .texture(RTGI_LPV_TEX_ALBEDO, gb.albedo)
        .texture(RTGI_LPV_TEX_MATERIAL, gb.material)
        .texture(RTGI_LPV_TEX_INJECT_SKY, &v.sky);
    if (moments) b.texture(RTGI_LPV_TEX_INJECT_MOMENTS, &v.visibility);
    const InjectTarget t = injectTarget(v);
    bindRgbImages(*t.rgb, RTGI_LPV_INJECT_IMG_INJECT_R, GL_READ_WRITE, GL_R32F);
    if (t.hi) {
        bindRgbImages(*t.hi, RTGI_LPV_INJECT_IMG_INJECT_HI_R, GL_READ_WRITE, GL_R32F);
        glBindImageTexture(RTGI_LPV_INJECT_IMG_INJECT_LAST, t.last->id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32F);
    }
    gl::dispatch(prog, (gb.size.x + gb.stride - 1) / gb.stride, (gb.size.y + gb.stride - 1) / gb.stride);
}

void injectFaces(gl::ProgramCache& programs, const gl::Buffer& ubo, const Rsm& rsmArray, const gl::Buffer& faces,
                 int first, int count, const InjectTarget& target, int shOrder, const gl::Buffer& stats,
                 int statsSlot) {
    if (count <= 0) return;
    gl::Defines d{{"RTGI_LPV_INJECT_FACES", ""}};
    if (shOrder == 2) d.push_back({"RTGI_LPV_SH2", ""});
    const gl::Program& prog = programs.compute("lpv/inject.comp", d);
    bindUbo(ubo);
    bindInjection(rsmArray, target, stats);  // the face list: a buffer upload, ordered before the dispatch
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_LPV_RSM_FACES, faces.id());
    prog.set(RTGI_LPV_INJECT_LOC_FIRST_FACE, first);
    prog.set(RTGI_LPV_INJECT_LOC_STATS_SLOT, statsSlot);
    const int n = rsmArray.flux.width();
    gl::dispatch(prog, n, n, count);
}

bool InjectCache::ensure(gl::MemoryLedger& ledger, glm::ivec3 g, int shOrder) {
    bool changed = ensureRgb(ledger, rgb, "lpv.inject_cache", injectDesc(g), false);
    if (shOrder == 2) {
        changed |= ensureRgb(ledger, hi, "lpv.inject_cache_hi", injectDesc(g), false);
        changed |= last.ensure(ledger, "lpv.inject_cache_last", injectLastDesc(g));
    } else {
        for (auto& t : hi) t.reset();
        last.reset();
    }
    if (changed) clear();
    return changed;
}

void InjectCache::clear() const {
    // Producer: earlier injections into the cache (image atomics).
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    for (auto& t : rgb) t.clear();
    if (last) {
        for (auto& t : hi) t.clear();
        last.clear();
    }
}

void InjectCache::reset() {
    for (auto& t : rgb) t.reset();
    for (auto& t : hi) t.reset();
    last.reset();
}

InjectTarget InjectCache::target() {
    if (last) return {&rgb, &hi, &last};
    return {&rgb, nullptr, nullptr};
}

std::vector<gl::NamedTextureDesc> injectCacheTextures(glm::ivec3 g, int shOrder) {
    std::vector<gl::NamedTextureDesc> t;
    addRgb(t, "lpv.inject_cache", injectDesc(g));
    if (shOrder == 2) {
        addRgb(t, "lpv.inject_cache_hi", injectDesc(g));
        t.push_back({"lpv.inject_cache_last", injectLastDesc(g)});
    }
    return t;
}

void copyInjectCache(gl::ProgramCache& programs, const InjectCache& cache, Volumes& v) {
    // Producers: the injections into the cache (image atomics, read here as textures) and the zeroing of
    // v.inject by lpv.pack (image stores, overwritten here by image stores).
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    // Dispatches, not glCopyImageSubData: with the copy in the frame the H200 idled 5-36 ms inside later
    // passes' scopes (docs/BENCHMARKS.md "Session 14 device run").
    auto check = [](const gl::Texture& from, const gl::Texture& to) {
        if (from.desc() != to.desc()) throw std::logic_error("lpv: injection cache and volume differ in layout");
    };
    auto copy = [&](const Rgb& from, Rgb& to) {
        for (std::size_t c = 0; c < 3; ++c) check(from[c], to[c]);
        copyVolumes(programs, from, to, {to[0].width(), to[0].height(), to[0].depth()}, to[0].format());
    };
    copy(cache.rgb, v.inject);
    if (v.shOrder == 2) {
        copy(cache.hi, v.injectHi);
        check(cache.last, v.injectLast);
        gl::Defines d = formatDefines(v.injectLast.format());
        d.push_back({"RTGI_LPV_COPY_ONE", ""});
        const gl::Program& prog = programs.compute("lpv/copy.comp", d);
        glBindTextureUnit(RTGI_LPV_TEX_SRC_R, cache.last.id());
        glBindImageTexture(RTGI_LPV_IMG_DST_R, v.injectLast.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, v.injectLast.format());
        gl::dispatch(prog, v.injectLast.width(), v.injectLast.height(), v.injectLast.depth());
    }
    // Consumer: the frame's further injections (image atomics) add onto the copy.
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

void packLight(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v) {
    const gl::Program& prog = programs.compute("lpv/pack.comp", formatDefines(v.format));
    bindUbo(ubo);
    // Producer: lpv.inject (image atomics).
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    bindRgbImages(v.inject, RTGI_LPV_PACK_IMG_INJECT_R, GL_READ_WRITE, GL_R32F);
    bindRgbImages(v.step[0], RTGI_LPV_IMG_VOL_R, GL_WRITE_ONLY, v.format);
    gl::dispatch(prog, v.grid.x, v.grid.y, v.grid.z);
    if (v.shOrder == 2) {  // coefficients 4-8: a second dispatch (8 image units)
        gl::Defines d = formatDefines(v.format);
        d.push_back({"RTGI_LPV_PACK_HI", ""});
        const gl::Program& hi = programs.compute("lpv/pack.comp", d);
        bindRgbImages(v.injectHi, RTGI_LPV_PACK_IMG_INJECT_HI_R, GL_READ_WRITE, GL_R32F);
        glBindImageTexture(RTGI_LPV_PACK_IMG_INJECT_LAST, v.injectLast.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32F);
        bindHiImages(v.stepHi[0], RTGI_LPV_PACK_IMG_VOL_HI_R, GL_WRITE_ONLY, v.format);
        gl::dispatch(hi, v.grid.x, v.grid.y, v.grid.z);
    }
}

namespace {
void injectRasterWith(const gl::Program& prog, const gl::Buffer& ubo, const Rsm& rsm, int rsmSize, Volumes& v,
                      bool clear) {
    bindUbo(ubo);
    const float zero[4] = {0, 0, 0, 0};
    if (clear)
        for (int i = 0; i < 6; ++i) glClearNamedFramebufferfv(v.injectFbo.id(), GL_COLOR, i, zero);
    // Producer: lpv.rsm (framebuffer writes).
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    rasterState(v, v.injectFbo.id(), true);
    glBindTextureUnit(RTGI_LPV_TEX_FLUX, rsm.flux.id());
    glBindTextureUnit(RTGI_LPV_TEX_NORMAL, rsm.normal.id());
    glBindTextureUnit(RTGI_LPV_TEX_DEPTH, rsm.depth.id());
    glUseProgram(prog.id());
    glBindVertexArray(v.emptyVao.id());
    glDrawArrays(GL_POINTS, 0, rsmSize * rsmSize);
    gl::Profiler::noteDispatch();
    endRaster();
}
}  // namespace

void injectRaster(gl::ProgramCache& programs, const gl::Buffer& ubo, const Rsm& rsm, int rsmSize, Volumes& v,
                  bool clear) {
    v.ensureRasterTargets();
    const gl::Program& prog =
        programs.raster("lpv/inject_raster.vert", "lpv/inject_raster.frag", {}, "lpv/inject_raster.geom");
    injectRasterWith(prog, ubo, rsm, rsmSize, v, clear);
}

void injectRasterLayer(gl::ProgramCache& programs, const gl::Buffer& ubo, const Rsm& rsmArray, int layer,
                       const glm::mat4& invViewProj, Volumes& v, bool clear) {
    v.ensureRasterTargets();
    const gl::Program& prog = programs.raster("lpv/inject_raster.vert", "lpv/inject_raster.frag",
                                              {{"RTGI_LPV_RSM_ARRAY", ""}}, "lpv/inject_raster.geom");
    prog.set(RTGI_LPV_INJECT_RASTER_LOC_LAYER, layer);
    prog.set(RTGI_LPV_INJECT_RASTER_LOC_INV_VIEW_PROJ, invViewProj);
    injectRasterWith(prog, ubo, rsmArray, rsmArray.flux.width(), v, clear);
}

void injectGeometry(gl::ProgramCache& programs, const gl::Buffer& ubo, const Rsm& rsm, int rsmSize,
                    const GBufferView& gb, Volumes& v) {
    bindUbo(ubo);
    // Producers: lpv.rsm and gbuffer (framebuffer writes); the zeroing of the accumulation by
    // the previous geometry pack (image stores) or its clear at allocation.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindImageTexture(RTGI_LPV_INJECT_GEOMETRY_IMG_GEOMETRY_ACCUM, v.geometryAccum.id(), 0, GL_TRUE, 0, GL_READ_WRITE,
                       GL_R32F);
    // lpv.blocking=two-sided allocated the axis blocking (ensureGeometry): the variant that fills it.
    const bool twoSided = bool(v.geometryAxes);
    gl::Defines variant;
    if (twoSided) variant.push_back({"RTGI_LPV_TWO_SIDED", ""});
    // One dispatch for both sources (lpv/inject_geometry.comp): workgroup layer z = 0 the RSM's texels,
    // z = 1 the G-buffer's samples; the x/y extent covers the larger of the two, and workgroups
    // beyond a source's extent add nothing.
    const bool fromRsm = rsmSize > 0, fromGBuffer = gb.linearDepth != nullptr;
    if (fromRsm || fromGBuffer) {
        gl::Defines d = variant;
        glm::ivec2 extent(0);
        gl::ScopedBindings b;
        if (fromRsm) {
            d.push_back({"RTGI_LPV_GV_RSM", ""});
            b.texture(RTGI_LPV_INJECT_GEOMETRY_TEX_RSM_FLUX, rsm.flux)
                .texture(RTGI_LPV_INJECT_GEOMETRY_TEX_RSM_NORMAL, rsm.normal)
                .texture(RTGI_LPV_INJECT_GEOMETRY_TEX_RSM_DEPTH, rsm.depth);
            extent = glm::max(extent, glm::ivec2(rsmSize));
        }
        if (fromGBuffer) {
            d.push_back({"RTGI_LPV_GV_GBUFFER", ""});
            if (gb.stride != 2) d.push_back({"RTGI_LPV_GV_STRIDE", std::to_string(gb.stride)});
            b.texture(RTGI_LPV_TEX_LINEAR_DEPTH, *gb.linearDepth)
                .texture(RTGI_LPV_TEX_VIEW_NORMAL, *gb.normal)
                .texture(RTGI_LPV_TEX_ALBEDO, *gb.albedo)
                .texture(RTGI_LPV_TEX_MATERIAL, *gb.material);
            extent = glm::max(extent, (gb.size + gb.stride - 1) / gb.stride);
        }
        extent = (extent + RTGI_LPV_GV_BLOCK - 1) / RTGI_LPV_GV_BLOCK;  // a block of samples per invocation
        gl::dispatch(programs.compute("lpv/inject_geometry.comp", d), extent.x, extent.y, fromRsm && fromGBuffer ? 2 : 1);
    }
    const gl::Program& pack =
        programs.compute("lpv/pack.comp", [&] {
            gl::Defines d = formatDefines(v.format);
            d.push_back({"RTGI_LPV_PACK_GEOMETRY", ""});
            if (twoSided) d.push_back({"RTGI_LPV_TWO_SIDED", ""});
            return d;
        }());
    // Producer: the geometry injection dispatches above (image atomics).
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glBindImageTexture(RTGI_LPV_PACK_IMG_GEOMETRY_ACCUM, v.geometryAccum.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32F);
    glBindImageTexture(RTGI_LPV_IMG_GEOMETRY, v.geometry.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, v.format);
    glBindImageTexture(RTGI_LPV_IMG_GEOMETRY_ALBEDO, v.geometryAlbedo.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    if (twoSided)
        glBindImageTexture(RTGI_LPV_IMG_GEOMETRY_AXES, v.geometryAxes.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    gl::dispatch(pack, v.grid.x + 1, v.grid.y + 1, v.grid.z + 1);
}

ComputePropagation::ComputePropagation(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v,
                                       int iterations, bool near, bool visibility, int fuse, int nearIterations,
                                       bool faceKernel)
    : programs_(programs), ubo_(ubo), v_(v), iterations_(iterations), near_(near), visibility_(visibility),
      sh2_(v.shOrder == 2), faceKernel_(faceKernel && v.shOrder == 1), defines_(formatDefines(v.format, v.shOrder)) {
    if (visibility) defines_.push_back({"RTGI_LPV_PROPAGATE_VISIBILITY", ""});
    // Near part = accum_K + f (accum_{K+1} - accum_K): K the last step of weight 1, f the next one's.
    const int n = nearIterations > 0 ? nearIterations : iterations;
    while (nearK_ + 1 <= iterations && cascadeNearWeight(nearK_ + 1, n) >= 1.0) ++nearK_;
    nearF_ = nearK_ + 1 <= iterations ? float(cascadeNearWeight(nearK_ + 1, n)) : 0.0f;
    // Fused: band 1 only, and not with the traced face openness (its reflected flux was
    // written against the unfused step and is not covered by the fused-equals-unfused test).
    maxFuse_ = sh2_ || visibility ? 1 : std::clamp(fuse, 1, kMaxFuse);
    bindUbo(ubo);
    nearStep(0);
    if (sh2_) {
        // Band 2 sums in lpv/accumulate.comp: accum starts as step 0 (lpv.pack's image stores).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        copyVolumes(programs, v.step[0], v.accum, v.grid, v.format);
        copyVolumes(programs, v.stepHi[0], v.accumHi, v.grid, v.format);
    }
}

void ComputePropagation::nearStep(int k) {
    Volumes& v = v_;
    if (!near_) return;
    if (k == nearK_) {
        // Producer: lpv.pack (k = 0, step[0]) or the iteration k (accum), image stores.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        copyVolumes(programs_, k == 0 ? v.step[0] : v.accum, v.near, v.grid, v.format);
        if (sh2_) copyVolumes(programs_, k == 0 ? v.stepHi[0] : v.accumHi, v.nearHi, v.grid, v.format);
    } else if (k == nearK_ + 1 && nearF_ > 0.0f) {
        const gl::Program& mix = programs_.compute("lpv/near.comp", formatDefines(v.format, v.shOrder));
        // Producers: the copy above and iteration k's accum stores.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_TEXTURE_UPDATE_BARRIER_BIT);
        bindRgbTextures(v.accum, RTGI_LPV_TEX_SOURCE_R);
        bindRgbImages(v.near, RTGI_LPV_IMG_NEAR_R, GL_READ_WRITE, v.format);
        if (sh2_) {
            bindHiTextures(v.accumHi, RTGI_LPV_TEX_SOURCE_HI_R);
            bindHiImages(v.nearHi, RTGI_LPV_IMG_NEAR_HI_R, GL_READ_WRITE, v.format);
        }
        mix.set(RTGI_LPV_LOC_NEAR_FRACTION, nearF_);
        mix.set(RTGI_LPV_LOC_NEAR_OFFSET, 0);
        gl::dispatch(mix, v.grid.x, v.grid.y, v.grid.z);
    }
}

void ComputePropagation::step(bool leadingBarrier) {
    Volumes& v = v_;
    const int k = k_;
    // Iterations k .. k + count - 1 in this dispatch: a chunk ends where the near part is
    // copied (after step nearK) or mixed (step nearK + 1).
    int count = std::min(maxFuse_, iterations_ - k + 1);
    if (near_)
        for (int e : {nearK_, nearK_ + 1})
            if (e >= k && e < k + count - 1) count = e - k + 1;
    // Rebound every step: the near part's mix and the band-2 sum use units of their own, and an
    // interleaved cascade binds its own block and volumes in between.
    bindUbo(ubo_);
    glBindTextureUnit(RTGI_LPV_TEX_GEOMETRY, v.geometry.id());
    glBindTextureUnit(RTGI_LPV_TEX_GEOMETRY_ALBEDO, v.geometryAlbedo.id());
    glBindTextureUnit(RTGI_LPV_TEX_GEOMETRY_AXES, v.geometryAxes.id());
    if (visibility_) glBindTextureUnit(RTGI_LPV_TEX_PROPAGATE_VISIBILITY, v.faces.id());
    if (!sh2_) bindRgbImages(v.accum, RTGI_LPV_IMG_ACCUM_R, GL_READ_WRITE, v.format);
    const int src = src_, dst = 1 - src;
    // Producer: lpv.pack / the previous iteration (image stores into step[src] and accum).
    if (leadingBarrier) glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    bindRgbTextures(v.step[std::size_t(src)], RTGI_LPV_TEX_SRC_R);
    bindRgbImages(v.step[std::size_t(dst)], RTGI_LPV_IMG_DST_R, GL_WRITE_ONLY, v.format);
    if (sh2_) {
        bindHiTextures(v.stepHi[std::size_t(src)], RTGI_LPV_TEX_SRC_HI_R);
        bindHiImages(v.stepHi[std::size_t(dst)], RTGI_LPV_IMG_DST_HI_R, GL_WRITE_ONLY, v.format);
    }
    if (count > 1) {
        gl::Defines fd = defines_;
        fd.push_back({"RTGI_LPV_FUSE", std::to_string(maxFuse_)});
        const gl::Program& fused = programs_.compute("lpv/propagate_fused.comp", fd);
        fused.set(RTGI_LPV_LOC_ITERATION, k);
        fused.set(RTGI_LPV_LOC_FUSED_COUNT, count);
        gl::dispatch(fused, v.grid.x, v.grid.y, v.grid.z);
    } else if (faceKernel_) {
        const gl::Program& prog = programs_.compute("lpv/propagate_faces.comp", defines_);
        prog.set(RTGI_LPV_LOC_ITERATION, k);
        gl::dispatch(prog, v.grid.x * v.grid.y * v.grid.z, 6, 3);
    } else {
        const gl::Program& prog = programs_.compute("lpv/propagate.comp", defines_);
        prog.set(RTGI_LPV_LOC_ITERATION, k);
        gl::dispatch(prog, v.grid.x, v.grid.y, v.grid.z);
    }
    if (sh2_) {
        const gl::Program& acc = programs_.compute("lpv/accumulate.comp", formatDefines(v.format));
        // Producer: the step just written (image stores), read as textures here.
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        bindRgbTextures(v.step[std::size_t(dst)], RTGI_LPV_ACC_TEX_STEP_R);
        bindHiTextures(v.stepHi[std::size_t(dst)], RTGI_LPV_ACC_TEX_STEP_HI_R);
        bindRgbImages(v.accum, RTGI_LPV_ACC_IMG_ACCUM_R, GL_READ_WRITE, v.format);
        bindHiImages(v.accumHi, RTGI_LPV_ACC_IMG_ACCUM_HI_R, GL_READ_WRITE, v.format);
        gl::dispatch(acc, v.grid.x, v.grid.y, v.grid.z);
    }
    src_ = dst;
    for (int j = k; j < k + count; ++j) nearStep(j);
    k_ += count;
}

int propagateCompute(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v, int iterations, bool near,
                     bool visibility, int fuse, int nearIterations, bool faceKernel) {
    ComputePropagation p(programs, ubo, v, iterations, near, visibility, fuse, nearIterations, faceKernel);
    while (!p.done()) p.step();
    return p.last();
}

std::vector<gl::NamedTextureDesc> jointTextures(glm::ivec3 g, GLenum format) {
    std::vector<gl::NamedTextureDesc> t;
    const glm::ivec3 stacked{g.x, g.y, kJointCascades * g.z};
    for (int k = 0; k < 2; ++k) addRgb(t, "lpv.joint.step" + std::to_string(k), volumeDesc(stacked, format));
    addRgb(t, "lpv.joint.accum", volumeDesc(stacked, format));
    return t;
}

void JointVolumes::ensure(gl::MemoryLedger& ledger, glm::ivec3 g, GLenum format) {
    // Every texel is written before it is read (the copies in, then whole steps): no clear.
    const gl::TextureDesc d = volumeDesc({g.x, g.y, kJointCascades * g.z}, format);
    for (int k = 0; k < 2; ++k) ensureRgb(ledger, step[std::size_t(k)], "lpv.joint.step" + std::to_string(k), d, false);
    ensureRgb(ledger, accum, "lpv.joint.accum", d, false);
}

bool jointPropagationApplies(int cascades, int shOrder, int fuse, bool visibility) {
    return cascades >= 2 && shOrder == 1 && fuse == 1 && !visibility;
}

namespace {
// Copies volume `from` (z from fromZ) into `to` (z from toZ), grid g, every channel.
void copySlab(const Rgb& from, int fromZ, Rgb& to, int toZ, glm::ivec3 g) {
    for (std::size_t c = 0; c < 3; ++c)
        glCopyImageSubData(from[c].id(), GL_TEXTURE_3D, 0, 0, 0, fromZ, to[c].id(), GL_TEXTURE_3D, 0, 0, 0, toZ, g.x,
                           g.y, g.z);
}
}  // namespace

int propagateJoint(gl::ProgramCache& programs, const gl::Buffer& ubo, const std::vector<Volumes*>& vs,
                   const std::vector<bool>& near, JointVolumes& joint, int iterations) {
    const int n = int(vs.size());
    if (n < 1 || n > kJointCascades || int(near.size()) != n)
        throw std::logic_error("lpv::propagateJoint: 1.." + std::to_string(kJointCascades) + " cascades");
    const glm::ivec3 g = vs[0]->grid;
    const GLenum format = vs[0]->format;
    for (const Volumes* v : vs)
        if (v->grid != g || v->format != format || v->shOrder != 1)
            throw std::logic_error("lpv::propagateJoint: the cascades differ in grid, format or SH order");
    gl::Defines defines = formatDefines(format);
    defines.push_back({"RTGI_LPV_JOINT", ""});
    const gl::Program& prog = programs.compute("lpv/propagate.comp", defines);
    // The near part as in propagateCompute: accum_K, then mixed with accum_{K+1} by f.
    int nearK = 0;
    while (nearK + 1 <= iterations && cascadeNearWeight(nearK + 1, iterations) >= 1.0) ++nearK;
    float nearF = nearK + 1 <= iterations ? float(cascadeNearWeight(nearK + 1, iterations)) : 0.0f;
    auto nearStep = [&](int k) {
        for (int i = 0; i < n; ++i) {
            if (!near[std::size_t(i)]) continue;
            Volumes& v = *vs[std::size_t(i)];
            if (k == nearK) {
                // Producer: lpv.pack (k = 0, step[0]) or iteration k (the stacked sum), image stores.
                // step[0] is read as textures by the compute copy, the sum by glCopyImageSubData.
                glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                                GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
                if (k == 0)
                    copyVolumes(programs, v.step[0], v.near, g, format);
                else
                    copySlab(joint.accum, i * g.z, v.near, 0, g);
            } else if (k == nearK + 1 && nearF > 0.0f) {
                const gl::Program& mix = programs.compute("lpv/near.comp", formatDefines(format));
                // Producers: the copy above and iteration k's stores into the stacked sum.
                glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                                GL_TEXTURE_UPDATE_BARRIER_BIT);
                bindRgbTextures(joint.accum, RTGI_LPV_TEX_SOURCE_R);
                bindRgbImages(v.near, RTGI_LPV_IMG_NEAR_R, GL_READ_WRITE, format);
                mix.set(RTGI_LPV_LOC_NEAR_FRACTION, nearF);
                mix.set(RTGI_LPV_LOC_NEAR_OFFSET, i * g.z);
                gl::dispatch(mix, g.x, g.y, g.z);
            }
        }
    };
    bindUbo(ubo);  // the first cascade's: the propagation reads only what all cascades share (grid, flags)
    // Producer: lpv.pack (image stores into each cascade's step[0]).
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    for (int i = 0; i < n; ++i) copySlab(vs[std::size_t(i)]->step[0], 0, joint.step[0], i * g.z, g);
    nearStep(0);
    // Whole workgroups per cascade along z (the shader splits by workgroup index).
    const int zGroups = (g.z + RTGI_LPV_LOCAL_3D - 1) / RTGI_LPV_LOCAL_3D;
    int src = 0;
    for (int k = 1; k <= iterations; ++k) {
        const int dst = 1 - src;
        // Rebound every iteration: the near part's mix uses units of its own.
        glBindTextureUnit(RTGI_LPV_TEX_GEOMETRY, vs[0]->geometry.id());
        glBindTextureUnit(RTGI_LPV_TEX_GEOMETRY_ALBEDO, vs[0]->geometryAlbedo.id());
        glBindTextureUnit(RTGI_LPV_TEX_GEOMETRY_AXES, vs[0]->geometryAxes.id());
        const Volumes& last = *vs[std::size_t(n - 1)];
        glBindTextureUnit(RTGI_LPV_TEX_JOINT_GEOMETRY_1, last.geometry.id());
        glBindTextureUnit(RTGI_LPV_TEX_JOINT_GEOMETRY_ALBEDO_1, last.geometryAlbedo.id());
        glBindTextureUnit(RTGI_LPV_TEX_JOINT_GEOMETRY_AXES_1, last.geometryAxes.id());
        bindRgbImages(joint.accum, RTGI_LPV_IMG_ACCUM_R, GL_READ_WRITE, format);
        // Producer: the copies in / the previous iteration (image stores into step[src] and accum).
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_TEXTURE_UPDATE_BARRIER_BIT);
        bindRgbTextures(joint.step[std::size_t(src)], RTGI_LPV_TEX_SRC_R);
        bindRgbImages(joint.step[std::size_t(dst)], RTGI_LPV_IMG_DST_R, GL_WRITE_ONLY, format);
        prog.set(RTGI_LPV_LOC_ITERATION, k);
        gl::dispatch(prog, g.x, g.y, n * zGroups * RTGI_LPV_LOCAL_3D);
        src = dst;
        nearStep(k);
    }
    // The results where the per-cascade propagation leaves them: accum and the last step.
    // Producer: the last iteration (image stores).
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    for (int i = 0; i < n; ++i) {
        copySlab(joint.accum, i * g.z, vs[std::size_t(i)]->accum, 0, g);
        copySlab(joint.step[std::size_t(src)], i * g.z, vs[std::size_t(i)]->step[std::size_t(src)], 0, g);
    }
    return src;
}

int propagateRaster(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v, int iterations) {
    v.ensureRasterTargets();
    const gl::Program& prog = programs.raster("lpv/propagate_raster.vert", "lpv/propagate_raster.frag",
                                              formatDefines(v.format), "lpv/propagate_raster.geom");
    bindUbo(ubo);
    glUseProgram(prog.id());
    glBindVertexArray(v.emptyVao.id());
    glBindTextureUnit(RTGI_LPV_TEX_GEOMETRY, v.geometry.id());
    glBindTextureUnit(RTGI_LPV_TEX_GEOMETRY_ALBEDO, v.geometryAlbedo.id());
    glBindTextureUnit(RTGI_LPV_TEX_GEOMETRY_AXES, v.geometryAxes.id());
    int src = 0;
    for (int k = 1; k <= iterations; ++k) {
        int dst = 1 - src;
        rasterState(v, v.propagateFbo[std::size_t(dst)].id(), false);
        // Producer: the previous draw's framebuffer writes into step[src].
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
        bindRgbTextures(v.step[std::size_t(src)], RTGI_LPV_TEX_SRC_R);
        prog.set(RTGI_LPV_LOC_ITERATION, k);
        glDrawArraysInstanced(GL_TRIANGLES, 0, 3, v.grid.z);
        gl::Profiler::noteDispatch();
        src = dst;
    }
    endRaster();
    return src;
}

namespace {
// out = mix(cur, prev re-indexed by the cell shift, lpv.temporal) (lpv/temporal.comp).
void blendVolume(gl::ProgramCache& programs, const gl::Buffer& ubo, const Volumes& v, const Rgb& cur, const Hi& curHi,
                 const Rgb& prev, const Hi& prevHi, const Rgb& out, const Hi& outHi) {
    const gl::Program& prog = programs.compute("lpv/temporal.comp", formatDefines(v.format, v.shOrder));
    bindUbo(ubo);
    // Producer: lpv.propagate (image stores / blended framebuffer writes into accum and near).
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    bindRgbTextures(cur, RTGI_LPV_TEX_CUR_R);
    bindRgbTextures(prev, RTGI_LPV_TEX_PREV_R);
    bindRgbImages(out, RTGI_LPV_IMG_OUT_R, GL_WRITE_ONLY, v.format);
    if (v.shOrder == 2) {
        bindHiTextures(curHi, RTGI_LPV_TEX_CUR_HI_R);
        bindHiTextures(prevHi, RTGI_LPV_TEX_PREV_HI_R);
        bindHiImages(outHi, RTGI_LPV_IMG_OUT_HI_R, GL_WRITE_ONLY, v.format);
    }
    gl::dispatch(prog, v.grid.x, v.grid.y, v.grid.z);
}
}  // namespace

void temporalBlend(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v, int target) {
    const auto t = std::size_t(target), p = std::size_t(1 - target);
    blendVolume(programs, ubo, v, v.accum, v.accumHi, v.history[p], v.historyHi[p], v.history[t], v.historyHi[t]);
}

void temporalBlendNear(gl::ProgramCache& programs, const gl::Buffer& ubo, Volumes& v, int target) {
    const auto t = std::size_t(target), p = std::size_t(1 - target);
    blendVolume(programs, ubo, v, v.near, v.nearHi, v.nearHistory[p], v.nearHistoryHi[p], v.nearHistory[t],
                v.nearHistoryHi[t]);
}

void applyCompute(gl::ProgramCache& programs, const gl::Buffer& ubo, const ApplyInputs& in) {
    gl::Defines d;
    const gl::Texture* directional = in.s3ho ? in.s3ho : in.bentNormal;
    if (in.s3ho) d.push_back({"RTGI_LPV_S3HO", ""});
    else if (in.bentNormal) d.push_back({"RTGI_LPV_BENT_NORMAL", ""});
    if (in.rsm) d.push_back({"RTGI_LPV_SELF", ""});
    const bool cascaded = in.cascades > 1;
    if (cascaded) d.push_back({"RTGI_LPV_CASCADED", ""});
    if (in.volumeHi) d.push_back({"RTGI_LPV_SH2", ""});
    if (in.geometry) d.push_back({"RTGI_LPV_LOOKUP_GEOMETRY", ""});
    else if (in.visibility) appendVisibilityDefines(d, in.visibilityExponent, in.visibilityViewBias);
    if (in.damping) d.push_back({"RTGI_LPV_DAMPING", ""});
    if (in.sky) d.push_back({"RTGI_LPV_SKY", ""});
    if (in.sky && in.skySelf) d.push_back({"RTGI_LPV_SKY_SELF", ""});
    if (in.lowGeometry) d.push_back({"RTGI_LPV_APPLY_HALF", ""});
    // The specular in a dispatch of its own after the diffuse one (docs/lpv.md, "Apply cost"): the same
    // shader, each variant lighter than both in one. The two write different images.
    const gl::Program& prog = programs.compute("lpv/apply.comp", d);
    const gl::Program* specularProg = nullptr;
    if (in.specular) {
        gl::Defines ds = d;
        ds.push_back({"RTGI_LPV_SPECULAR", ""});
        ds.push_back({"RTGI_LPV_APPLY_SPECULAR_ONLY", ""});
        if (in.brdfLut) ds.push_back({"RTGI_LPV_BRDF_LUT", ""});
        specularProg = &programs.compute("lpv/apply.comp", ds);
    }
    bindUbo(ubo);
    // Producers: lpv.propagate / lpv.temporal (image stores or blended draws), gbuffer, ao.*, brdf_lut.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    const GBufferView& g = in.gbuffer;
    const Rgb& light = *in.volume;
    gl::ScopedBindings b;
    b.texture(RTGI_LPV_TEX_LINEAR_DEPTH, g.linearDepth)
        .texture(RTGI_LPV_TEX_VIEW_NORMAL, g.normal)
        .texture(RTGI_LPV_TEX_ALBEDO, g.albedo)
        .texture(RTGI_LPV_TEX_MATERIAL, g.material)
        .texture(RTGI_LPV_TEX_LIGHT_R, light[0])
        .texture(RTGI_LPV_TEX_LIGHT_G, light[1])
        .texture(RTGI_LPV_TEX_LIGHT_B, light[2])
        .texture(RTGI_LPV_TEX_BRDF_LUT, in.brdfLut)
        .texture(RTGI_LPV_TEX_DIRECTIONAL, directional)
        .image(RTGI_LPV_IMG_INDIRECT, *in.indirect, GL_WRITE_ONLY, GL_RGBA16F);
    if (in.specular) b.image(RTGI_LPV_IMG_SPECULAR, *in.specular, GL_WRITE_ONLY, GL_RGBA16F);
    if (in.lowGeometry) b.image(RTGI_LPV_IMG_APPLY_LOW_GEOMETRY, *in.lowGeometry, GL_WRITE_ONLY, GL_RGBA32F);
    if (in.volumeHi)
        b.texture(RTGI_LPV_TEX_LIGHT_HI_R, (*in.volumeHi)[0])
            .texture(RTGI_LPV_TEX_LIGHT_HI_G, (*in.volumeHi)[1])
            .texture(RTGI_LPV_TEX_LIGHT_HI_B, (*in.volumeHi)[2])
            .texture(RTGI_LPV_TEX_LIGHT_LAST, (*in.volumeHi)[3]);
    if (in.geometry) b.texture(RTGI_LPV_TEX_APPLY_GEOMETRY, *in.geometry).texture(RTGI_LPV_TEX_APPLY_GEOMETRY_AXES, in.geometryAxes);
    if (!in.geometry && in.visibility) b.texture(RTGI_LPV_TEX_APPLY_VISIBILITY, *in.visibility);
    if (in.sky) b.texture(RTGI_LPV_TEX_APPLY_SKY, *in.sky);
    if (in.rsm) b.texture(RTGI_LPV_TEX_APPLY_RSM_FLUX, in.rsm->flux).texture(RTGI_LPV_TEX_APPLY_RSM_DEPTH, in.rsm->depth);
    if (cascaded) {
        if (in.cascade > 0)
            b.texture(RTGI_LPV_TEX_APPLY_NEAR_R, (*in.near)[0])
                .texture(RTGI_LPV_TEX_APPLY_NEAR_G, (*in.near)[1])
                .texture(RTGI_LPV_TEX_APPLY_NEAR_B, (*in.near)[2]);
        if (in.cascade > 0 && in.nearHi)
            b.texture(RTGI_LPV_TEX_APPLY_NEAR_HI_R, (*in.nearHi)[0])
                .texture(RTGI_LPV_TEX_APPLY_NEAR_HI_G, (*in.nearHi)[1])
                .texture(RTGI_LPV_TEX_APPLY_NEAR_HI_B, (*in.nearHi)[2])
                .texture(RTGI_LPV_TEX_APPLY_NEAR_LAST, (*in.nearHi)[3]);
        // Producer: the previous cascade's dispatch (image stores into the sums).
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        b.image(RTGI_LPV_IMG_APPLY_SUM_E, *in.sumE, GL_READ_WRITE, GL_RGBA32F)
            .image(RTGI_LPV_IMG_APPLY_SUM_S, *in.sumS, GL_READ_WRITE, GL_RGBA32F);
        prog.set(RTGI_LPV_LOC_APPLY_LAST, in.cascade == in.cascades - 1 ? 1 : 0);
        if (specularProg) specularProg->set(RTGI_LPV_LOC_APPLY_LAST, in.cascade == in.cascades - 1 ? 1 : 0);
    }
    const glm::ivec2 size = in.lowGeometry ? applyHalfSize(g.size) : g.size;
    gl::dispatch(prog, size.x, size.y);
    if (specularProg) gl::dispatch(*specularProg, size.x, size.y);
}

void applyUpsample(gl::ProgramCache& programs, const gl::Buffer& ubo, const UpsampleInputs& in) {
    gl::Defines d;
    if (in.specular) d.push_back({"RTGI_LPV_SPECULAR", ""});
    if (in.specular && in.brdfLut) d.push_back({"RTGI_LPV_BRDF_LUT", ""});
    const gl::Program& prog = programs.compute("lpv/upsample.comp", d);
    bindUbo(ubo);
    // Producer: the half-resolution lpv.apply (image stores), read as textures here.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    const GBufferView& g = in.gbuffer;
    gl::ScopedBindings b;
    b.texture(RTGI_LPV_TEX_LINEAR_DEPTH, g.linearDepth)
        .texture(RTGI_LPV_TEX_VIEW_NORMAL, g.normal)
        .texture(RTGI_LPV_TEX_ALBEDO, g.albedo)
        .texture(RTGI_LPV_TEX_MATERIAL, g.material)
        .texture(RTGI_LPV_TEX_BRDF_LUT, in.specular ? in.brdfLut : nullptr)
        .texture(RTGI_LPV_UPSAMPLE_TEX_LOW_INDIRECT, in.lowIndirect)
        .texture(RTGI_LPV_UPSAMPLE_TEX_LOW_SPECULAR, in.specular ? in.lowSpecular : nullptr)
        .texture(RTGI_LPV_UPSAMPLE_TEX_LOW_GEOMETRY, in.lowGeometry)
        .image(RTGI_LPV_IMG_INDIRECT, *in.indirect, GL_WRITE_ONLY, GL_RGBA16F);
    if (in.specular) b.image(RTGI_LPV_IMG_SPECULAR, *in.specular, GL_WRITE_ONLY, GL_RGBA16F);
    gl::dispatch(prog, g.size.x, g.size.y);
}

}  // namespace rtgi::lpv
