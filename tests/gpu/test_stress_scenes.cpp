// Issue 9 acceptance: --check on every built-in scene with every technique
// on (LPV where a sun exists, each AO variant with its directional /
// near-field / radius options, each SSR tracer on a glossy floor, the
// reference path tracer) finds no NaN and no Inf in any pass output, and no
// negative value where the output cannot be negative. Also runs the
// rtgi-bench binary with --check once (exit code, results.json "check").
#include "gpu_fixture.h"

#include "render/gpu_scene.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>

using namespace rtgi;
using namespace rtgi::test;
namespace fs = std::filesystem;

namespace {

using Variant = AoSettings::Variant;
const Variant kVariants[] = {Variant::SsaoDisk, Variant::SsaoSphere, Variant::SsaoHemisphere,
                             Variant::Vo,       Variant::Hbao,       Variant::Gtao};

// Configuration k of the matrix for a scene: AO variant k, and the options
// cycled so that every option value meets every scene at least once.
Settings matrixSettings(const Scene& scene, int k) {
    Settings s;
    s.light.shadowSize = 256;  // llvmpipe time; the shadow map's size does not change what is checked
    bool sun = resolveSun(scene, s).has_value();
    s.lpv.mode = sun ? Toggle::On : Toggle::Off;
    s.lpv.grid = glm::ivec3(16);
    s.lpv.rsm = 64;
    s.lpv.specular = sun ? Toggle::On : Toggle::Auto;
    s.lpv.temporal = k % 2 ? 0.5f : 0.0f;
    s.lpv.format = k % 3 == 2 ? LpvSettings::Format::Rgba32f : LpvSettings::Format::Rgba16f;
    s.lpv.path = k == 5 ? LpvSettings::Path::Raster : LpvSettings::Path::Compute;
    s.lpv.energyConserving = k == 4;
    s.lpv.shOrder = k == 2 || k == 4 ? 2 : 1;  // band 2 (compute path, no temporal blend)
    s.ao.variant = kVariants[k];
    s.ao.samples = 8;
    s.ao.directional = k % 2 ? AoSettings::Directional::S3ho : AoSettings::Directional::BentNormals;
    s.ao.nearfield = 1.0f;
    const AoSettings::RadiusMode modes[] = {AoSettings::RadiusMode::Dynamic6, AoSettings::RadiusMode::Dual,
                                            AoSettings::RadiusMode::Dynamic1, AoSettings::RadiusMode::Fixed,
                                            AoSettings::RadiusMode::Dynamic3, AoSettings::RadiusMode::Dynamic6};
    s.ao.radiusMode = modes[k];
    s.ao.halfResolution = k % 3 != 1;
    s.ao.blurAfterTemporal = k % 2 == 0;
    s.ao.multiBounce = true;
    // Light-depth AO needs a point-sampling variant and a sun.
    if (sun && kVariants[k] == Variant::SsaoSphere) s.ao.depthSource = AoSettings::DepthSource::Light;
    const SsrSettings::Tracer tracers[] = {SsrSettings::Tracer::Linear, SsrSettings::Tracer::Dda,
                                           SsrSettings::Tracer::Hiz};
    s.ssr.tracer = tracers[k % 3];
    s.ssr.halfResolution = k % 2 == 0;
    s.ssr.diffuseHistory = k % 4 == 1;
    s.floorRoughness = 0.1f;
    if (k == 0) {
        s.reference.kind = ReferenceSettings::Kind::Full;
        s.reference.spp = 2;
        s.reference.bounces = 2;
        s.reference.cacheDir = "off";
    } else if (k == 3) {
        s.reference.kind = ReferenceSettings::Kind::Ao;
        s.reference.spp = 2;
        s.reference.cacheDir = "off";
    }
    return s;
}

}  // namespace

