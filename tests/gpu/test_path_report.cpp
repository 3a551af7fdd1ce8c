// Issue 23, deliverable 5 on llvmpipe: a path run writes the PNG sequence of
// its frames (--path-frames; path.mp4 exactly when ffmpeg is on PATH) and the
// per-frame disocclusion counts of the temporal filters, and report.py turns
// two path runs into the per-frame error/flicker plot, the Pareto plot and a
// table whose means match the CSVs.
#include "bench_runner.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace rtgi::test;

namespace {

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// PNG width and height from the IHDR chunk (big-endian at bytes 16..23).
std::pair<int, int> pngSize(const fs::path& p) {
    std::string b = slurp(p);
    if (b.size() < 24 || b.substr(1, 3) != "PNG") return {0, 0};
    auto be = [&](std::size_t o) {
        return int((unsigned char)b[o]) << 24 | int((unsigned char)b[o + 1]) << 16 | int((unsigned char)b[o + 2]) << 8 |
               int((unsigned char)b[o + 3]);
    };
    return {be(16), be(20)};
}

// Mean of a temporal.csv column over the rows that have a value.
double columnMean(const fs::path& csv, const std::string& column, int& rows) {
    std::istringstream in(slurp(csv));
    std::string header, line;
    std::getline(in, header);
    std::vector<std::string> names;
    std::stringstream hs(header);
    for (std::string c; std::getline(hs, c, ',');) names.push_back(c);
    std::size_t idx = std::find(names.begin(), names.end(), column) - names.begin();
    REQUIRE(idx < names.size());
    double sum = 0;
    int n = 0;
    rows = 0;
    while (std::getline(in, line)) {
        ++rows;
        std::vector<std::string> cells;
        std::stringstream ls(line);
        for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
        if (idx < cells.size() && !cells[idx].empty()) sum += std::stod(cells[idx]), ++n;
    }
    return n ? sum / n : -1.0;
}

}  // namespace

TEST_CASE("path run: PNG frames, video when ffmpeg exists, disocclusion columns, and report.py's path plots") {
    fs::path dir = fs::temp_directory_path() / ("rtgi-path-report-" + std::to_string(getpid()));
    fs::remove_all(dir);
    const std::string common = "--scene builtin:cornell --path cornell-moving-box --frames 4 --warmup 1 --res 32x24 "
                               "--reference --reference-every 1 --set reference.spp=4 --set reference.cache=off ";
    BenchRun a = runBench(common + "--path-frames --out " + shellQuote((dir / "temporal-on").string()), 240);
    REQUIRE_MESSAGE(a.rc == 0, a.err);
    BenchRun b = runBench(common + "--set ao.temporal=off --out " + shellQuote((dir / "temporal-off").string()), 240);
    REQUIRE_MESSAGE(b.rc == 0, b.err);
    for (int i = 0; i < 4; ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04d.png", i);
        CHECK(pngSize(dir / "temporal-on" / "frames" / name) == std::make_pair(32, 24));
    }
    CHECK_FALSE(fs::exists(dir / "temporal-on" / "frames" / "frame_0004.png"));
    CHECK_FALSE(fs::exists(dir / "temporal-off" / "frames"));
    const bool ffmpeg = std::system("command -v ffmpeg > /dev/null 2>&1") == 0;
    auto res = nlohmann::json::parse(slurp(dir / "temporal-on" / "results.json"));
    if (res.is_array()) res = res[0];
    CHECK(fs::exists(dir / "temporal-on" / "path.mp4") == ffmpeg);
    CHECK(res["path"]["video"]["mp4"].is_null() == !ffmpeg);
    if (!ffmpeg) CHECK(a.err.find("ffmpeg is not on PATH") != std::string::npos);
    // The AO filter's counts: a column with values when it runs, empty when ao.temporal=off.
    int rows = 0;
    CHECK(columnMean(dir / "temporal-on" / "temporal.csv", "disoccluded.ao.temporal", rows) >= 0.0);
    CHECK(rows == 4);
    CHECK(columnMean(dir / "temporal-off" / "temporal.csv", "disoccluded.ao.temporal", rows) == -1.0);
    // --path-frames without --path: one sentence, exit 2.
    BenchRun bad = runBench("--scene builtin:cornell --path-frames --out " + shellQuote((dir / "bad").string()));
    CHECK(bad.rc == 2);
    CHECK(bad.err.find("--path-frames applies only to --path") != std::string::npos);

    if (const char* e = std::getenv("RTGI_NO_MATPLOTLIB"); e && std::string(e) == "1") {
        MESSAGE("report.py not run: RTGI_NO_MATPLOTLIB=1");
        fs::remove_all(dir);
        return;
    }
    const std::string cmd = "/usr/bin/python3 " + std::string(RTGI_SOURCE_DIR) + "/benchmarks/report.py " +
                            shellQuote(dir.string()) + " --out " + shellQuote((dir / "report").string()) + " > /dev/null";
    REQUIRE(std::system(cmd.c_str()) == 0);
    int frames = 0, pareto = 0;
    for (auto& e : fs::directory_iterator(dir / "report")) {
        const std::string n = e.path().filename().string();
        if (n.rfind("path_", 0) != 0) continue;
        CHECK(pngSize(e.path()).first > 0);
        (n.rfind("path_pareto_", 0) == 0 ? pareto : frames)++;
    }
    CHECK(frames == 1);  // one path, both runs in one figure
    CHECK(pareto == 1);
    // The table's mean flicker of each run is the mean of its CSV column (%.4g).
    const std::string md = slurp(dir / "report" / "report.md");
    for (const char* runDir : {"temporal-on", "temporal-off"}) {
        double mean = columnMean(dir / runDir / "temporal.csv", "flicker", rows);
        REQUIRE(mean >= 0.0);
        char text[32];
        std::snprintf(text, sizeof text, "%.4g", mean);
        CAPTURE(runDir);
        CHECK(md.find(std::string("| ") + runDir + " |") != std::string::npos);
        CHECK(md.find(text) != std::string::npos);
    }
    fs::remove_all(dir);
}
