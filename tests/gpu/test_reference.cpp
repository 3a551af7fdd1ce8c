// GPU tier of the ray-traced reference: GPU BVH traversal == CPU brute
// force; rays at shared vertices and edges never slip through; AO of a plane == 1; AO beside a wall == CPU quadrature over the same
// finite geometry (unbounded and finite rays); furnace (closed box of albedo
// a, emission Le: L = Le/(1-a)); same seed -> same bits; SE ~ 1/sqrt(N);
// cache round trip. Images 32x32, <= 64 samples (llvmpipe budget).
#include "gpu_fixture.h"

#include "render/reference/reference_passes.h"
#include "scene/bvh.h"
#include "watertight_rays.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const glm::ivec2 kSize{32, 32};

Settings referenceSettings(ReferenceSettings::Kind kind, int spp) {
    Settings s;
    s.reference.kind = kind;
    s.reference.spp = spp;
    s.reference.cacheDir = "off";
    s.lpv.mode = Toggle::Off;
    return s;
}

struct RefResult {
    FloatImage mean, se, depth;
    bool fromCache = false;
};

RefResult renderReference(const Scene& scene, const Settings& s) {
    gl::Profiler prof(false);
    auto r = renderFrames(scene, s, kSize, prof);
    auto* out = dynamic_cast<ReferenceOutput*>(r->findPass(s.reference.kind == ReferenceSettings::Kind::Ao ? "ref.ao" : "ref.path"));
    REQUIRE(out != nullptr);
    return {readTexture(out->mean()), readTexture(out->standardError()), readTexture(r->resources().gbuffer.linearDepth),
            out->fromCache()};
}


// Floor [-2,2]^2 at y = 0 and a wall at z = -1, x in [-2,2], y in [0, 1.5], facing +z.
constexpr double kWallZ = -1.0, kWallW = 2.0, kWallH = 1.5;

// AO = (1/π)∫ cos θ V dω over the hemisphere of a floor point; with the
// Malley map (u1 = sin²θ, u2 = φ/2π) the integrand is V on the unit square:
// midpoint rule on n × 2n cells, ray-rectangle test in double.
double aoQuadrature(glm::dvec3 p, double rayLength, double wallW, double wallH, int n = 256) {
    double visible = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < 2 * n; ++j) {
            double u1 = (i + 0.5) / n, phi = 2.0 * M_PI * (j + 0.5) / (2 * n);
            double r = std::sqrt(u1);
            glm::dvec3 d(r * std::cos(phi), std::sqrt(1.0 - u1), r * std::sin(phi));
            bool hit = false;
            if (d.z < 0) {
                double t = (kWallZ - p.z) / d.z;
                glm::dvec3 q = p + t * d;
                hit = t < rayLength && std::abs(q.x) <= wallW && q.y >= 0 && q.y <= wallH;
            }
            if (!hit) visible += 1;
        }
    return visible / double(2 * n * n);
}

}  // namespace

