// LPV end to end on scenes: raster baseline vs compute path, extremes of
// sun intensity and cell size, a volume that misses the scene, pruning,
// LPV specular (listing 8) on a uniform SH volume against a CPU evaluation.
#include "gpu_fixture.h"

#include "render/lpv/lpv_math.h"
#include "render/lpv/lpv_volumes.h"
#include "render/reference/reference_passes.h"

#include <glm/gtx/component_wise.hpp>

#include <algorithm>
#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const double kPi = 3.14159265358979323846;



// Accumulated LPV volume (R, G, B) as floats, through the pass's checked outputs.
std::vector<float> accumulated(const Renderer& r) {
    std::vector<float> out;
    Pass* p = r.findPass("lpv.propagate");
    REQUIRE(p != nullptr);
    for (auto& o : r.checkedOutputs(*p))
        for (int z = 0; z < o.tex->depth(); ++z) {
            FloatImage img = readTexture(*o.tex, z);
            out.insert(out.end(), img.data.begin(), img.data.end());
        }
    return out;
}

double relL2(const std::vector<float>& a, const std::vector<float>& b) {
    double n = 0, d = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        n += double(a[i] - b[i]) * double(a[i] - b[i]);
        d += double(b[i]) * double(b[i]);
    }
    return d > 0 ? std::sqrt(n / d) : std::sqrt(n);
}

}  // namespace

TEST_CASE("LPV raster baseline produces the compute path's volumes on the cornell scene") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = loadBuiltin("cornell");
    for (auto format : {LpvSettings::Format::Rgba32f, LpvSettings::Format::Rgba16f}) {
        Settings s = smallLpvSettings();
        s.lpv.format = format;
        auto compute = renderFrames(scene, s, {32, 32}, prof);
        std::vector<float> a = accumulated(*compute);
        s.lpv.path = LpvSettings::Path::Raster;
        auto raster = renderFrames(scene, s, {32, 32}, prof);
        CHECK(raster->findPass("lpv.pack") == nullptr);
        std::vector<float> b = accumulated(*raster);
        REQUIRE(a.size() == b.size());
        double mx = 0;
        for (float x : a) mx = std::max(mx, double(std::abs(x)));
        CHECK(mx > 0.0);
        // Same math from the same GLSL. fp32: only the summation order of injected points
        // differs (blending vs atomics): 1e-5. fp16: the raster path blends every injected
        // point into a half partial sum (each add rounded, towards zero on llvmpipe, 2^-10
        // relative), the compute path sums in fp32 and rounds once; with tens of points per
        // cell and 4 iterations that bias reaches ~6e-3: 1e-2 (about ten half ulps).
        CHECK(relL2(b, a) <= (format == LpvSettings::Format::Rgba32f ? 1e-5 : 1e-2));
    }
}

TEST_CASE("LPV raster baseline (one draw per local RSM face) produces the compute path's batched and cached volumes on the gallery") {
    // builtin:gallery (spot and point lights, no sun): the compute path injects every local face of
    // the RSM arrays in one dispatch, and from the third frame out of the injection cache
    // (lpv.inject_cache=on); the raster baseline draws one point per texel of each face. fp32: only
    // the summation order differs (1e-5, as on cornell above).
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = loadBuiltin("gallery");
    Settings s = smallLpvSettings();
    s.lpv.rsm = 16;
    s.lpv.format = LpvSettings::Format::Rgba32f;
    s.light.localShadowSize = 32;
    for (bool cache : {true, false}) {
        CAPTURE(cache);
        s.lpv.injectCache = cache;
        s.lpv.path = LpvSettings::Path::Compute;
        auto compute = renderFrames(scene, s, {32, 32}, prof, 3);
        double fromCache = 0;
        for (auto& [k, v] : compute->findPass("lpv.inject")->stats())
            if (k == "local_faces_from_cache") fromCache = v;
        CHECK((fromCache > 0.0) == cache);
        std::vector<float> a = accumulated(*compute);
        s.lpv.path = LpvSettings::Path::Raster;
        auto raster = renderFrames(scene, s, {32, 32}, prof, 3);
        std::vector<float> b = accumulated(*raster);
        REQUIRE(a.size() == b.size());
        double mx = 0;
        for (float x : a) mx = std::max(mx, double(std::abs(x)));
        CHECK(mx > 0.0);
        CHECK(relL2(b, a) <= 1e-5);
    }
}

