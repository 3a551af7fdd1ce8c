// The command line shared by rtgi-bench and rtgi-view (app/cli.h): each binary
// accepts and lists only its own options, and names the other binary when
// given one of its options; the recorded command line quotes like a shell.
#include "app/cli.h"

#include <doctest/doctest.h>

#include <string>
#include <vector>

using namespace rtgi;

namespace {
CommandLine parse(Host h, std::vector<std::string> args) {
    args.insert(args.begin(), h == Host::Bench ? "rtgi-bench" : "rtgi-view");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    return parseCommandLine(h, int(argv.size()), argv.data());
}

std::string error(Host h, std::vector<std::string> args) {
    try {
        parse(h, std::move(args));
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST_CASE("cli: the viewer refuses bench-only options, naming rtgi-bench, and the bench refuses viewer options") {
    for (const char* opt : {"--sweep", "--out", "--check", "--no-images", "--warmup", "--device", "--list-devices", "--shard"}) {
        INFO(opt);
        std::string e = error(Host::View, {opt, "x"});
        CHECK(e.find(std::string("'") + opt + "' is for rtgi-bench only") != std::string::npos);
    }
    for (const char* opt : {"--screenshot", "--no-vsync", "--script"}) {
        INFO(opt);
        CHECK(error(Host::Bench, {opt, "x"}).find("is for rtgi-view only") != std::string::npos);
    }
    CHECK(error(Host::View, {"--bogus"}).find("unknown option '--bogus'") != std::string::npos);
    // Shared options mean the same in both.
    for (Host h : {Host::Bench, Host::View}) {
        CommandLine c = parse(h, {"--scene", "builtin:cornell", "--res", "64x48", "--set", "ao=gtao", "--frames", "3"});
        CHECK(c.run.scenes == std::vector<std::string>{"builtin:cornell"});
        CHECK(c.run.resolution == glm::ivec2(64, 48));
        CHECK((c.settings.ao.variant == AoSettings::Variant::Gtao));
        CHECK(c.framesGiven);
        CHECK(parse(h, {"--version"}).version);
    }
    CHECK(parse(Host::View, {"--reference"}).liveReference);
    CHECK(parse(Host::Bench, {"--reference"}).run.reference);
    CHECK(parse(Host::View, {"--screenshot", "a.png", "--no-vsync"}).screenshot == "a.png");
}

TEST_CASE("cli: each binary's --help lists exactly the options it accepts") {
    const std::string view = optionsHelp(Host::View), bench = optionsHelp(Host::Bench);
    for (const char* opt : {"--sweep", "--out", "--check", "--compare", "--warmup", "--device", "--shard"}) {
        INFO(opt);
        CHECK(view.find(opt) == std::string::npos);
        CHECK(bench.find(opt) != std::string::npos);
    }
    for (const char* opt : {"--screenshot", "--no-vsync", "--script"}) {
        INFO(opt);
        CHECK(view.find(opt) != std::string::npos);
        CHECK(bench.find(opt) == std::string::npos);
    }
    CHECK(versionString().rfind("rtgi ", 0) == 0);
}

TEST_CASE("cli: the recorded command line is shell-quoted") {
    std::vector<std::string> args = {"rtgi-bench", "--set", "camera.position=1,2,3", "--out", "my dir", "it's"};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    CHECK(quoteCommandLine(int(argv.size()), argv.data()) ==
          "rtgi-bench --set camera.position=1,2,3 --out 'my dir' 'it'\\''s'");
}