namespace {

struct TestRay {  // ref/trace_test.comp
    glm::vec4 origin, direction;
};

// Traces rays (origin.xyz, tMax in w; direction.xyz) through bvh on the GPU;
// returns direction = (closest t or -1, triangle id bits, any hit 0/1, 0).
std::vector<TestRay> traceOnGpu(const Bvh& bvh, const std::vector<TestRay>& rays) {
    gl::MemoryLedger ledger;
    gl::Buffer nodes(ledger, "t.nodes", std::int64_t(bvh.nodes.size() * sizeof(gpu::BvhNode)), bvh.nodes.data(), 0);
    gl::Buffer tris(ledger, "t.tris", std::int64_t(bvh.triangles.size() * sizeof(gpu::BvhTriangle)), bvh.triangles.data(), 0);
    gl::Buffer rayBuf(ledger, "t.rays", std::int64_t(rays.size() * sizeof(TestRay)), rays.data());
    gl::Buffer frameUbo(ledger, "t.frame", sizeof(gpu::FrameUniforms));
    gl::ProgramCache programs;
    const gl::Program& prog = programs.compute("ref/trace_test.comp");
    glBindBufferBase(GL_UNIFORM_BUFFER, RTGI_UBO_FRAME, frameUbo.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_BVH_NODES, nodes.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_BVH_TRIS, tris.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RTGI_SSBO_REF_RAYS, rayBuf.id());
    prog.set(0, unsigned(rays.size()));
    // Not gl::dispatch: it notes the dispatch in the last active Profiler,
    // which an earlier test case destroyed (gl::Profiler::active_ dangles).
    glUseProgram(prog.id());
    glDispatchCompute(gl::groupCount(int(rays.size()), prog.localSize().x), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // producer: trace_test.comp (SSBO writes)
    std::vector<TestRay> out(rays.size());
    rayBuf.download(out.data(), std::int64_t(out.size() * sizeof(TestRay)));
    return out;
}

std::uint32_t hitTriangle(const TestRay& r) {
    std::uint32_t id;
    std::memcpy(&id, &r.direction.y, 4);
    return id;
}

}  // namespace

TEST_CASE("Reference: GPU BVH traversal equals CPU brute force") {
    GpuFixture fx;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<glm::vec3> v;
    for (int t = 0; t < 300; ++t) {
        glm::vec3 c(u(rng) * 3, u(rng) * 3, u(rng) * 3);
        for (int k = 0; k < 3; ++k) v.push_back(c + 0.5f * glm::vec3(u(rng), u(rng), u(rng)));
    }
    Bvh bvh = buildBvh(v);
    std::vector<TestRay> rays(256);
    std::normal_distribution<float> g;
    for (auto& r : rays) {
        r.origin = glm::vec4(u(rng) * 4, u(rng) * 4, u(rng) * 4, 1e30f);
        r.direction = glm::vec4(glm::normalize(glm::vec3(g(rng), g(rng), g(rng))), 0);
    }
    std::vector<TestRay> out = traceOnGpu(bvh, rays);
    int hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        glm::vec3 o(rays[i].origin), d(rays[i].direction);
        // Brute force over all triangles on the CPU, original order.
        std::optional<RayHit> best;
        for (auto& t : bvh.triangles)
            if (auto h = intersectTriangle(t, o, d, 0.0f, best ? best->t : 1e30f)) best = h;
        REQUIRE((out[i].direction.x >= 0.0f) == best.has_value());
        CHECK((out[i].direction.z > 0.5f) == best.has_value());
        if (!best) continue;
        ++hits;
        CHECK(hitTriangle(out[i]) == best->triangle);
        // The GPU's division may be inexact (GLSL allows 2.5 ulp):
        // distances agree to float rounding.
        CHECK(out[i].direction.x == doctest::Approx(best->t).epsilon(1e-5));
    }
    CHECK(hits > 20);
}