TEST_CASE("LPV extremes: sun 1e-6..1e6 is linear in fp32 and finite in fp16; a volume off the scene gives no light") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = loadBuiltin("cornell");
    Settings s = smallLpvSettings();
    s.lpv.format = LpvSettings::Format::Rgba32f;
    s.light.sunIrradiance = 1.0f;
    std::vector<float> ref = accumulated(*renderFrames(scene, s, {16, 16}, prof));
    for (float e : {1e-6f, 1e6f}) {
        s.light.sunIrradiance = e;
        std::vector<float> v = accumulated(*renderFrames(scene, s, {16, 16}, prof));
        for (float& x : v) x /= e;
        // fp32 relative rounding, independent of the magnitude (no denormals at 1e-6 x flux).
        CHECK(relL2(v, ref) <= 1e-5);
    }
    // fp16: 1e6 saturates the volume at the largest half (documented clamp), never Inf/NaN.
    s.lpv.format = LpvSettings::Format::Rgba16f;
    s.light.sunIrradiance = 1e6f;
    auto r = renderFrames(scene, s, {16, 16}, prof);
    r->setCheck(true);
    r->render(makeView(resolveCamera(scene, s), {16, 16}, nullptr, 0));
    for (auto& f : r->finiteCounts()) {
        INFO(f.pass << " " << f.resource);
        CHECK(f.nan == 0);
        CHECK(f.inf == 0);
    }
    // A camera-following volume of 8 cells of 1 mm, 30 % ahead of the camera (in the air
    // in front of the box): the RSM fitted to it sees no surface, nothing is injected and
    // no pixel receives LPV light.
    s.lpv.cell = 1e-3f;
    s.light.sunIrradiance = 1.0f;
    auto off = renderFrames(scene, s, {16, 16}, prof);
    for (float x : accumulated(*off)) CHECK(x == 0.0f);
    FloatImage ind = readTexture(off->resources().indirectDiffuse);
    double sum = 0, minAlpha = 1, maxRgb = 0;
    int below = 0, first = -1;
    for (std::size_t i = 0; i < ind.data.size(); ++i) {
        sum += ind.data[i];
        if (i % 4 == 3 && ind.data[i] != 1.0f && below++ == 0) first = int(i / 4);
        if (i % 4 == 3) minAlpha = std::min(minAlpha, double(ind.data[i]));
        else maxRgb = std::max(maxRgb, double(std::abs(ind.data[i])));
    }
    INFO("alpha below 1 at " << below << " pixels (first: pixel " << first << "), lowest " << minAlpha
                              << ", largest |rgb| " << maxRgb);
    CHECK(sum == doctest::Approx(16.0 * 16.0).epsilon(1e-9));  // only the alpha channel (1) is non-zero
}

TEST_CASE("LPV radiance is invariant under scaling the scene by 1e-3 and 1e3 (auto-fitted cells)") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene base = loadBuiltin("cornell");
    Settings s = smallLpvSettings();
    s.lpv.format = LpvSettings::Format::Rgba32f;
    s.lpv.occlusion = s.lpv.bounce = false;  // the G-buffer blockers' areas depend on pixel footprints only
    auto render = [&](float k) {
        Scene sc = scaledScene(base, k);
        return readTexture(renderFrames(sc, s, {24, 24}, prof)->resources().indirectDiffuse);
    };
    FloatImage ref = render(1.0f);
    double refSum = 0;  // the RGB channels (alpha: the sky visibility of lpv.sky=visibility, docs/lpv.md)
    for (std::size_t i = 0; i < ref.data.size(); ++i)
        if (i % std::size_t(ref.channels) != 3) refSum += ref.data[i];
    CHECK(refSum > 0.0);  // some indirect light
    for (float k : {1e-3f, 1e3f}) {
        FloatImage img = render(k);
        double num = 0, den = 0;
        for (std::size_t i = 0; i < img.data.size(); ++i) {
            num += std::pow(double(img.data[i] - ref.data[i]), 2);
            den += std::pow(double(ref.data[i]), 2);
        }
        // Radiance depends on E_perp and albedos only; scaling changes fp32 rounding of positions
        // (cell assignment of texels right on a boundary) and fp16 output rounding: 1 %.
        CHECK(std::sqrt(num / den) <= 1e-2);
    }
}

