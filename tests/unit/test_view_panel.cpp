// rtgi-view's ImGui panel model (view/panel_model.h): every configuration key
// has a widget that can show and set its values, edits go through the
// settings table, timing history order and median, --script parsing.
#include "view/panel_model.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <sstream>

using namespace rtgi;
using namespace rtgi::view;

TEST_CASE("viewer panel: every key of rtgi-bench --help gets a widget that holds its default and can set it") {
    const Settings defaults;
    const auto shown = describe(defaults);
    for (auto& k : settingKeys()) {
        INFO(k.key << " values " << k.values);
        KeyWidget w = widgetFor(k);
        const std::string v = shown.at(k.key);
        switch (w.kind) {
            case KeyWidget::Kind::Toggle: CHECK((v == "on" || v == "off")); break;
            case KeyWidget::Kind::Choice:
                CHECK(std::find(w.choices.begin(), w.choices.end(), v) != w.choices.end());
                for (auto& c : w.choices) {  // every listed choice is a value the table accepts
                    Settings s;
                    CHECK(applyPanelSetting(s, k.key, c) == "");
                }
                break;
            case KeyWidget::Kind::Int:
            case KeyWidget::Kind::Float: {
                double x = std::stod(v);
                CHECK(x >= w.lo);
                CHECK(x <= w.hi);
                Settings s;  // both ends of the slider are accepted
                std::ostringstream lo, hi;
                lo << w.lo;
                hi << w.hi;
                CHECK(applyPanelSetting(s, k.key, w.kind == KeyWidget::Kind::Int ? std::to_string(int(w.lo)) : lo.str()) == "");
                CHECK(applyPanelSetting(s, k.key, w.kind == KeyWidget::Kind::Int ? std::to_string(int(w.hi)) : hi.str()) == "");
                break;
            }
            case KeyWidget::Kind::Text: {
                Settings s;  // the text field round-trips the shown value
                CHECK(applyPanelSetting(s, k.key, v) == "");
                break;
            }
        }
    }
    CHECK(widgetFor(*std::find_if(settingKeys().begin(), settingKeys().end(), [](auto& k) { return k.key == "ao"; })).choices.size() == 9u);
    auto find = [](const char* key) {
        return widgetFor(*std::find_if(settingKeys().begin(), settingKeys().end(), [&](auto& k) { return k.key == key; }));
    };
    CHECK(find("ao.radius").kind == KeyWidget::Kind::Float);
    CHECK(find("ao.radius").hi == 1e6);
    CHECK(find("ao.radius").logScale);
    CHECK(find("lpv.iterations").kind == KeyWidget::Kind::Int);
    CHECK(find("lpv.occlusion").kind == KeyWidget::Kind::Toggle);
    CHECK(find("ao.radius_mode").choices.size() == 8u);  // fixed, dual, dynamic1..dynamic6
    CHECK(find("lpv.grid").kind == KeyWidget::Kind::Text);  // N or NxMxK
    CHECK(find("camera.fov").kind == KeyWidget::Kind::Text);  // auto or a number
}

TEST_CASE("viewer panel: an invalid edit leaves the settings alone and says why") {
    Settings s;
    CHECK(applyPanelSetting(s, "ao.radius", "2.5") == "");
    CHECK(s.ao.radius == 2.5f);
    std::string msg = applyPanelSetting(s, "ao.radius", "-1");
    CHECK(msg.find("ao.radius") != std::string::npos);
    CHECK(s.ao.radius == 2.5f);
    CHECK(changedKeys(Settings{}, s) == std::vector<std::string>{"ao.radius"});
}

TEST_CASE("viewer timing history: execution order with the frame total last, rolling window, median") {
    TimingHistory h(3);
    h.add({{"frame", 10.0}, {"gbuffer", 1.0}, {"ao.gtao", 4.0}});
    h.add({{"gbuffer", 3.0}, {"ao.gtao", 2.0}, {"frame", 12.0}});
    h.add({{"gbuffer", 2.0}, {"ao.gtao", 9.0}, {"frame", 11.0}});
    h.add({{"gbuffer", 100.0}, {"ao.gtao", 1.0}, {"frame", 14.0}});  // the first frame drops out
    CHECK(h.order() == std::vector<std::string>{"gbuffer", "ao.gtao", "frame"});
    CHECK(h.samples("gbuffer").size() == 3u);
    CHECK(h.median("gbuffer") == 3.0);
    CHECK(h.median("ao.gtao") == 2.0);
    CHECK(h.median("frame") == 12.0);
    h.add({{"gbuffer", 1.0}, {"frame", 1.0}});  // AO switched off: it leaves the panel
    CHECK(h.order() == std::vector<std::string>{"gbuffer", "frame"});
    CHECK(h.samples("ao.gtao").empty());
}

TEST_CASE("viewer --script: actions sorted by frame; malformed lines name the file and line") {
    auto a = parseScript("# comment\n5 set ao.radius 2\n2 compare split\n\n7 screenshot out.png  # after\n", "s.txt");
    REQUIRE(a.size() == 3u);
    CHECK(a[0].frame == 2);
    CHECK(a[0].verb == "compare");
    CHECK(a[1].args == std::vector<std::string>{"ao.radius", "2"});
    CHECK(a[2].args == std::vector<std::string>{"out.png"});
    auto p = parseScript("0 path play\n4 history reset\n", "p.txt");  // --path playback and the history key
    REQUIRE(p.size() == 2u);
    CHECK(p[0].verb == "path");
    CHECK(p[1].args == std::vector<std::string>{"reset"});
    for (const char* bad : {"x set a 1", "3 fly away", "3 set ao.radius", "3"}) {
        INFO(bad);
        try {
            parseScript(std::string("1 panel on\n") + bad + "\n", "s.txt");
            FAIL("no error");
        } catch (const ConfigError& e) {
            CHECK(std::string(e.what()).find("s.txt:2") != std::string::npos);
        }
    }
}