// Watertightness on the GPU (tests/watertight_rays.h; the CPU side is in
// tests/unit/test_bvh.cpp): rays at the shared vertices and edges of a
// tessellated quad all hit, rays just outside its border all miss, and each
// hit is the CPU's: the same distance, on a triangle holding the point aimed
// at. Not necessarily the CPU's triangle: a ray through a shared edge or
// vertex hits several at one distance, and which one wins can turn on an
// ulp of the shear constants d[kx]/d[kz], ... (GLSL's division need not
// round as the CPU's does; on an H200 19 % of these rays chose another).
TEST_CASE("Reference: GPU rays at shared vertices and edges never slip through and equal the CPU's hits") {
    GpuFixture fx;
    test::WatertightCase c = test::watertightCase(64, 2, 5u);
    Bvh bvh = buildBvh(c.triangles);
    std::vector<TestRay> rays;
    for (const auto& r : c.rays) rays.push_back({glm::vec4(r.origin, 1e30f), glm::vec4(r.dir, 0.0f)});
    std::vector<TestRay> out = traceOnGpu(bvh, rays);
    int onMesh = 0, missed = 0, anyMissed = 0, spurious = 0, otherDistance = 0, notIncident = 0, sameTriangle = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const test::WatertightRay& r = c.rays[i];
        const bool hit = out[i].direction.x >= 0.0f, any = out[i].direction.z > 0.5f;
        if (!r.onMesh) {
            spurious += hit || any;
            continue;
        }
        ++onMesh;
        missed += !hit;
        anyMissed += !any;
        auto cpu = traceClosest(bvh, r.origin, r.dir, 0.0f, 1e30f);
        if (!hit || !cpu) continue;
        otherDistance += !(out[i].direction.x == doctest::Approx(cpu->t).epsilon(1e-5));
        notIncident += std::find(r.incident.begin(), r.incident.end(), hitTriangle(out[i])) == r.incident.end();
        sameTriangle += hitTriangle(out[i]) == cpu->triangle;
    }
    INFO(onMesh << " rays at shared vertices / edges: " << missed << " missed, any-hit missed " << anyMissed
                << ", distance unlike the CPU's " << otherDistance << ", on a triangle not holding the target "
                << notIncident << ", the CPU's triangle " << sameTriangle << "; " << rays.size() - std::size_t(onMesh)
                << " rays just outside the border, " << spurious << " hit");
    CHECK(onMesh > 30000);
    CHECK(missed == 0);
    CHECK(anyMissed == 0);
    CHECK(otherDistance == 0);
    CHECK(notIncident == 0);
    CHECK(spurious == 0);
    MESSAGE("hits on the CPU's triangle: " << sameTriangle << " of " << onMesh);
}

TEST_CASE("Reference AO: a plane is unoccluded (AO = 1)") {
    GpuFixture fx;
    Scene s = floorScene(20.0f, glm::vec3(0.5f), false);
    Settings st = referenceSettings(ReferenceSettings::Kind::Ao, 16);
    st.ao.radius = 1e6f;
    RefResult r = renderReference(s, st);
    int geometry = 0;
    for (int y = 0; y < kSize.y; ++y)
        for (int x = 0; x < kSize.x; ++x) {
            if (!(r.depth.at(x, y, 0) > 0)) continue;
            ++geometry;
            CHECK(r.mean.at(x, y, 0) == 1.0f);  // exact: no ray can hit the plane it leaves
            CHECK(r.se.at(x, y, 0) == 0.0f);
        }
    CHECK(geometry > kSize.x * kSize.y / 2);
}

TEST_CASE("Reference AO: floor beside a wall equals quadrature over the same geometry (unbounded and finite rays)") {
    // The oracle itself: beside a very large wall, unbounded rays see AO -> 1/2.
    CHECK(aoQuadrature({0, 0, kWallZ + 1e-4}, 1e30, 1e5, 1e5) == doctest::Approx(0.5).epsilon(0.01));

    GpuFixture fx;
    Scene s = floorAndWallScene();
    for (double length : {1e6, 0.5}) {
        Settings st = referenceSettings(ReferenceSettings::Kind::Ao, 64);
        st.ao.radius = float(length);
        RefResult r = renderReference(s, st);
        int n = 0, outside = 0;
        double sumDiff = 0, sumVar = 0, sumSeReported = 0, sumSeExact = 0;
        for (int y = 0; y < kSize.y; ++y)
            for (int x = 0; x < kSize.x; ++x) {
                if (!(r.depth.at(x, y, 0) > 0)) continue;
                glm::dvec3 p = worldPosition(s, st, kSize, r.depth, x, y);
                if (std::abs(p.y) > 1e-3 || p.z < kWallZ + 0.02) continue;  // floor pixels in front of the wall
                double expect = aoQuadrature(p, length, kWallW, kWallH, 128);
                double got = r.mean.at(x, y, 0);
                // Each cosine-sampled ray is a Bernoulli trial with p = AO, so
                // the estimator's exact standard error is sqrt(p(1-p)/N) (the
                // per-pixel sample SE of 64 trials is too noisy to test with).
                double se = std::sqrt(expect * (1.0 - expect) / 64.0);
                // 3 standard errors + 4e-3 for the quadrature's discretization
                // of the wall's silhouette (128 x 256 cells).
                if (std::abs(got - expect) > 3.0 * se + 4e-3) ++outside;
                sumDiff += got - expect;
                sumVar += se * se;
                sumSeReported += r.se.at(x, y, 0);
                sumSeExact += se;
                ++n;
            }
        INFO("ray length " << length << ", floor pixels " << n << ", outside 3 SE " << outside);
        REQUIRE(n > 200);
        // Per pixel: 3 SE holds for 99.7 % of normal errors; allow 2 % for
        // the binomial tails at 64 samples.
        CHECK(outside <= n / 50);
        // Aggregate over all pixels: the mean error within 3 of its SE.
        CHECK(std::abs(sumDiff / n) <= 3.0 * std::sqrt(sumVar) / n + 2e-3);
        // The reported SE image estimates the exact binomial SE (10 %: the
        // sample SE of 64 trials, averaged over a few hundred pixels).
        CHECK(sumSeReported / n == doctest::Approx(sumSeExact / n).epsilon(0.1));
    }
}