TEST_CASE("LPV pass pruning: no sun -> no LPV passes; occlusion/bounce off -> no geometry volume") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Settings s = smallLpvSettings();
    s.lpv.mode = Toggle::Auto;
    Scene dark = floorScene(2, glm::vec3(0.5f), false);
    Renderer r(dark, s, prof);
    for (auto& p : r.passes()) CHECK(p->name().rfind("lpv.", 0) != 0);
    Scene lit = floorScene(2, glm::vec3(0.5f), true);
    s.lpv.occlusion = s.lpv.bounce = false;
    Renderer r2(lit, s, prof);
    CHECK(r2.findPass("lpv.rsm") != nullptr);
    CHECK(r2.findPass("lpv.apply") != nullptr);
    CHECK(r2.findPass("lpv.inject_geometry") == nullptr);
    CHECK(r2.findPass("lpv.temporal") == nullptr);
}

namespace {

// A volume holding the lobe k_c cosLobe9(dir) (lpv::shCosineLobe9, tested against integrals in the
// unit tier) in every cell: trilinear lookups return it exactly. `lo` alone is the band-1 volume
// k_c cosLobe(dir), `lo` + `hi` the band-2 one (docs/lpv.md, "Second-order SH").
struct UniformVolume {
    lpv::Rgb lo;
    lpv::Hi hi;
};
UniformVolume uniformVolume(gl::MemoryLedger& ledger, const lpv::Placement& pl, glm::dvec3 dir, const double k[3]) {
    auto texture = [&](glm::vec4 v) {
        gl::Texture t(ledger, "t.volume", {GL_TEXTURE_3D, GL_RGBA32F, pl.grid.x, pl.grid.y, pl.grid.z});
        t.setSampling(GL_LINEAR, GL_LINEAR);
        std::vector<glm::vec4> data(std::size_t(pl.grid.x * pl.grid.y * pl.grid.z), v);
        glTextureSubImage3D(t.id(), 0, 0, 0, 0, pl.grid.x, pl.grid.y, pl.grid.z, GL_RGBA, GL_FLOAT, data.data());
        return t;
    };
    lpv::Sh9 l = lpv::shCosineLobe9(dir);
    UniformVolume u;
    for (int c = 0; c < 3; ++c) {
        u.lo[std::size_t(c)] = texture(glm::vec4(glm::dvec4(l[0], l[1], l[2], l[3]) * k[c]));
        u.hi[std::size_t(c)] = texture(glm::vec4(glm::dvec4(l[4], l[5], l[6], l[7]) * k[c]));
    }
    u.hi[3] = texture(glm::vec4(float(k[0] * l[8]), float(k[1] * l[8]), float(k[2] * l[8]), 0.0f));
    return u;
}

}  // namespace

