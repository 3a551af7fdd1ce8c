// The frame built from the passes' declarations (render/frame_plan.h): no GL
// context is needed, since declare() only describes what a pass uses.
#include "render/renderer.h"
#include "scene/builtin.h"

#include <doctest/doctest.h>

#include <functional>

using namespace rtgi;

namespace {

// A pass that only declares (the frame build never executes it).
class DeclaredPass final : public Pass {
public:
    DeclaredPass(std::string name, std::function<void(PassDecl&)> decl) : name_(std::move(name)), decl_(decl) {}
    std::string name() const override { return name_; }
    void declare(PassDecl& d, const Scene&, const Settings&) const override { decl_(d); }
    void execute(FrameContext&) override {}

private:
    std::string name_;
    std::function<void(PassDecl&)> decl_;
};

using Script = std::vector<std::pair<std::string, std::function<void(PassDecl&)>>>;

FramePlan build(const Script& script, const Settings& s = {}, const std::vector<Family>& families = {}) {
    std::vector<std::unique_ptr<Pass>> passes;
    for (auto& [n, d] : script) passes.push_back(std::make_unique<DeclaredPass>(n, d));
    return FramePlan::build(std::move(passes), families, Scene{}, s);
}

int indexOf(const FramePlan& p, const std::string& name) {
    for (std::size_t i = 0; i < p.passes().size(); ++i)
        if (p.passes()[i]->name() == name) return int(i);
    return -1;
}

bool isSkipped(const FramePlan& p, const std::string& name, const std::string& why) {
    for (auto& s : p.skipped())
        if (s.name == name) return s.reason.find(why) != std::string::npos;
    return false;
}

}  // namespace

TEST_CASE("frame build: a pass reading what no earlier pass writes is reported, naming pass and resource") {
    // Deliberately wrong declaration: "shade" reads ao, but the AO producer runs after it.
    Script wrong = {{"gbuffer", [](PassDecl& d) { d.write(R::normal); }},
                    {"shade", [](PassDecl& d) { d.read(R::normal).read(R::ao).write(R::hdr); }},
                    {"ao", [](PassDecl& d) { d.read(R::normal).write(R::ao); }}};
    CHECK_THROWS_WITH_AS(build(wrong), doctest::Contains("pass 'shade' reads 'ao', which no earlier pass"),
                         ConfigError);
    // The same frame in the right order builds.
    Script right = {wrong[0], wrong[2], wrong[1]};
    CHECK(build(right).passes().size() == 3);
    // Forcing the producer off is the same error, at frame build.
    Settings off;
    off.post.passesOff = "ao";
    CHECK_THROWS_WITH_AS(build(right, off), doctest::Contains("reads 'ao'"), ConfigError);
    off.post.passesOff = "nonesuch";
    CHECK_THROWS_WITH_AS(build(right, off), doctest::Contains("no pass named 'nonesuch'"), ConfigError);
}

TEST_CASE("frame build: a second plain write is an error; accumulate adds only after an earlier writer") {
    Script twice = {{"a", [](PassDecl& d) { d.write(R::indirectDiffuse); }},
                    {"b", [](PassDecl& d) { d.write(R::indirectDiffuse); }}};
    CHECK_THROWS_WITH_AS(build(twice), doctest::Contains("'a' already wrote this frame"), ConfigError);

    Script acc = {{"lpv", [](PassDecl& d) { d.write(R::indirectDiffuse); }},
                  {"near", [](PassDecl& d) { d.accumulate(R::indirectDiffuse); }}};
    FramePlan p = build(acc);
    CHECK_FALSE(p.writtenBefore(indexOf(p, "lpv"), R::indirectDiffuse));
    CHECK(p.writtenBefore(indexOf(p, "near"), R::indirectDiffuse));  // adds to lpv's value
    // Without the first writer the accumulating pass is the first writer: it overwrites.
    Settings off;
    off.post.passesOff = "lpv";
    FramePlan q = build(acc, off);
    CHECK_FALSE(q.writtenBefore(indexOf(q, "near"), R::indirectDiffuse));
}