namespace {
// Closed box [-1,1]^3 (gpu_fixture.h) seen from inside.
Scene furnaceBox(float albedo, float le) {
    Scene s = closedBoxScene(albedo, le);
    s.name = "test:furnace";
    return s;
}
}  // namespace

TEST_CASE("Reference path tracer: furnace box returns Le/(1-a) (full) and a·Le/(1-a) or a²·Le/(1-a) (indirect)") {
    GpuFixture fx;
    // a = 0.6 = 153/255 is exact in the RGBA8 G-buffer albedo; Le = 1 is
    // exact in R11G11B10F. Lambert only (the GGX lobe adds its own albedo).
    const double a = 0.6, le = 1.0;
    Scene s = furnaceBox(float(a), float(le));
    // Indirect with emissive.lights=on: the walls' emission seen from x1 is
    // x1's direct light (area lights of the real-time path), a·(L − Le).
    for (int config = 0; config < 3; ++config) {
        auto kind = config == 0 ? ReferenceSettings::Kind::Full : ReferenceSettings::Kind::Indirect;
        Settings st = referenceSettings(kind, 32);
        st.reference.specular = false;
        st.reference.bounces = 64;  // truncation a^64 ~ 1e-14 of the series
        st.light.emissiveLights = config != 1;
        RefResult r = renderReference(s, st);
        double expect = config == 0 ? le / (1 - a) : config == 1 ? a * le / (1 - a) : a * a * le / (1 - a);
        // Every pixel estimates the same value with the same distribution:
        // the pooled (RMS) standard error is the per-pixel SE, far steadier
        // than one pixel's sample SE of 32 paths with Russian roulette.
        double sum = 0, var = 0;
        int n = 0, outside = 0;
        for (int y = 0; y < kSize.y; ++y)
            for (int x = 0; x < kSize.x; ++x) {
                REQUIRE(r.depth.at(x, y, 0) > 0);  // the box encloses the camera
                sum += r.mean.at(x, y, 0);
                var += double(r.se.at(x, y, 0)) * r.se.at(x, y, 0);
                ++n;
            }
        double pooled = std::sqrt(var / n);
        for (int y = 0; y < kSize.y; ++y)
            for (int x = 0; x < kSize.x; ++x)
                if (std::abs(r.mean.at(x, y, 0) - expect) > 3.0 * pooled) ++outside;
        INFO("config " << config << " mean " << sum / n << " expected " << expect);
        CHECK(std::abs(sum / n - expect) <= 3.0 * std::sqrt(var) / n);  // aggregate within 3 SE
        CHECK(outside <= n / 50);  // per pixel: 3 SE except the tails (2 %)
    }
}