TEST_CASE("LPV specular: 3 samples along R of a uniform SH volume equal listing 8 evaluated on the CPU") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    const glm::ivec2 size{24, 24};
    Scene scene = floorScene(2.0f, glm::vec3(0.5f), true, {0.3f, 1.0f, 0.2f});
    scene.materials[0].metallic = 1.0f;  // mirror-like: F0 = albedo, no diffuse
    scene.materials[0].roughness = 0.02f;
    Settings s = smallLpvSettings();
    s.lpv.format = LpvSettings::Format::Rgba32f;
    s.lpv.specular = Toggle::On;
    s.lpv.occlusion = s.lpv.bounce = false;
    s.ssr.tracer = SsrSettings::Tracer::Off;  // no split-sum LUT: listing 8 times F0 (docs/lpv.md)
    auto r = renderFrames(scene, s, size, prof);  // G-buffer + frame uniforms (binding 0 stays bound)
    FrameResources& res = r->resources();

    // A volume holding the same SH lobe in every cell: trilinear lookups return it exactly.
    Camera cam = resolveCamera(scene, s);
    lpv::Placement pl = lpv::placeVolume(s.lpv, scene.bounds(), cam.position, glm::normalize(cam.target - cam.position));
    const glm::dvec3 lobeDir = glm::normalize(glm::dvec3(0.3, -0.8, 0.5));
    const double k[3] = {2.0, 1.0, 0.5};
    gl::MemoryLedger ledger;
    gl::ProgramCache programs;
    // lpv.sh_order = 1, then 2 (the band-2 lobe k cosLobe9 in the 7 textures of docs/lpv.md).
    UniformVolume uv = uniformVolume(ledger, pl, lobeDir, k);
    for (int order = 1; order <= 2; ++order) {
    CAPTURE(order);
    lpv::UniformInputs in;
    in.placement = pl;
    in.specular = true;
    gpu::LpvUniforms u = lpv::makeUniforms(s.lpv, in);
    gl::Buffer ubo(ledger, "t.lpv.uniforms", sizeof(u), &u);
    gl::Texture indirect(ledger, "t.indirect", {GL_TEXTURE_2D, GL_RGBA16F, size.x, size.y});
    gl::Texture specular(ledger, "t.specular", {GL_TEXTURE_2D, GL_RGBA16F, size.x, size.y});
    lpv::ApplyInputs ai;
    ai.gbuffer = {&res.gbuffer.linearDepth, &res.gbuffer.normal, &res.gbuffer.albedo, &res.gbuffer.material, size};
    ai.volume = &uv.lo;
    ai.volumeHi = order == 2 ? &uv.hi : nullptr;
    ai.indirect = &indirect;
    ai.specular = &specular;
    lpv::applyCompute(programs, ubo, ai);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    FloatImage spec = readTexture(specular), depth = readTexture(res.gbuffer.linearDepth),
               albedo = readTexture(res.gbuffer.albedo);

    // CPU: listing 8 -- mean over i = 1..3 of max(0, I(-R)) / s^2 at p + i s R (0 outside the grid), times F0.
    View v = makeView(cam, size, nullptr, 0);
    glm::dmat4 invView = glm::inverse(glm::dmat4(v.view));
    double th = std::tan(0.5 * double(cam.fovY)), aspect = double(size.x) / double(size.y), cell = pl.cell;
    int checked = 0, lit = 0;
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
            double d = depth.at(x, y, 0);
            if (!(d > 0)) continue;
            glm::dvec2 ndc((x + 0.5) / size.x * 2.0 - 1.0, (y + 0.5) / size.y * 2.0 - 1.0);
            glm::dvec3 p(invView * glm::dvec4(ndc.x * th * aspect * d, ndc.y * th * d, -d, 1.0));
            glm::dvec3 view = glm::normalize(glm::dvec3(cam.position) - p), R = glm::reflect(-view, glm::dvec3(0, 1, 0));
            double sum = 0;
            bool nearEdge = false;
            for (int i = 1; i <= 3; ++i) {
                glm::dvec3 q = (p + R * (i * cell) - glm::dvec3(pl.origin)) / (cell * glm::dvec3(pl.grid));
                double margin = std::min(glm::compMin(q), 1.0 - glm::compMax(q));
                nearEdge = nearEdge || std::abs(margin) < 1e-3;  // float positions may put it on either side
                if (margin >= 0.0) sum += 1.0;
            }
            if (nearEdge) continue;
            for (int c = 0; c < 3; ++c) {
                // I(w) of k cosLobe(n) is k (1/4 + n.w / 2) (band 0-1 clamped cosine, docs/lpv.md);
                // bands 0-2 add k (5/16) P2(n.w) = k (5/32)(3 (n.w)^2 - 1) (A_2 = pi/4, sum_m Y2m Y2m = 5/(4 pi) P2).
                double cw = glm::dot(lobeDir, -R);
                double I = std::max(0.0, k[c] * (0.25 + 0.5 * cw + (order == 2 ? 5.0 / 32.0 * (3.0 * cw * cw - 1.0) : 0.0)));
                double expected = albedo.at(x, y, c) * sum / 3.0 * I / (cell * cell);
                // fp16 output (11-bit mantissa) and fp32 positions: 2e-3 relative.
                CHECK(spec.at(x, y, c) == doctest::Approx(expected).epsilon(2e-3));
            }
            ++checked;
            lit += sum > 0 ? 1 : 0;
        }
    CHECK(checked > size.x * size.y / 4);
    CHECK(lit > 0);
    }
}