TEST_CASE("stress: --check on every built-in scene with every technique on finds no NaN, Inf or impossible negative") {
    GpuFixture gpu;
    const glm::ivec2 size(64, 48);
    std::set<std::string> passesSeen;
    for (const std::string& name : builtinSceneNames()) {
        Scene scene = loadBuiltin(name);
        for (int k = 0; k < 6; ++k) {
            Settings st = matrixSettings(scene, k);
            INFO(scene.name << " config " << k << " ao=" << toString(st.ao.variant)
                            << " ssr=" << toString(st.ssr.tracer) << " lpv=" << toString(st.lpv.mode));
            gl::Profiler prof(false);
            Renderer r(scene, st, prof);
            r.setCheck(true);
            Camera cam = resolveCamera(scene, st);
            View prev;
            for (int f = 0; f < 3; ++f) {
                View v = makeView(cam, size, f ? &prev : nullptr, unsigned(f));
                r.render(v);
                prev = v;
            }
            REQUIRE_FALSE(r.finiteCounts().empty());
            for (const FiniteCount& c : r.finiteCounts()) {
                passesSeen.insert(c.pass);
                INFO(c.pass << " " << c.resource << ": nan=" << c.nan << " inf=" << c.inf << " negative="
                            << c.negative << " fp16-saturated=" << c.fp16Saturated);
                CHECK(c.nan == 0);
                CHECK(c.inf == 0);
                CHECK(c.negative == 0);
            }
        }
    }
    // Every family's passes were checked (an output list that went missing would pass silently).
    // The G-buffer pass with checked outputs (visibility.raster writes a buffer, not images).
    std::vector<std::string> families{gbufferPassNames(Settings{}).back()};
    for (const char* p : {"direct", "brdf_lut", "lpv.rsm", "lpv.inject", "lpv.pack", "lpv.inject_geometry",
                          "lpv.propagate", "lpv.temporal", "lpv.apply", "ao.downsample", "ao.radius", "ao.ssao-disk",
                          "ao.ssao-sphere", "ao.ssao-hemisphere", "ao.vo", "ao.hbao", "ao.gtao", "ao.blur",
                          "ao.temporal", "ao.blur2", "ao.upsample", "ao.nearfield", "ssr.hiz", "ssr.trace",
                          "ssr.resolve", "ssr.blur", "ssr.temporal", "ssr.shade", "ssr.diffuse_history",
                          "post.compose", "post.history", "ref.path", "ref.ao"})
        families.push_back(p);
    for (const std::string& p : families) {
        INFO("pass " << p);
        CHECK(passesSeen.count(p) == 1);
    }
}

TEST_CASE("stress: rtgi-bench --check exits 0 and writes zero non-finite counts (cornell, every technique)") {
    fs::path dir = fs::temp_directory_path() / ("rtgi-stress-bench-" + std::to_string(getpid()));
    fs::remove_all(dir);
    const std::string cmd = std::string(RTGI_BENCH_EXE) +
                            " --scene builtin:cornell --res 48x32 --frames 2 --warmup 1 --check --no-images"
                            " --set lpv=on --set lpv.grid=8 --set lpv.rsm=32 --set shadow.size=128 --set ao=gtao"
                            " --set ao.directional=s3ho --set ao.nearfield=1 --set ao.radius_mode=dynamic6"
                            " --set ssr=hiz --set floor.roughness=0.1 --out " +
                            dir.string() + " > /dev/null 2>&1";
    int rc = std::system(cmd.c_str());
    REQUIRE(WIFEXITED(rc));
    CHECK(WEXITSTATUS(rc) == 0);
    std::ifstream in(dir / "results.json");
    REQUIRE(in.good());
    nlohmann::json j = nlohmann::json::parse(in);
    REQUIRE(j.contains("check"));
    CHECK(j["check"]["non_finite"].get<std::uint64_t>() == 0);
    CHECK(j["check"]["outputs"].size() > 20);  // every pass's outputs are listed
    fs::remove_all(dir);
}