TEST_CASE("Reference: same seed gives the same bits, another seed other bits; SE falls as 1/sqrt(N)") {
    GpuFixture fx;
    Scene s = floorAndWallScene();
    Settings st = referenceSettings(ReferenceSettings::Kind::Ao, 16);
    st.ao.radius = 1.0f;
    RefResult a = renderReference(s, st), b = renderReference(s, st);
    CHECK(a.mean.data == b.mean.data);
    CHECK(a.se.data == b.se.data);
    st.reference.seed = 2;
    CHECK(renderReference(s, st).mean.data != a.mean.data);
    st.reference.seed = 1;
    st.reference.spp = 64;
    RefResult c = renderReference(s, st);
    // Mean SE over pixels that are partly occluded at both sample counts.
    double se16 = 0, se64 = 0;
    int n = 0;
    for (std::size_t i = 0; i < a.se.data.size(); i += 4)
        if (a.se.data[i] > 0 && c.se.data[i] > 0) {
            se16 += a.se.data[i];
            se64 += c.se.data[i];
            ++n;
        }
    REQUIRE(n > 100);
    // 4x the samples: half the standard error; 10 % for the estimate's own
    // noise over a few hundred pixels and the bias of sqrt(s²) at small n.
    CHECK(se16 / se64 == doctest::Approx(2.0).epsilon(0.1));
}

TEST_CASE("Reference cache: a second renderer loads the stored reference") {
    GpuFixture fx;
    Scene s = floorAndWallScene();
    Settings st = referenceSettings(ReferenceSettings::Kind::Ao, 8);
    std::filesystem::path dir = std::filesystem::temp_directory_path() / "rtgi-test-ref-cache";
    std::filesystem::remove_all(dir);
    st.reference.cacheDir = dir.string();
    RefResult a = renderReference(s, st);
    CHECK_FALSE(a.fromCache);
    RefResult b = renderReference(s, st);
    CHECK(b.fromCache);
    CHECK(a.mean.data == b.mean.data);  // PFM stores float32: lossless
    st.reference.spp = 9;  // other settings, other key
    CHECK_FALSE(renderReference(s, st).fromCache);
    std::filesystem::remove_all(dir);
}

namespace {
// Lambert floor (y = 0, albedo 153/255, exact in RGBA8) under a black square
// emitter of side 2h at height y0, emitting Le (two-sided), no other light.
constexpr double kRectH = 0.2, kRectY = 0.5, kRectLe = 5.0, kFloorAlbedo = 0.6;
Scene rectLightScene() {
    Scene s = floorScene(3.0f, glm::vec3(float(kFloorAlbedo)), false);
    s.name = "test:rect-light";
    Material e;
    e.baseColor = glm::vec4(0, 0, 0, 1);
    e.emissive = glm::vec3(float(kRectLe));
    s.materials.push_back(e);
    const float h = float(kRectH), y = float(kRectY);
    addQuad(s, {-h, y, -h}, {h, y, -h}, {h, y, h}, {-h, y, h}, 1);  // faces down
    s.cameras[0].position = {0.0f, 1.6f, 1.6f};
    s.cameras[0].target = {0.0f, 0.0f, 0.2f};
    return s;
}

// Irradiance of the floor point p from the square (gpu_fixture.h).
double rectIrradiance(glm::dvec3 p) {
    const double h = kRectH;
    return polygonIrradiance(p, {0, 1, 0}, {{-h, kRectY, -h}, {h, kRectY, -h}, {h, kRectY, h}, {-h, kRectY, h}}, kRectLe);
}

struct FloorStats {
    int n = 0, outside = 0;
    double sumDiff = 0, sumVar = 0, sumSe = 0;
};

// Floor pixels of a reference of rectLightScene against ρ/π·E in double.
FloorStats compareRect(const Scene& s, const Settings& st, const RefResult& r) {
    FloorStats f;
    for (int y = 0; y < kSize.y; ++y)
        for (int x = 0; x < kSize.x; ++x) {
            if (!(r.depth.at(x, y, 0) > 0)) continue;
            glm::dvec3 p = worldPosition(s, st, kSize, r.depth, x, y);
            if (std::abs(p.y) > 1e-3) continue;  // the emitter's pixels
            double expect = kFloorAlbedo / M_PI * rectIrradiance(p);
            double got = r.mean.at(x, y, 0), se = r.se.at(x, y, 0);
            if (std::abs(got - expect) > 3.0 * se + 2e-3 * expect) ++f.outside;
            f.sumDiff += got - expect;
            f.sumVar += se * se;
            f.sumSe += se;
            ++f.n;
        }
    return f;
}
}  // namespace