TEST_CASE("LPV diffuse apply: a uniform SH volume gives <mirror(I), cosLobe(n)> / s^2 in bands 0-1 and 0-2") {
    // Irradiance of a lobe k cosLobe(a) flowing through every cell at a receiver of normal n
    // (docs/lpv.md, apply; "Second-order SH"): sum_l (-1)^l A_l^2 (2l + 1) / (4 pi) P_l(a.n), i.e.
    // k (pi/4 - (pi/3) c) for band 1 and + k (5 pi / 64) P2(c) for band 2, c = a.n; outgoing
    // radiance albedo / pi * E (metallic 0, lpv.strength 1).
    GpuFixture gpu;
    gl::Profiler prof(false);
    const glm::ivec2 size{24, 24};
    Scene scene = floorScene(2.0f, glm::vec3(0.5f), true, {0.3f, 1.0f, 0.2f});
    scene.materials[0].metallic = 0.0f;
    Settings s = smallLpvSettings();
    s.lpv.format = LpvSettings::Format::Rgba32f;
    s.lpv.specular = Toggle::Off;
    s.lpv.occlusion = s.lpv.bounce = false;
    auto r = renderFrames(scene, s, size, prof);
    FrameResources& res = r->resources();
    Camera cam = resolveCamera(scene, s);
    lpv::Placement pl = lpv::placeVolume(s.lpv, scene.bounds(), cam.position, glm::normalize(cam.target - cam.position));
    const glm::dvec3 a = glm::normalize(glm::dvec3(0.3, -0.8, 0.5));
    const double k[3] = {2.0, 1.0, 0.5};
    gl::MemoryLedger ledger;
    gl::ProgramCache programs;
    FloatImage depth = readTexture(res.gbuffer.linearDepth), albedo = readTexture(res.gbuffer.albedo);
    UniformVolume uv = uniformVolume(ledger, pl, a, k);
    for (int order = 1; order <= 2; ++order) {
        CAPTURE(order);
        lpv::UniformInputs in;
        in.placement = pl;
        gpu::LpvUniforms u = lpv::makeUniforms(s.lpv, in);
        gl::Buffer ubo(ledger, "t.lpv.uniforms", sizeof(u), &u);
        gl::Texture indirect(ledger, "t.indirect", {GL_TEXTURE_2D, GL_RGBA16F, size.x, size.y});
        lpv::ApplyInputs ai;
        ai.gbuffer = {&res.gbuffer.linearDepth, &res.gbuffer.normal, &res.gbuffer.albedo, &res.gbuffer.material, size};
        ai.volume = &uv.lo;
        ai.volumeHi = order == 2 ? &uv.hi : nullptr;
        ai.indirect = &indirect;
        lpv::applyCompute(programs, ubo, ai);
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
        FloatImage out = readTexture(indirect);
        const double c = glm::dot(a, glm::dvec3(0, 1, 0)), cell = pl.cell;
        const double e = kPi / 4.0 - kPi / 3.0 * c + (order == 2 ? 5.0 * kPi / 64.0 * 0.5 * (3.0 * c * c - 1.0) : 0.0);
        int checked = 0;
        for (int y = 0; y < size.y; ++y)
            for (int x = 0; x < size.x; ++x) {
                if (!(depth.at(x, y, 0) > 0) || out.at(x, y, 0) == 0.0f) continue;  // sky, or lookup outside the grid
                for (int ch = 0; ch < 3; ++ch) {
                    double expected = albedo.at(x, y, ch) / kPi * std::max(0.0, k[ch] * e) / (cell * cell);
                    CHECK(out.at(x, y, ch) == doctest::Approx(expected).epsilon(2e-3));  // fp16 output
                }
                ++checked;
            }
        CHECK(checked > size.x * size.y / 4);
    }
}

