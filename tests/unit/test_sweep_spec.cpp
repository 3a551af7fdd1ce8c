// Sweep expansion, ids, shards, resume and the CSV/JSON round trip (no GL).
#include "bench/results_csv.h"
#include "bench/sweep_spec.h"

#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

using namespace rtgi;

namespace {

std::string value(const SweepConfig& c, const std::string& key) {
    for (auto& [k, v] : c.assignments)
        if (k == key) return v;
    return "";
}

// An independent RFC 4180 reader (the oracle of the CSV round trip).
std::vector<std::string> readCsvLine(const std::string& line) {
    std::vector<std::string> out;
    std::string cur;
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
                cur += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                cur += c;
            }
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            out.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    out.push_back(cur);
    return out;
}

const char* kProduct = R"({
  "name": "t",
  "scenes": [{"scene": "builtin:atrium", "views": ["a", "b"]}, ["builtin:plane", "$SCENES/dragon/dragon.gltf"]],
  "resolutions": ["64x48", "32x24"],
  "frames": 3, "warmup": 1,
  "base": {"lpv": "off", "ao": {"radius": 0.5}},
  "axes": [{"ao": ["hbao", "vo", "gtao"]}, {"ao.samples": [8, 16]}]
})";

}  // namespace

TEST_CASE("sweep: scenes x views x resolutions x axes expand to the full cartesian product") {
    SweepSpec s = parseSweep(kProduct, "t.json");
    // (2 views of atrium + 1 dragon camera) x 2 resolutions x 3 variants x 2 sample counts.
    REQUIRE(s.configs.size() == 3u * 2u * 3u * 2u);
    CHECK(s.duplicates == 0);
    std::set<std::string> ids, tuples;
    for (auto& c : s.configs) {
        ids.insert(c.id);
        tuples.insert(c.sceneLabel + "|" + value(c, "view") + "|" + std::to_string(c.resolution.x) + "|" +
                      value(c, "ao") + "|" + value(c, "ao.samples"));
        CHECK(value(c, "lpv") == "off");        // base applies to every configuration
        CHECK(value(c, "ao.radius") == "0.5");  // nested base objects flatten to dotted keys
        CHECK(c.frames == 3);
        CHECK(c.warmup == 1);
        CHECK(c.id.size() == 16u);
    }
    CHECK(ids.size() == s.configs.size());     // distinct configurations, distinct ids
    CHECK(tuples.size() == s.configs.size());  // every combination exactly once
    // Scenes are the outermost loop (a renderer is reused across a scene's run).
    CHECK(s.configs.front().sceneLabel == "atrium");
    CHECK(s.configs.back().sceneLabel == "dragon");  // default label: file name of the last scene
    CHECK(s.configs.back().scenes == std::vector<std::string>{"builtin:plane", "$SCENES/dragon/dragon.gltf"});
    // Settings validate: the configuration's Settings carry the values.
    Settings st = s.configs.front().settings();
    CHECK((st.ao.variant == AoSettings::Variant::Hbao));
    CHECK(st.ao.samples == 8);
    CHECK((st.lpv.mode == Toggle::Off));
}

TEST_CASE("sweep: explicit lists, zipped keys and ranges") {
    SweepSpec s = parseSweep(R"({
      "scenes": ["builtin:cornell"],
      "resolutions": ["16x16"],
      "axes": [
        [{"ao": "hbao", "ao.samples": 8}, {"ao": "vo", "resolution": "7x3"}],
        {"lpv.grid": {"from": 8, "to": 64, "times": 2}},
        {"ssr.steps": [16, 32], "ssr.thickness": [0.1, 0.2]}
      ]})", "x.json");
    REQUIRE(s.configs.size() == 2u * 4u * 2u);
    std::multiset<std::string> grids, zipped;
    int small = 0;
    for (auto& c : s.configs) {
        grids.insert(value(c, "lpv.grid"));
        zipped.insert(value(c, "ssr.steps") + "/" + value(c, "ssr.thickness"));
        if (value(c, "ao") == "vo") {
            CHECK(c.resolution == glm::ivec2(7, 3));  // a case may override the resolution
            CHECK(value(c, "ao.samples").empty());   // and sets only its own keys
            ++small;
        } else {
            CHECK(c.resolution == glm::ivec2(16, 16));
        }
    }
    CHECK(small == 8);
    // Geometric range 8, 16, 32, 64 (inclusive), each with 2 x 2 partners.
    for (auto g : {"8", "16", "32", "64"}) CHECK(grids.count(g) == 4u);
    // Zipped keys vary together: only the two listed pairs.
    CHECK(zipped.count("16/0.1") == 8u);
    CHECK(zipped.count("32/0.2") == 8u);
}