TEST_CASE("Reference path tracer: a square emitter over a Lambert floor equals the polygon irradiance in closed form; "
          "NEE + MIS has lower variance than BRDF sampling") {
    // The oracle itself: far below a small square, E -> Le·A/d² (point source).
    CHECK(rectIrradiance({0, kRectY - 100.0, 0}) == doctest::Approx(kRectLe * 4 * kRectH * kRectH / 1e4).epsilon(1e-3));
    GpuFixture fx;
    Scene s = rectLightScene();
    Settings st = referenceSettings(ReferenceSettings::Kind::Full, 64);
    st.reference.specular = false;
    st.reference.bounces = 1;  // the floor cannot see itself; the emitter is black
    RefResult nee = renderReference(s, st);
    FloorStats a = compareRect(s, st, nee);
    st.reference.lightSampling = false;
    RefResult bsdf = renderReference(s, st);
    FloorStats b = compareRect(s, st, bsdf);
    INFO("floor pixels " << a.n << "; NEE+MIS: mean err " << a.sumDiff / a.n << ", mean SE " << a.sumSe / a.n
                         << ", outside 3 SE " << a.outside << "; BRDF only: mean err " << b.sumDiff / b.n
                         << ", mean SE " << b.sumSe / b.n);
    REQUIRE(a.n > 300);
    CHECK(a.outside <= a.n / 50);
    CHECK(std::abs(a.sumDiff / a.n) <= 3.0 * std::sqrt(a.sumVar) / a.n + 1e-4);
    // BRDF sampling alone converges to the same value (aggregate)...
    CHECK(std::abs(b.sumDiff / b.n) <= 3.0 * std::sqrt(b.sumVar) / b.n + 1e-4);
    // ...with a much larger standard error at equal samples (measured ~10x
    // lower with NEE + MIS here; asserted: at least 3x).
    CHECK(a.sumSe * 3.0 < b.sumSe);
}

