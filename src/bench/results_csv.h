#pragma once
// results.csv in tidy form (docs/benchmarks-howto.md): one row per run × pass;
// one column per run property, per configuration key (named as the key) and
// per error metric (error.*); numbers unquoted so that pandas.read_csv and
// Python's csv module see typed columns without post-processing. Single runs
// and sweeps write the same columns (the sweep ones are empty for a single run).
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rtgi {

// A configuration value as typed JSON: a number when the whole text is a
// finite decimal number ("8", "0.5", "1e-3"), else the string ("hbao",
// "16x8x4", "auto", "1,2,3").
nlohmann::json typedValue(const std::string& text);

std::string resultsCsvHeader();
// The rows of one results object (a single run's results.json, or a sweep's
// results.jsonl line); none for a failed sweep line.
std::vector<std::string> resultsCsvRows(const nlohmann::json& results);
// RFC 4180 quoting of one CSV field.
std::string csvQuote(const std::string& s);

}  // namespace rtgi