TEST_CASE("sweep: ids are stable and depend only on what the configuration says") {
    SweepSpec a = parseSweep(kProduct, "a.json");
    // Same configurations written differently: key order, 0.50 vs 0.5, dotted vs nested base.
    SweepSpec b = parseSweep(R"({
      "name": "other name",
      "frames": 3, "warmup": 1,
      "axes": [{"ao": ["hbao", "vo", "gtao"]}, {"ao.samples": [8, 16]}],
      "base": {"ao.radius": 0.50, "lpv": "off"},
      "resolutions": ["64x48", "32x24"],
      "scenes": [{"scene": "builtin:atrium", "views": ["a", "b"]}, ["builtin:plane", "$SCENES/dragon/dragon.gltf"]]
    })", "b.json");
    REQUIRE(a.configs.size() == b.configs.size());
    for (std::size_t i = 0; i < a.configs.size(); ++i) CHECK(a.configs[i].id == b.configs[i].id);
    // The id is the FNV-1a hash of the canonical text (independent check of the
    // published FNV-1a 64 test vectors: "" and "a").
    CHECK(stableHash("") == "cbf29ce484222325");
    CHECK(stableHash("a") == "af63dc4c8601ec8c");
    CHECK(a.configs[0].id == stableHash(a.configs[0].canonical()));
    // Changing frames changes every id (results with other frame counts are not reused).
    std::string more = kProduct;
    more.replace(more.find("\"frames\": 3"), 11, "\"frames\": 4");
    SweepSpec c = parseSweep(more, "c.json");
    for (std::size_t i = 0; i < a.configs.size(); ++i) CHECK(a.configs[i].id != c.configs[i].id);
}

TEST_CASE("sweep: duplicates are dropped, bad input names the file and key") {
    SweepSpec d = parseSweep(R"({"scenes": ["builtin:cornell"], "axes": [{"ao.samples": [8, 8, 16]}]})", "d.json");
    CHECK(d.configs.size() == 2u);
    CHECK(d.duplicates == 1);
    auto throwsWith = [](const char* json, const std::string& needle) {
        try {
            parseSweep(json, "bad.json");
        } catch (const ConfigError& e) {
            std::string m = e.what();
            CHECK_MESSAGE(m.find("bad.json") != std::string::npos, m);
            CHECK_MESSAGE(m.find(needle) != std::string::npos, m);
            return;
        }
        FAIL("no ConfigError for " << json);
    };
    throwsWith(R"({"scenes": ["builtin:cornell"], "axes": [{"ao.smples": [8]}]})", "ao.smples");
    throwsWith(R"({"scenes": ["builtin:cornell"], "axes": [{"ao.samples": [0]}]})", "ao.samples");
    throwsWith(R"({"scenes": ["builtin:cornell"], "resolutions": ["64by48"]})", "64by48");
    throwsWith(R"({"scenes": ["builtin:cornell"], "axes": [{"a.b": [1], "ssr.steps": [1, 2]}]})", "different numbers");
    throwsWith(R"({"scenes": []})", "scenes");
    throwsWith(R"({"scenes": ["builtin:cornell"], "frame": 3})", "frame");
    throwsWith(R"({"scenes": ["builtin:cornell"] )", "not valid JSON");
}

TEST_CASE("sweep: shards partition the configurations exactly once") {
    SweepSpec s = parseSweep(kProduct, "t.json");
    for (int n : {1, 2, 3, 5, 7, 36, 50}) {
        std::map<std::string, int> seen;
        std::size_t total = 0;
        for (int i = 0; i < n; ++i) {
            auto part = shardOf(s.configs, i, n);
            total += part.size();
            // Balanced: shard sizes differ by at most one.
            CHECK(part.size() >= s.configs.size() / std::size_t(n));
            CHECK(part.size() <= s.configs.size() / std::size_t(n) + 1);
            for (auto& c : part) ++seen[c.id];
        }
        CHECK(total == s.configs.size());
        CHECK(seen.size() == s.configs.size());
        for (auto& [id, count] : seen) CHECK(count == 1);
    }
    CHECK_THROWS_AS(shardOf(s.configs, 3, 3), ConfigError);
}