TEST_CASE("Reference path tracer and G-buffer: a single-sided emitter (glTF doubleSided = false) emits from its front "
          "face only; doubleSided emits from both") {
    GpuFixture fx;
    Settings st = referenceSettings(ReferenceSettings::Kind::Full, 32);
    st.reference.specular = false;
    st.reference.bounces = 1;
    for (bool doubleSided : {false, true})
        for (bool faceUp : {false, true}) {
            Scene s = rectLightScene();  // faces down: the floor sees its front, the camera above its back
            s.materials.back().doubleSided = doubleSided;
            if (faceUp) std::swap(s.indices[s.indices.size() - 6 + 1], s.indices[s.indices.size() - 6 + 2]),
                        std::swap(s.indices[s.indices.size() - 3 + 1], s.indices[s.indices.size() - 3 + 2]);
            for (bool nee : {true, false}) {
                st.reference.lightSampling = nee;
                RefResult r = renderReference(s, st);
                bool floorLit = doubleSided || !faceUp, panelSeen = doubleSided || faceUp;
                FloorStats f = compareRect(s, st, r);
                // The emitter's pixels: the camera (y = 1.6) looks at the panel's upper side.
                int panel = 0, panelWrong = 0;
                double floorMax = 0;
                for (int y = 0; y < kSize.y; ++y)
                    for (int x = 0; x < kSize.x; ++x) {
                        if (!(r.depth.at(x, y, 0) > 0)) continue;
                        glm::dvec3 p = worldPosition(s, st, kSize, r.depth, x, y);
                        if (std::abs(p.y - kRectY) < 1e-3) {
                            ++panel;
                            // Black albedo: the pixel is its emission, Le or 0, nothing else.
                            double expect = panelSeen ? kRectLe : 0.0;
                            if (std::abs(r.mean.at(x, y, 0) - expect) > 1e-3 * kRectLe) ++panelWrong;
                        } else if (std::abs(p.y) < 1e-3)
                            floorMax = std::max(floorMax, double(r.mean.at(x, y, 0)));
                    }
                INFO("doubleSided " << doubleSided << ", panel faces " << std::string(faceUp ? "up" : "down") << ", NEE " << nee
                                    << ": floor pixels " << f.n << " mean err " << f.sumDiff / std::max(f.n, 1)
                                    << ", floor max " << floorMax << ", panel pixels " << panel << " wrong " << panelWrong);
                REQUIRE(f.n > 300);
                REQUIRE(panel > 20);
                CHECK(panelWrong == 0);
                if (floorLit) {
                    if (nee) CHECK(f.outside <= f.n / 50);  // BRDF sampling alone: the aggregate only (as above)
                    CHECK(std::abs(f.sumDiff / f.n) <= 3.0 * std::sqrt(f.sumVar) / f.n + 1e-4);
                } else {
                    CHECK(floorMax == 0.0);  // the back face sends nothing: exactly black, no noise
                }
            }
        }
}

namespace {
// floorAndWallScene moved by t and scaled by k (cameras too).
Scene movedCorner(glm::vec3 t, float k) {
    Scene s = scaledScene(floorAndWallScene(), k);
    for (auto& v : s.vertices) v.position += t;
    for (auto& c : s.cameras) {
        c.position += t;
        c.target += t;
    }
    return s;
}
}  // namespace

TEST_CASE("Reference AO: ray origins from the point's own magnitude: a plane far from the origin and a tiny corner") {
    GpuFixture fx;
    // Exactly unoccluded plane 3 km from the origin and one of 2 mm at it.
    for (auto [t, k] : {std::pair{glm::vec3(3000.0f, -400.0f, 2000.0f), 1.0f}, std::pair{glm::vec3(0.0f), 1e-3f}}) {
        Scene plane = scaledScene(floorScene(20.0f, glm::vec3(0.5f), false), k);
        for (auto& v : plane.vertices) v.position += t;
        for (auto& c : plane.cameras) {
            c.position += t;
            c.target += t;
        }
        Settings st = referenceSettings(ReferenceSettings::Kind::Ao, 16);
        st.ao.radius = 1e6f * k;
        RefResult r = renderReference(plane, st);
        int geometry = 0, occluded = 0;
        for (int y = 0; y < kSize.y; ++y)
            for (int x = 0; x < kSize.x; ++x)
                if (r.depth.at(x, y, 0) > 0) {
                    ++geometry;
                    occluded += r.mean.at(x, y, 0) != 1.0f;
                }
        INFO("translation " << t.x << " scale " << k);
        CHECK(geometry > kSize.x * kSize.y / 2);
        CHECK(occluded == 0);
    }
    // Floor beside a wall, moved far away and shrunk: AO against the
    // quadrature in the corner's own coordinates (a scene-size offset would
    // lift the origins off the floor; a too small one would self-intersect).
    // Third case: the corner beside a 2 km quad 100 m below it (out of its
    // rays' reach): a scene-diagonal offset (1e-4 × 2.8 km = 0.28 m) would
    // lift every origin far off the floor; the point's own magnitude does not.
    for (int c = 0; c < 3; ++c) {
        glm::vec3 t = c == 0 ? glm::vec3(1000.0f, 500.0f, -2000.0f) : glm::vec3(0.0f);
        float k = c == 1 ? 1e-3f : 1.0f;
        Scene s = movedCorner(t, k);
        if (c == 2) addQuad(s, {-1000, -100, 1000}, {1000, -100, 1000}, {1000, -100, -1000}, {-1000, -100, -1000}, 0);
        Settings st = referenceSettings(ReferenceSettings::Kind::Ao, 64);
        const double length = 0.5;
        st.ao.radius = float(length) * k;
        RefResult r = renderReference(s, st);
        int n = 0, outside = 0;
        double sumDiff = 0, sumVar = 0;
        for (int y = 0; y < kSize.y; ++y)
            for (int x = 0; x < kSize.x; ++x) {
                if (!(r.depth.at(x, y, 0) > 0)) continue;
                glm::dvec3 p = (worldPosition(s, st, kSize, r.depth, x, y) - glm::dvec3(t)) / double(k);
                if (std::abs(p.y) > 2e-3 || p.z < kWallZ + 0.02) continue;
                p.y = 0;
                double expect = aoQuadrature(p, length, kWallW, kWallH, 128);
                double se = std::sqrt(expect * (1.0 - expect) / 64.0);
                if (std::abs(r.mean.at(x, y, 0) - expect) > 3.0 * se + 4e-3) ++outside;
                sumDiff += r.mean.at(x, y, 0) - expect;
                sumVar += se * se;
                ++n;
            }
        INFO("translation " << t.x << " scale " << k << " floor pixels " << n << " outside " << outside << " mean err "
                            << sumDiff / std::max(n, 1));
        REQUIRE(n > 200);
        CHECK(outside <= n / 50);
        CHECK(std::abs(sumDiff / n) <= 3.0 * std::sqrt(sumVar) / n + 2e-3);
    }
}

