// rtgi-view: a window on the same renderer as rtgi-bench (GLFW + Dear ImGui;
// docs/viewer.md). Uses app/ (command line, scenes), render/ and view/; never bench/.
#include "app/cli.h"
#include "compute/lib/view_shared.h"
#include "gl/input_files.h"
#include "gl/program.h"
#include "gl/window_host.h"
#include "render/renderer.h"
#include "scene/path.h"
#include "view/controls.h"
#include "view/display.h"
#include "view/fly_camera.h"
#include "view/live_reference.h"
#include "view/panel_model.h"
#include "view/path_player.h"
#include "view/ui.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

using namespace rtgi;

namespace {

int run(int argc, char** argv) {
    CommandLine cl = parseCommandLine(Host::View, argc, argv);
    if (cl.help) {
        std::printf("rtgi-view: a window on the rtgi renderer\n%s\n\n%s"
                    "  With --frames N (or --screenshot) rtgi-view renders N frames and exits.\n\nKeys:\n",
                    versionString().c_str(), optionsHelp(Host::View).c_str());
        for (auto& l : view::keyHelp()) std::printf("  %s\n", l.c_str());
        std::printf("\n%s", settingsHelp().c_str());
        return 0;
    }
    if (cl.version) {
        std::printf("rtgi-view %s\n", versionString().c_str());
        return 0;
    }
    std::vector<view::ScriptAction> script;
    if (!cl.script.empty()) {
        try {
            script = view::parseScript(readInputFile(cl.script, InputKind::Config), escapeControl(cl.script));
        } catch (const InputError& e) {
            throw ConfigError(std::string("--script ") + e.what());
        }
    }
    const std::string screenshotPath = cl.screenshot;
    bool vsync = cl.vsync;
    const bool automate = cl.framesGiven || !screenshotPath.empty();

    Scene scene = loadScenes(cl.run.scenes);
    for (auto& w : scene.warnings) std::fprintf(stderr, "rtgi-view: warning: %s\n", escapeControl(w).c_str());
    auto host = gl::WindowHost::create(cl.run.resolution, "rtgi-view: " + scene.name, cl.debug, vsync && !automate);
    gl::Profiler profiler(host->info().timerQuery);
    Settings settings = settingsFor(scene, cl);
    // What the panel's reset buttons restore: the defaults with the scene's suggestions.
    const Settings defaults = effectiveSettings(scene.suggestedSettings, {}, scene.name);
    // --path (issue 23, docs/viewer.md "Paths"): the scene state at the player's time, evaluated from the
    // rest scene every frame as rtgi-bench does; the path's camera keys, else the user's camera.
    std::optional<Scene> rest;
    std::optional<Path> path;
    std::optional<view::PathPlayer> player;
    if (!cl.run.path.empty()) {
        rest = scene;
        path = loadPath(cl.run.path, scene);
        player.emplace(path->frameCount(), path->fps);
    }
    Renderer renderer(scene, settings, profiler);
    gl::ProgramCache& programs = renderer.programs();
    view::ScreenPainter painter;
    view::TimingHistory timings(240);
    view::LiveReference live(4);
    view::Ui ui(host->nativeHandle());
    view::ViewState state;
    state.liveReference = cl.liveReference;
    if (path) {
        state.temporal.path = true;
        state.temporal.pathName = path->name;
        state.temporal.frames = path->frameCount();
        state.temporal.fps = path->fps;
    }
    FloatImage lastFinal;  // the previous frame's final image (frame-to-frame change)

    const Camera sceneCamera = resolveCamera(scene, settings);
    const float diagonal = glm::length(scene.bounds().extent());
    Camera camera = sceneCamera;  // used as is until the user flies, so --frames matches rtgi-bench exactly
    view::FlyCamera fly = view::FlyCamera::fromCamera(camera, diagonal);
    const std::vector<std::string> views = namedViews(scene);
    int viewIndex = -1;

    std::vector<std::pair<int, int>> keys;
    host->onKey = [&](int k, int mods) { keys.emplace_back(k, mods); };
    bool cut = true;
    View prev;
    unsigned frame = 0;
    glm::dvec2 lastCursor = host->cursor();
    auto lastTime = std::chrono::steady_clock::now();
    int shots = 0;
    std::size_t nextAction = 0;

    auto say = [&](const std::string& m) {
        state.message = m;
        std::fprintf(stderr, "rtgi-view: %s\n", m.c_str());
    };
    // Every settings change (keys, panel widgets, --script) ends here:
    // reconfigure, or keep the old frame and say why the new one cannot run.
    auto reconfigure = [&](const Settings& before, const std::string& what) {
        try {
            renderer.configure(settings);
            say(what);
        } catch (const ConfigError& e) {
            settings = before;
            renderer.configure(settings);
            say(e.what());
        }
        cut = true;
    };

    while (!host->shouldClose()) {
        host->pollEvents();
        auto now = std::chrono::steady_clock::now();
        float dt = std::min(std::chrono::duration<float>(now - lastTime).count(), 0.1f);
        lastTime = now;

        // --script: this frame's actions, through the panel's own functions.
        std::vector<std::string> viewShots, windowShots;
        for (; nextAction < script.size() && script[nextAction].frame <= int(frame); ++nextAction) {
            const view::ScriptAction& a = script[nextAction];
            const std::string& x = a.args[0];
            if (a.verb == "set") {
                Settings before = settings;
                std::string err = view::applyPanelSetting(settings, a.args[0], a.args[1]);
                if (!err.empty()) throw ConfigError(cl.script + ": " + err);
                reconfigure(before, a.args[0] + "=" + a.args[1]);
            } else if (a.verb == "image") state.imageName = x;
            else if (a.verb == "exposure") state.present.exposure = std::stof(x);
            else if (a.verb == "channel") {
                const char* names[] = {"rgb", "r", "g", "b", "a"};
                for (int c = 0; c < 5; ++c)
                    if (x == names[c]) state.present.channel = c;
            } else if (a.verb == "reference") state.liveReference = x == "on";
            else if (a.verb == "compare") {
                const char* names[] = {"off", "split", "toggle", "heatmap", "side"};
                for (int c = 0; c < 5; ++c)
                    if (x == names[c]) state.compare = c;
            } else if (a.verb == "split") state.present.split = std::stof(x);
            else if (a.verb == "screenshot") viewShots.push_back(x);
            else if (a.verb == "window") windowShots.push_back(x);
            else if (a.verb == "panel") state.showPanel = x == "on";
            else if (a.verb == "history") state.temporal.resetHistory = x == "reset";
            else if (a.verb == "path") {
                if (!player) throw ConfigError(cl.script + ": 'path " + x + "' needs --path");
                if ((x == "play" && !player->playing()) || (x == "pause" && player->playing())) player->togglePlay();
                else if (x == "home") player->home();
                else if (x == "next" || x == "prev") player->step(x == "next" ? 1 : -1);
                else if (x != "play" && x != "pause")
                    throw ConfigError(cl.script + ": 'path " + x + "': expected play, pause, home, next or prev");
            }
        }

        bool screenshot = false;
        for (auto [k, mods] : keys) {
            if (ui.wantsKeyboard()) break;  // typing into a panel field
            Settings before = settings;
            view::KeyAction a = view::handleKey(k, mods, settings);
            if (a.reconfigure) reconfigure(before, a.message);
            if (a.quit) host->requestClose();
            if (a.toggleHelp) state.showPanel = !state.showPanel;
            if (a.toggleVsync) {
                vsync = !vsync;
                host->setVsync(vsync);
                say(std::string("vsync ") + (vsync ? "on" : "off"));
            }
            if (a.finalImage) state.imageName = "final";
            if (a.imageStep != 0) {
                auto imgs = view::displayImages(renderer);
                int n = int(imgs.size()), cur = 0;
                for (int i = 0; i < n; ++i)
                    if (imgs[std::size_t(i)].name == state.imageName) cur = i;
                if (n > 0) state.imageName = imgs[std::size_t((cur + a.imageStep + n) % n)].name;
            }
            if ((a.viewStep != 0 && !views.empty()) || a.resetCamera) {
                Settings s = settings;
                if (a.resetCamera) {
                    viewIndex = -1;
                    s.camera.view.clear();
                } else {
                    int n = int(views.size());
                    viewIndex = ((viewIndex < 0 ? (a.viewStep > 0 ? -1 : 0) : viewIndex) + a.viewStep + n) % n;
                    s.camera.view = views[std::size_t(viewIndex)];
                }
                camera = resolveCamera(scene, s);
                fly = view::FlyCamera::fromCamera(camera, diagonal);
                cut = true;
                say(a.resetCamera ? "scene camera" : "view " + s.camera.view);
            }
            if (a.playPause || a.frameStep != 0 || a.pathHome) {
                if (!player) say("no --path given: Space, Left/Right and Home play a path");
                else if (a.playPause) player->togglePlay();
                else if (a.pathHome) player->home();
                else player->step(a.frameStep);
            }
            if (a.toggleHistoryReset) {
                state.temporal.resetHistory = !state.temporal.resetHistory;
                say(state.temporal.resetHistory ? "history: reset every frame" : "history: live reprojection");
            }
            screenshot |= a.screenshot;
            if (a.dumpConfig) {
                std::string file = "rtgi-view-config-" + std::to_string(shots++) + ".json";
                std::ofstream(file) << view::dumpConfig(settings, camera);
                std::string scenes;
                for (auto& s : cl.run.scenes) scenes += " --scene " + s;
                glm::ivec2 fb = host->framebufferSize();
                say("wrote " + file + "; replay: rtgi-bench" + scenes + " --res " + std::to_string(fb.x) + "x" +
                    std::to_string(fb.y) + " --config " + file);
            }
        }
        keys.clear();

        if (!automate) {
            // Mouse look while the right button is held (not over the panel); WASD/QE movement.
            glm::dvec2 c = host->cursor();
            bool flew = false;
            if (host->mouseButtonDown(1) && !ui.wantsMouse()) {
                fly.look(float(c.x - lastCursor.x), float(c.y - lastCursor.y), 0.003f);
                flew = c != lastCursor;
            }
            lastCursor = c;
            glm::vec3 axes(0.0f);
            if (!ui.wantsKeyboard()) {
                if (host->keyDown(GLFW_KEY_W)) axes.z += 1;
                if (host->keyDown(GLFW_KEY_S)) axes.z -= 1;
                if (host->keyDown(GLFW_KEY_D)) axes.x += 1;
                if (host->keyDown(GLFW_KEY_A)) axes.x -= 1;
                if (host->keyDown(GLFW_KEY_E)) axes.y += 1;
                if (host->keyDown(GLFW_KEY_Q)) axes.y -= 1;
            }
            if (axes != glm::vec3(0.0f)) {
                fly.move(axes, dt, host->keyDown(GLFW_KEY_LEFT_SHIFT) || host->keyDown(GLFW_KEY_RIGHT_SHIFT));
                flew = true;
            }
            if (flew) camera = fly.toCamera();  // the live reference restarts: its view changed
        }

        // The panel's play button and frame slider (last frame's panel).
        if (player && state.temporal.playToggled) player->togglePlay();
        if (player && state.temporal.scrubTo >= 0) player->scrub(state.temporal.scrubTo);
        state.temporal.playToggled = false;
        state.temporal.scrubTo = -1;
        Camera frameCamera = camera;
        if (player) {
            Scene sceneNow = *rest;
            evaluateScene(sceneNow, *rest, &*path, player->time());
            renderer.updateScene(sceneNow);
            frameCamera = pathCamera(&*path, player->time(), camera);
            cut = cut || player->jumped();  // a scrub or a step back: the histories belong to another time
        }

        glm::ivec2 size = host->framebufferSize();
        if (size.x <= 0 || size.y <= 0) continue;  // minimized
        if (size != prev.size) cut = true;          // resized: histories do not match
        // X: every frame as a cut, so every temporal filter shows its no-history value.
        View v = makeView(frameCamera, size, cut || state.temporal.resetHistory ? nullptr : &prev, frame);
        renderer.render(v);
        prev = v;
        cut = false;
        if (player) player->rendered();
        if (state.showPanel) {
            // The live temporal numbers: the filters' disoccluded-pixel counts (a read-back) and the change of
            // the final image since the last frame (with a still camera: its flicker).
            state.temporal.disoccluded.clear();
            for (const char* name : {"ao.temporal", "ssr.temporal"})
                if (Pass* p = renderer.findPass(name)) {
                    view::TemporalState::FilterCount c{name, 0, 0};
                    for (auto& [k, val] : p->stats())
                        if (k == "disoccluded_pixels") c.disoccluded = val;
                    auto dbg = renderer.debugImages(*p);
                    if (!dbg.empty() && dbg.front().tex) c.pixels = double(dbg.front().tex->width()) * dbg.front().tex->height();
                    state.temporal.disoccluded.push_back(c);
                }
            FloatImage fin = readTexture(renderer.resources().ldr);
            auto change = view::rmsChange(lastFinal, fin, 3);
            state.temporal.haveChange = bool(change);
            state.temporal.change = change.value_or(0.0);
            lastFinal = std::move(fin);
        }
        if (player) {
            state.temporal.frame = player->frame();
            state.temporal.time = player->time();
            state.temporal.playing = player->playing();
        }

        // Live reference: a few more samples of the matching reference.
        if (state.liveReference) {
            try {
                live.setSamplesPerFrame(state.samplesPerFrame);
                live.update(renderer, v);
            } catch (const std::exception& e) {
                state.liveReference = false;
                live.reset();
                say(std::string("live reference: ") + e.what());
            }
        } else if (live.active()) {
            live.reset();
        }

        auto imgs = view::displayImages(renderer);
        const view::DisplayImage* shown = imgs.empty() ? nullptr : &imgs.front();
        for (auto& im : imgs)
            if (im.name == state.imageName) shown = &im;
        if (state.autoHeat && live.errors().valid && live.errors().heatMax > 0)
            state.present.heatMax = float(live.errors().heatMax);
        view::PresentOptions opts = state.present;
        view::DisplayImage comparedImage;
        const gl::Texture* refTex = state.liveReference ? live.mean() : nullptr;
        const gl::Texture* cmpTex = refTex ? live.compared(renderer) : nullptr;
        if (refTex && cmpTex && state.compare != RTGI_VIEW_COMPARE_OFF) {
            // Comparing: the technique's output that matches the reference, shown the same way.
            const bool ao = live.kind() == ReferenceSettings::Kind::Ao;
            comparedImage = {ao ? "ao" : "compared", cmpTex, ao ? RTGI_VIEW_MODE_GREY : RTGI_VIEW_MODE_RADIANCE,
                             ao ? 1.0f : settings.post.exposure};
            opts.compare = state.compare;
            opts.reference = refTex;
            opts.referenceMode = comparedImage.mode;
            shown = &comparedImage;
        }
        if (shown) painter.drawImage(programs, *shown, size, frameCamera.far, opts);
        for (auto& f : viewShots) {  // the view as drawn, without the panel
            view::writeWindowScreenshot(f, size);
            say("wrote " + f);
        }

        // Timings in execution order, frame total last.
        std::vector<std::pair<std::string, double>> latest;
        const auto& lat = profiler.latest();
        for (auto& p : renderer.passes())
            if (auto it = lat.find(p->name()); it != lat.end()) latest.emplace_back(p->name(), it->second);
        if (auto it = lat.find("frame"); it != lat.end()) latest.emplace_back("frame", it->second);
        timings.add(latest);

        const std::string title = scene.name + "  " + std::to_string(size.x) + "x" + std::to_string(size.y) +
                                  "  timer=" + profiler.timer() + "  (H: hide panel)";
        Settings before = settings;
        if (ui.build(settings, defaults, state, imgs, timings, live, title)) reconfigure(before, state.message);
        ui.render();
        for (auto& f : windowShots) {
            view::writeWindowScreenshot(f, size);
            say("wrote " + f);
        }

        bool last = automate && int(frame) + 1 >= cl.run.frames;
        if ((screenshot || (last && !screenshotPath.empty())) && shown) {
            // The displayed image at render resolution (as rtgi-bench writes it) and the window with the panel.
            std::string file = last && !screenshotPath.empty() ? screenshotPath
                                                               : "rtgi-view-" + std::to_string(shots++) + ".png";
            view::writeScreenshot(file, *shown, frameCamera.far);
            std::string windowFile = file.substr(0, file.size() - (file.size() > 4 && file.substr(file.size() - 4) == ".png" ? 4 : 0)) + ".window.png";
            view::writeWindowScreenshot(windowFile, size);
            say("wrote " + file + " and " + windowFile);
        }
        host->swapBuffers();
        ++frame;
        if (player) player->advance();
        if (last) break;
    }
    int glErrors = gl::takeDebugErrorCount();
    if (cl.debug && glErrors > 0) std::fprintf(stderr, "rtgi-view: %d GL errors (KHR_debug)\n", glErrors);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const SceneError& e) {
        std::fprintf(stderr, "rtgi-view: %s\n", escapeControl(e.what()).c_str());
        return 3;
    } catch (const ConfigError& e) {
        std::fprintf(stderr, "rtgi-view: %s\n", escapeControl(e.what()).c_str());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rtgi-view: %s\n", escapeControl(e.what()).c_str());
        return 4;
    }
}