TEST_CASE("sweep: resume skips completed configurations, retries failed and survives a torn line") {
    SweepSpec s = parseSweep(kProduct, "t.json");
    const auto& c = s.configs;
    std::ostringstream jsonl;
    jsonl << nlohmann::json{{"sweep", {{"id", c[0].id}}}, {"total_ms", 1.0}}.dump() << "\n";
    jsonl << nlohmann::json{{"sweep", {{"id", c[1].id}}}, {"failed", "ao: not in this build"}}.dump() << "\n";
    jsonl << "\n";
    jsonl << nlohmann::json{{"sweep", {{"id", c[2].id}}}, {"total_ms", 2.0}}.dump() << "\n";
    jsonl << R"({"sweep": {"id": ")" << c[3].id << R"("}, "total_)";  // killed while writing
    std::istringstream in(jsonl.str());
    int unreadable = -1;
    auto done = completedIds(in, &unreadable);
    CHECK(unreadable == 1);
    CHECK(done == std::set<std::string>{c[0].id, c[2].id});
    auto todo = pending(c, done);
    CHECK(todo.size() == c.size() - 2);
    for (auto& t : todo) CHECK((t.id != c[0].id && t.id != c[2].id));
    CHECK(todo.front().id == c[1].id);  // order kept, the failed one is retried
}

namespace {
// A results line as runBenchmark writes it, with awkward strings and one
// configuration value still in the old all-strings form.
nlohmann::json sampleResults(const SweepConfig& c) {
    nlohmann::json r = {
        {"scene", "builtin:\"atrium\", copy"}, {"resolution", "64x48"}, {"timer", "gpu"}, {"device", "GPU, \"x\""},
        {"version", "rtgi 0.9.0 (git abc)"}, {"frames", 5}, {"warmup", 1},
        {"config", {{"ao", "hbao"}, {"camera.position", "1,2,3"}, {"ao.samples", 16}, {"ao.radius", 0.5},
                    {"lpv.iterations", "8"}}},
        {"passes",
         {{{"name", "gbuffer"}, {"gpu_ms", {{"median", 0.25}, {"min", 0.125}, {"max", 1.5}, {"mean", 0.3}}}, {"dispatches", 1.0}},
          {{"name", "ao.hbao"}, {"gpu_ms", {{"median", 1.0625}, {"min", 1.0}, {"max", 2.0}, {"mean", 1.1}}}, {"dispatches", 2.0}}}},
        {"total_ms", 3.5}, {"memory_bytes", {{"total", 123456}}},
        {"error", {{"kind", "ao"}, {"rmse", 0.046}, {"psnr", 26.7}, {"interior", {{"rmse", 0.03}}},
                   {"reference", {{"spp", 64}, {"mean_stderr", 0.0323}, {"from_cache", true}}}}}};
    r["sweep"] = c.describe();
    r["sweep"]["name"] = "t";
    return r;
}
}  // namespace