TEST_CASE("Reference: progressive mode (rtgi-view's live comparison) converges to the all-at-once trace; a new view restarts it") {
    // Oracle: the normal trace of the same samples (sample i of a pixel is a
    // pure function of pixel, i and seed); only the float summation order of
    // the accumulation differs (4 samples a frame vs 16 a dispatch).
    GpuFixture fx;
    Scene s = floorAndWallScene();
    Settings st = referenceSettings(ReferenceSettings::Kind::Ao, 16);
    st.ao.radius = 1.0f;
    RefResult all = renderReference(s, st);

    gl::Profiler prof(false);
    Renderer r(s, st, prof);
    auto* out = dynamic_cast<ReferenceOutput*>(r.findPass("ref.ao"));
    REQUIRE(out != nullptr);
    out->setProgressive(4);
    Camera cam = resolveCamera(s, st);
    View v = makeView(cam, kSize, nullptr, 0);
    std::vector<int> done;
    FloatImage partial;
    for (int f = 0; f < 5; ++f) {  // the fifth frame adds nothing: converged at reference.spp
        r.render(v);
        done.push_back(out->samplesDone());
        if (f == 0) partial = readTexture(out->mean());
    }
    CHECK(done == std::vector<int>{4, 8, 12, 16, 16});
    FloatImage prog = readTexture(out->mean()), progSe = readTexture(out->standardError());
    double maxDiff = 0, maxSeDiff = 0, partialDiff = 0;
    for (std::size_t i = 0; i < prog.data.size(); ++i) {
        maxDiff = std::max(maxDiff, double(std::abs(prog.data[i] - all.mean.data[i])));
        maxSeDiff = std::max(maxSeDiff, double(std::abs(progSe.data[i] - all.se.data[i])));
        partialDiff = std::max(partialDiff, double(std::abs(partial.data[i] - all.mean.data[i])));
    }
    CHECK(maxDiff < 1e-5);
    CHECK(maxSeDiff < 1e-4);
    CHECK(partialDiff > 0.05);  // after 4 samples it is not yet the 16-sample image: the check can fail
    // A camera move restarts the accumulation.
    Camera moved = cam;
    moved.position += glm::vec3(0.05f, 0.0f, 0.0f);
    r.render(makeView(moved, kSize, nullptr, 0));
    CHECK(out->samplesDone() == 4);
}