TEST_CASE("LPV on cornell with the defaults beats black against the one-bounce reference and lights the far half") {
    // Issue 12 acceptance on llvmpipe: builtin:cornell with the defaults and the scene's
    // suggestions (lpv.bounce off so one bounce is what both model), against the path
    // tracer's one-bounce Lambert indirect light. skill = 1 - rmse / rmse(black) > 0.3,
    // and the pixels right of the image centre (away from the sunlit red wall) get a mean
    // within a factor of 3 of the reference's. The reference's noise must move the
    // measured RMSE by less than a tenth: independent noise of per-pixel standard error
    // se adds in quadrature, rmse_measured^2 = rmse^2 + mean(se^2), so the noise-free RMSE is
    // sqrt(rmse_measured^2 - mean(se^2)) and the difference must stay below 0.1 rmse.
    // 96x54, not 64x36: at 64x36 one pixel, the foot of the red wall beside the sunlit
    // floor (contact light within one cell: reference 0.94, LPV 0.08; a perfect probe
    // volume misses it too, probe skill 0.31), carried 46 % of the squared error (skill 0.28;
    // 0.39 at 96x54, 0.48 at 128x72, 0.46 at 160x90, docs/lpv.md): a one-pixel line
    // feature whose weight falls with the pixel count, not a property of the volume.
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene scene = loadBuiltin("cornell");
    const glm::ivec2 size{96, 54};
    Settings s = effectiveSettings(scene.suggestedSettings, {{"lpv", "on"}, {"lpv.bounce", "off"}}, scene.name);
    Settings rs = oneBounceReference(s, 256);
    auto ref = renderFrames(scene, rs, size, prof);
    auto* out = dynamic_cast<ReferenceOutput*>(ref->findPass("ref.path"));
    REQUIRE(out != nullptr);
    FloatImage refMean = readTexture(out->mean()), refSe = readTexture(out->standardError());
    auto run = renderFrames(scene, s, size, prof);
    FloatImage lpvImg = readTexture(run->resources().indirectDiffuse);
    FloatImage depth = readTexture(run->resources().gbuffer.linearDepth);
    double se2 = 0, e2 = 0, z2 = 0, rightLpv = 0, rightRef = 0;
    std::size_t n = 0;
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
            if (!(depth.at(x, y, 0) > 0)) continue;
            for (int c = 0; c < 3; ++c) {
                double a = lpvImg.at(x, y, c), r = refMean.at(x, y, c), sd = refSe.at(x, y, c);
                e2 += (a - r) * (a - r);
                z2 += r * r;
                se2 += sd * sd;
                if (x >= size.x / 2) {
                    rightLpv += a;
                    rightRef += r;
                }
            }
            ++n;
        }
    REQUIRE(n > 500);
    double rmse = std::sqrt(e2 / double(3 * n)), rmseZero = std::sqrt(z2 / double(3 * n));
    double noise = std::sqrt(se2 / double(3 * n));
    double skill = 1.0 - rmse / rmseZero;
    MESSAGE("cornell defaults: skill " << skill << " (rmse " << rmse << ", black " << rmseZero << ", reference noise "
                                       << noise << "), right half LPV/ref " << rightLpv / rightRef);
    double clean = std::sqrt(std::max(rmse * rmse - noise * noise, 0.0));
    CHECK(rmse - clean < 0.1 * rmse);
    CHECK(skill > 0.3);
    CHECK(rightLpv / rightRef > 1.0 / 3.0);
    CHECK(rightLpv / rightRef < 3.0);
}