TEST_CASE("sweep: tidy CSV rows round-trip the JSON line (one column per key and metric)") {
    SweepSpec s = parseSweep(kProduct, "t.json");
    const SweepConfig& c = s.configs[5];
    nlohmann::json r = sampleResults(c);
    auto header = readCsvLine(sweepCsvHeader());
    std::set<std::string> unique(header.begin(), header.end());
    CHECK(unique.size() == header.size());  // no duplicate column names
    auto rows = sweepCsvRows(r);
    REQUIRE(rows.size() == 2u);
    for (std::size_t p = 0; p < rows.size(); ++p) {
        auto cells = readCsvLine(rows[p]);
        REQUIRE(cells.size() == header.size());
        std::map<std::string, std::string> m;
        for (std::size_t i = 0; i < header.size(); ++i) m[header[i]] = cells[i];
        const auto& pass = r["passes"][p];
        CHECK(m["config_id"] == c.id);
        CHECK(m["sweep"] == "t");
        CHECK(m["scene_label"] == c.sceneLabel);
        CHECK(m["scene"] == r["scene"].get<std::string>());
        CHECK(m["device"] == r["device"].get<std::string>());
        CHECK(m["width"] == "64");
        CHECK(m["height"] == "48");
        CHECK(m["pass"] == pass["name"].get<std::string>());
        CHECK(std::stod(m["median_ms"]) == pass["gpu_ms"]["median"].get<double>());
        CHECK(std::stod(m["min_ms"]) == pass["gpu_ms"]["min"].get<double>());
        CHECK(std::stod(m["max_ms"]) == pass["gpu_ms"]["max"].get<double>());
        CHECK(std::stod(m["total_ms"]) == 3.5);
        CHECK(std::stod(m["memory_bytes"]) == 123456.0);
        // One column per configuration key, typed (the old string "8" too).
        CHECK(m["ao"] == "hbao");
        CHECK(m["camera.position"] == "1,2,3");
        CHECK(m["ao.samples"] == "16");
        CHECK(m["ao.radius"] == "0.5");
        CHECK(m["lpv.iterations"] == "8");
        CHECK(m["ssr.steps"].empty());  // a key the line does not hold: empty cell
        // One column per error metric.
        CHECK(m["error.kind"] == "ao");
        CHECK(std::stod(m["error.rmse"]) == doctest::Approx(0.046).epsilon(1e-9));
        CHECK(std::stod(m["error.psnr"]) == doctest::Approx(26.7).epsilon(1e-9));
        CHECK(std::stod(m["error.interior.rmse"]) == doctest::Approx(0.03).epsilon(1e-9));
        CHECK(std::stod(m["error.reference.mean_stderr"]) == doctest::Approx(0.0323).epsilon(1e-9));
        CHECK(m["error.reference.from_cache"] == "1");
        CHECK(m["error.ssim"].empty());
    }
    // Numbers are written bare and strings quoted, so readers can type columns.
    CHECK(rows[0].find(",16,") != std::string::npos);
    CHECK(rows[0].find("\"hbao\"") != std::string::npos);
    // A failed configuration has no CSV rows.
    nlohmann::json failed = {{"failed", "x"}, {"sweep", c.describe()}};
    CHECK(sweepCsvRows(failed).empty());
}

TEST_CASE("results.csv parses with Python's csv module into one typed column per key") {
    // pandas-free: tests/unit/check_results_csv.py reads the file with csv.DictReader
    // and checks that every numeric column's cells all parse as numbers.
    SweepSpec s = parseSweep(kProduct, "t.json");
    auto dir = std::filesystem::temp_directory_path() / "rtgi-csv-test";
    std::filesystem::create_directories(dir);
    const std::string file = (dir / "results.csv").string();
    {
        std::ofstream out(file);
        out << resultsCsvHeader() << "\n";
        for (std::size_t k : {std::size_t(0), std::size_t(5)}) {
            nlohmann::json r = sampleResults(s.configs[k]);
            // Typed config values of a full run: every key, as runBenchmark writes them.
            for (auto& [key, v] : describe(s.configs[k].settings())) r["config"][key] = typedValue(v);
            for (auto& row : resultsCsvRows(r)) out << row << "\n";
        }
        nlohmann::json single = sampleResults(s.configs[1]);  // a single run: no sweep columns
        single.erase("sweep");
        single.erase("error");
        for (auto& row : resultsCsvRows(single)) out << row << "\n";
    }
    const std::string cmd = "python3 " RTGI_SOURCE_DIR "/tests/unit/check_results_csv.py " + file +
                            " --rows 6 --numeric median_ms,total_ms,memory_bytes,width,ao.samples,ao.radius,"
                            "lpv.iterations,shadow.size,error.rmse,error.reference.mean_stderr"
                            " --string pass,scene,ao,lpv,error.kind";
    INFO(cmd);
    CHECK(std::system(cmd.c_str()) == 0);
}

TEST_CASE("sweep: every shipped sweep file parses and validates") {
    int files = 0;
    for (auto& e : std::filesystem::directory_iterator(std::string(RTGI_SOURCE_DIR) + "/benchmarks/sweeps")) {
        if (e.path().extension() != ".json") continue;
        std::ifstream f(e.path());
        std::stringstream ss;
        ss << f.rdbuf();
        SweepSpec s;
        CHECK_NOTHROW(s = parseSweep(ss.str(), e.path().string()));
        CHECK_MESSAGE(!s.configs.empty(), e.path());
        ++files;
    }
    CHECK(files >= 11);  // ten shipped sweeps + ci-tiny
}
