// Issue 16 without GL: atomic result files, NaN/Inf-safe metrics and heat
// maps, sweep and command-line errors that name the file / option and key.
#include "app/cli.h"
#include "bench/sweep_spec.h"
#include "gl/output_files.h"
#include "render/reference/metrics.h"

#include <doctest/doctest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

using namespace rtgi;
namespace fs = std::filesystem;

namespace {
fs::path scratch(const std::string& name) {
    fs::path d = fs::temp_directory_path() / ("rtgi-hardening-unit-" + std::to_string(getpid())) / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}
std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}
std::size_t entries(const fs::path& d) {
    std::size_t n = 0;
    for ([[maybe_unused]] auto& e : fs::directory_iterator(d)) ++n;
    return n;
}
}  // namespace

TEST_CASE("hardening: writeFileAtomic replaces the file whole and leaves no temporary behind") {
    fs::path d = scratch("atomic");
    writeFileAtomic((d / "results.json").string(), "first\n");
    writeFileAtomic((d / "results.json").string(), "second\n");
    CHECK(slurp(d / "results.json") == "second\n");
    CHECK(entries(d) == 1);
}

TEST_CASE("hardening: result files are not written through links, over directories or into missing directories") {
    fs::path d = scratch("refuse");
    fs::create_symlink("/dev/full", d / "full.json");
    CHECK_THROWS_WITH_AS(writeFileAtomic((d / "full.json").string(), "x"), doctest::Contains("symbolic link"), OutputError);
    std::ofstream(d / "target") << "previous run";
    fs::create_symlink(d / "target", d / "link.json");
    CHECK_THROWS_AS(writeFileAtomic((d / "link.json").string(), "x"), OutputError);
    CHECK(slurp(d / "target") == "previous run");  // nothing went through the link
    fs::create_directories(d / "results.json");
    CHECK_THROWS_WITH_AS(writeFileAtomic((d / "results.json").string(), "x"), doctest::Contains("is a directory"), OutputError);
    CHECK_THROWS_AS(writeFileAtomic((d / "missing" / "results.json").string(), "x"), OutputError);
    // --out below a regular file cannot be created.
    CHECK_THROWS_WITH_AS(prepareOutputDirectory((d / "target" / "out").string()), doctest::Contains("target"), OutputError);
    CHECK_NOTHROW(prepareOutputDirectory((d / "new" / "out").string()));
    CHECK(entries(d / "new" / "out") == 0);  // the probe file is gone
}

TEST_CASE("hardening: metrics leave NaN/Inf pixels out of the sums, count them, and the heat map marks NaN") {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    FloatImage t, r;
    t.width = r.width = 4;
    t.height = r.height = 1;
    t.channels = r.channels = 1;
    t.data = {0.5f, nan, 1.0f, inf};
    r.data = {0.25f, 0.0f, nan, 0.0f};
    ErrorMetrics m = compareImages(t, r, 1, 1.0);
    CHECK(m.pixels == 1);
    CHECK(m.nanPixels == 2);
    CHECK(m.infPixels == 1);
    CHECK(m.rmse == doctest::Approx(0.25));  // only pixel 0: |0.5 - 0.25|
    CHECK(m.mae == doctest::Approx(0.25));
    CHECK(std::isfinite(m.ssim));
    CHECK(errorQuantile(t, r, 1, 1.0) == doctest::Approx(0.25));  // the largest finite error
    FloatImage h = errorHeatmap(t, r, 1, errorQuantile(t, r, 1, 0.99));  // ramp(NaN) used to index with INT_MIN
    auto px = [&](int x) { return std::array<float, 3>{h.at(x, 0, 0), h.at(x, 0, 1), h.at(x, 0, 2)}; };
    CHECK(px(1) == std::array<float, 3>{0.0f, 1.0f, 1.0f});  // NaN: cyan, outside the ramp
    CHECK(px(2) == std::array<float, 3>{0.0f, 1.0f, 1.0f});
    CHECK(px(3)[1] == doctest::Approx(1.0f));  // Inf error saturates to the top (yellow)
    // A non-finite scale does not turn the map into NaN.
    FloatImage h2 = errorHeatmap(t, r, 1, std::numeric_limits<double>::infinity());
    for (float v : h2.data) CHECK(std::isfinite(v));
}

TEST_CASE("hardening: sweep files: a wrong type names the file and the key, without the parser's raw text") {
    auto err = [](const std::string& text) {
        try {
            (void)parseSweep(text, "s.json");
        } catch (const ConfigError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    std::string a = err(R"({"scenes": ["builtin:cornell"], "axes": [{"ao.samples": {"from": "4", "to": 8, "step": 2}}]})");
    CHECK(a == "s.json: 'ao.samples.from': expected a number, found a string");
    std::string b = err(R"({"scenes": ["builtin:cornell"], "frames": "10"})");
    CHECK(b == "s.json: 'frames': expected an integer, found a string");
    std::string c = err(R"({"scenes": ["builtin:cornell"], "images": 1})");
    CHECK(c == "s.json: 'images': expected true or false, found a number");
    std::string d = err(R"({"scenes": [{"scene": "builtin:cornell", "views": "front"}]})");
    CHECK(d.find("s.json: 'scenes[].views'") == 0);
    std::string e = err("{\"scenes\": [\"builtin:cornell\"],");
    CHECK(e.find("s.json: not valid JSON (") == 0);
    CHECK(e.find("json.exception") == std::string::npos);
    // Two 10^4-value axes: refused from the sizes, before 10^8 lists exist.
    auto t0 = std::chrono::steady_clock::now();
    std::string f = err(R"({"scenes": ["builtin:cornell"], "axes": [{"ao.samples": {"from": 1, "to": 10000, "step": 1}},
                                                                    {"ao.radius": {"from": 1, "to": 10000, "step": 1}}]})");
    CHECK(f.find("about 100000000 configurations") != std::string::npos);
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 2.0);
    std::string g = err(R"({"scenes": ["builtin:cornell"], "axes": [{"ao.radius": {"from": 1, "to": 1e9, "step": 1}}]})");
    CHECK(g.find("more than 10000") != std::string::npos);
}

TEST_CASE("hardening: command line: empty --scene, --shard without --sweep, --max-memory sizes") {
    auto parse = [](std::vector<std::string> args) {
        std::vector<char*> argv;
        static std::string prog = "rtgi-bench";
        argv.push_back(prog.data());
        for (auto& a : args) argv.push_back(a.data());
        try {
            (void)parseCommandLine(Host::Bench, int(argv.size()), argv.data());
        } catch (const ConfigError& e) {
            return std::string(e.what());
        }
        return std::string("ok");
    };
    CHECK(parse({"--scene", ""}) == "--scene: the scene path is empty");
    CHECK(parse({"--shard", "0/2"}) == "--shard applies only to --sweep (no sweep file given)");
    CHECK(parse({"--sweep", "x.json", "--shard", "1/2"}) == "ok");
    CHECK(parse({"--out", ""}) == "--out: the output directory is empty");
    CHECK(parse({"--max-memory", "lots"}).find("--max-memory 'lots'") == 0);
    CHECK(parseByteSize("--max-memory", "8G") == (std::int64_t(8) << 30));
    CHECK(parseByteSize("--max-memory", "512M") == (std::int64_t(512) << 20));
    CHECK(parseByteSize("--max-memory", "1000") == 1000);
}