TEST_CASE("frame build: onlyIfRead producers run while some pass reads them, this frame or the next") {
    auto history = [](PassDecl& d) { d.read(R::hdr).write(R::history).onlyIfRead(); };
    auto compose = [](PassDecl& d) { d.write(R::hdr); };
    FramePlan none = build({{"compose", compose}, {"history", history}});
    CHECK(indexOf(none, "history") < 0);
    CHECK(isSkipped(none, "history", "no pass in this frame reads history"));
    FramePlan read = build({{"reproject", [](PassDecl& d) { d.readPrevious(R::history).write(R::specular); }},
                            {"compose", compose},
                            {"history", history}});
    CHECK(indexOf(read, "history") == 2);
    // Reading the previous frame's value of something nobody writes is an error.
    CHECK_THROWS_WITH_AS(build({{"reproject", [](PassDecl& d) { d.readPrevious(R::diffuseHistory); }}}),
                         doctest::Contains("previous frame's 'diffuseHistory'"), ConfigError);
}

TEST_CASE("frame build: a family gate skips its passes with one reason; a requested family must run") {
    Family fx{"fx.", "fx", [](const Scene&, const Settings& s) {
                  return s.post.exposure > 2.0f ? Need::yes() : Need::no("fx needs exposure > 2");
              },
              [](const Settings& s) { return s.post.exposure == 1.5f; }, nullptr};
    Script script = {{"fx.a", [](PassDecl& d) { d.write(R::ao); }}, {"fx.b", [](PassDecl& d) { d.skip("b is off"); }}};
    Settings s;
    s.post.exposure = 1.0f;
    FramePlan p = build(script, s, {fx});
    CHECK(p.passes().empty());
    CHECK(isSkipped(p, "fx.a", "fx needs exposure > 2"));
    s.post.exposure = 3.0f;
    FramePlan q = build(script, s, {fx});
    CHECK(indexOf(q, "fx.a") == 0);
    CHECK(isSkipped(q, "fx.b", "b is off"));
    s.post.exposure = 1.5f;  // requested, but the gate says no
    CHECK_THROWS_WITH_AS(build(script, s, {fx}), doctest::Contains("setting 'fx': requested, but fx needs exposure"),
                         ConfigError);
}

TEST_CASE("the real frame: near-field light adds to the LPV's indirect light; history only when read") {
    Scene atrium = loadBuiltin("atrium");
    Settings s;
    s.ao.variant = AoSettings::Variant::Gtao;
    s.ao.nearfield = 1.0f;
    s.lpv.mode = Toggle::On;
    FramePlan p = FramePlan::build(frameScript(), frameFamilies(), atrium, s);
    int apply = indexOf(p, "lpv.apply"), near = indexOf(p, "ao.nearfield");
    REQUIRE(apply >= 0);
    REQUIRE(near > apply);
    // The bug this replaces: near-field light overwrote lpv.apply's indirect light.
    CHECK(p.decl(near).uses(R::indirectDiffuse, PassDecl::Access::accumulate));
    CHECK(p.writtenBefore(near, R::indirectDiffuse));
    CHECK(indexOf(p, "post.history") >= 0);  // ao.nearfield reprojects last frame's radiance

    s.ao.nearfield = 0.0f;
    s.ssr.tracer = SsrSettings::Tracer::Off;
    FramePlan q = FramePlan::build(frameScript(), frameFamilies(), atrium, s);
    CHECK(isSkipped(q, "post.history", "no pass in this frame reads history"));
    CHECK(isSkipped(q, "ao.nearfield", "ao.nearfield=0"));
    // Every shared resource a pass of the frame reads has a writer before it.
    for (int i = 0; i < int(q.passes().size()); ++i)
        for (auto& u : q.decl(i).uses())
            if (u.access == PassDecl::Access::read) CHECK(q.writtenBefore(i, u.resource));
}

TEST_CASE("--print-frame table lists each pass with reads and writes, and the skipped ones with why") {
    Script acc = {{"lpv", [](PassDecl& d) { d.write(R::indirectDiffuse); }},
                  {"near", [](PassDecl& d) { d.read(R::normal).accumulate(R::indirectDiffuse); }},
                  {"off", [](PassDecl& d) { d.skip("because"); }}};
    CHECK_THROWS_AS(build(acc), ConfigError);  // near reads normal that nobody writes
    acc.insert(acc.begin(), {"gbuffer", [](PassDecl& d) { d.write(R::normal); }});
    std::string t = build(acc).table();
    CHECK(t.find("+=indirectDiffuse") != std::string::npos);
    CHECK(t.find("because") != std::string::npos);
    CHECK(t.find("gbuffer.normal") != std::string::npos);
}
