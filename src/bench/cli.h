#pragma once
// Command-line options shared by rtgi-bench and rtgi-view (SPEC section 12).
#include "bench/run.h"

#include <string>
#include <vector>

namespace rtgi {

struct CommandLine {
    RunOptions run;
    Settings settings;
    int device = -1;
    bool debug = false;
    bool help = false;
    bool listDevices = false;
    bool validateOnly = false;  // --validate-only: load scenes and settings, no GL, exit 0
    std::string sweep;    // --sweep FILE.json
    int shardIndex = 0, shardCount = 1;
    bool scenesGiven = false;
    std::vector<std::string> extra;  // host-specific options left for the caller
    // --config files then --set, in order (settings = these applied on top of
    // the scene's suggested settings: see settingsFor).
    Assignments assignments;
};

// Parses argv; throws ConfigError naming the option on bad input. Options a
// host handles itself are returned in `extra` when listed in hostOptions
// (name -> takes a value).
CommandLine parseCommandLine(int argc, char** argv, const std::vector<std::pair<std::string, bool>>& hostOptions = {});
// The settings of a run of `scene`: defaults, the scene's suggestions, then
// the command line's --config / --set.
// Consistency of options that parse alone (empty --scene, --shard without
// --sweep); throws ConfigError. Called by parseCommandLine.
void checkCommandLine(const CommandLine& c);
// "8G", "512M", "1048576" -> bytes (binary multiples); throws ConfigError naming `opt`.
std::int64_t parseByteSize(const std::string& opt, const std::string& v);
Settings settingsFor(const Scene& scene, const CommandLine& cl);
std::string commonHelp();
std::string settingsHelp();

}  // namespace rtgi
