#pragma once
// Sweep files (benchmarks/sweeps/*.json) expanded into configurations, with
// stable ids, shards and resume bookkeeping. Pure: no GL, no files except
// what the caller passes in (unit-tested in tests/unit/test_sweep_spec.cpp).
// Format: docs/benchmarks-howto.md.
#include "render/settings.h"

#include <nlohmann/json.hpp>

#include <istream>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace rtgi {

struct SweepConfig {
    std::string id;                   // 16 hex digits, FNV-1a of the canonical description
    std::string sceneLabel;           // "atrium", "dragon", ...: how the report groups scenes
    std::vector<std::string> scenes;  // --scene list (merged), unexpanded ($SCENES stays)
    glm::ivec2 resolution{1920, 1080};
    int frames = 100, warmup = 20;
    // Explicit key=value assignments (base, then scene view, then axes), sorted
    // by key, last assignment of a key wins. Defaults are not listed, so ids
    // stay stable when new keys are added to the settings table.
    std::vector<std::pair<std::string, std::string>> assignments;
    // The subset of assignments that come from axes (what varies in the sweep).
    std::vector<std::pair<std::string, std::string>> axisValues;
    // Named in the sweep's "held_out" list: a view kept out of tuning, reported
    // as the test set (not part of the id).
    bool heldOut = false;

    std::string canonical() const;  // what the id hashes
    std::string label() const;      // "atrium view=a 1920x1080 ao=hbao ao.samples=8"
    Settings settings() const;      // defaults + assignments
    nlohmann::json describe() const;  // the "sweep" object of a results.jsonl line
};

struct SweepSpec {
    std::string name, description;
    bool images = false;  // write each configuration's images under DIR/images/<id>/
    bool check = false;   // --check on every configuration
    std::vector<SweepConfig> configs;  // deduplicated, in expansion order (scenes outermost)
    int duplicates = 0;                // expansions dropped because an earlier one had the same id
};

// Parses and expands a sweep; every assignment is validated against the
// settings table. Throws ConfigError naming `source` and the offending entry.
SweepSpec parseSweep(const std::string& jsonText, const std::string& source);

// 64-bit FNV-1a as 16 lower-case hex digits.
std::string stableHash(const std::string& text);

// Configuration k goes to shard k mod n (round robin spreads the expensive
// ends of an axis over all shards). Every configuration lands in exactly one shard.
std::vector<SweepConfig> shardOf(const std::vector<SweepConfig>& all, int index, int count);

// Ids of the configurations that completed in a results.jsonl stream (lines
// with "sweep".id and neither "failed" nor "retry"); unparsable lines (a run killed while
// writing) are ignored and counted in *unreadable.
std::set<std::string> completedIds(std::istream& jsonl, int* unreadable = nullptr);

// The configurations still to run.
std::vector<SweepConfig> pending(const std::vector<SweepConfig>& configs, const std::set<std::string>& done);

// CSV of a sweep: the tidy columns of results_csv.h (one row per
// configuration × pass; config_id, sweep and scene_label filled in).
std::string sweepCsvHeader();
std::vector<std::string> sweepCsvRows(const nlohmann::json& resultLine);

}  // namespace rtgi
