// rtgi-view: a window on the same renderer as rtgi-bench (GLFW; docs/viewer.md).
#include "app/cli.h"
#include "gl/program.h"
#include "gl/window_host.h"
#include "render/renderer.h"
#include "view/controls.h"
#include "view/display.h"
#include "view/fly_camera.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

using namespace rtgi;

namespace {

std::string fmtMs(double ms) {
    char b[32];
    std::snprintf(b, sizeof b, "%7.3f", ms);
    return b;
}

// One line per family with the keys the viewer steps through.
std::vector<std::string> configLines(const Settings& s) {
    auto d = describe(s);
    return {"lpv=" + d["lpv"] + " path=" + d["lpv.path"] + " grid=" + d["lpv.grid"] + " it=" + d["lpv.iterations"],
            "ao=" + d["ao"] + " samples=" + d["ao.samples"] + " radius=" + d["ao.radius"] + " res=" + d["ao.resolution"] +
                " dir=" + d["ao.directional"],
            "ssr=" + d["ssr"] + " steps=" + d["ssr.steps"] + "   reference=" + d["reference"]};
}

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
    const std::string screenshotPath = cl.screenshot;
    bool vsync = cl.vsync;
    const bool automate = cl.framesGiven || !screenshotPath.empty();

    Scene scene = loadScenes(cl.run.scenes);
    for (auto& w : scene.warnings) std::fprintf(stderr, "rtgi-view: warning: %s\n", w.c_str());
    auto host = gl::WindowHost::create(cl.run.resolution, "rtgi-view: " + scene.name, cl.debug, vsync && !automate);
    gl::Profiler profiler(host->info().timerQuery);
    Settings settings = settingsFor(scene, cl);
    Renderer renderer(scene, settings, profiler);
    gl::ProgramCache& programs = renderer.programs();
    view::ScreenPainter painter;
    view::SmoothedTimings timings;

    const Camera sceneCamera = resolveCamera(scene, settings);
    const float diagonal = glm::length(scene.bounds().extent());
    Camera camera = sceneCamera;  // used as is until the user flies, so --frames matches rtgi-bench exactly
    view::FlyCamera fly = view::FlyCamera::fromCamera(camera, diagonal);
    const std::vector<std::string> views = namedViews(scene);
    int viewIndex = -1;

    std::vector<std::pair<int, int>> keys;
    host->onKey = [&](int k, int mods) { keys.emplace_back(k, mods); };
    bool help = false, cut = true;
    std::string imageName = "final", message;
    int frameMessage = 0;
    View prev;
    unsigned frame = 0;
    glm::dvec2 lastCursor = host->cursor();
    auto lastTime = std::chrono::steady_clock::now();
    int shots = 0;

    while (!host->shouldClose()) {
        host->pollEvents();
        auto now = std::chrono::steady_clock::now();
        float dt = std::min(std::chrono::duration<float>(now - lastTime).count(), 0.1f);
        lastTime = now;
        auto say = [&](const std::string& m) {
            message = m;
            frameMessage = int(frame);
            std::fprintf(stderr, "rtgi-view: %s\n", m.c_str());
        };

        bool screenshot = false;
        for (auto [k, mods] : keys) {
            Settings before = settings;
            view::KeyAction a = view::handleKey(k, mods, settings);
            if (a.reconfigure) {
                try {
                    renderer.configure(settings);
                    say(a.message);
                } catch (const ConfigError& e) {
                    settings = before;  // e.g. a technique this scene cannot run: say why, keep the old frame
                    renderer.configure(settings);
                    say(e.what());
                }
                cut = true;
            }
            if (a.quit) host->requestClose();
            if (a.toggleHelp) help = !help;
            if (a.toggleVsync) {
                vsync = !vsync;
                host->setVsync(vsync);
                say(std::string("vsync ") + (vsync ? "on" : "off"));
            }
            if (a.finalImage) imageName = "final";
            if (a.imageStep != 0) {
                auto imgs = view::displayImages(renderer);
                int n = int(imgs.size()), cur = 0;
                for (int i = 0; i < n; ++i)
                    if (imgs[std::size_t(i)].name == imageName) cur = i;
                if (n > 0) imageName = imgs[std::size_t((cur + a.imageStep + n) % n)].name;
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
            // Mouse look while the right button is held; WASD/QE movement.
            glm::dvec2 c = host->cursor();
            bool flew = false;
            if (host->mouseButtonDown(1)) {
                fly.look(float(c.x - lastCursor.x), float(c.y - lastCursor.y), 0.003f);
                flew = c != lastCursor;
            }
            lastCursor = c;
            glm::vec3 axes(0.0f);
            if (host->keyDown(GLFW_KEY_W)) axes.z += 1;
            if (host->keyDown(GLFW_KEY_S)) axes.z -= 1;
            if (host->keyDown(GLFW_KEY_D)) axes.x += 1;
            if (host->keyDown(GLFW_KEY_A)) axes.x -= 1;
            if (host->keyDown(GLFW_KEY_E)) axes.y += 1;
            if (host->keyDown(GLFW_KEY_Q)) axes.y -= 1;
            if (axes != glm::vec3(0.0f)) {
                fly.move(axes, dt, host->keyDown(GLFW_KEY_LEFT_SHIFT) || host->keyDown(GLFW_KEY_RIGHT_SHIFT));
                flew = true;
            }
            if (flew) camera = fly.toCamera();
        }

        glm::ivec2 size = host->framebufferSize();
        if (size.x <= 0 || size.y <= 0) continue;  // minimized
        if (size != prev.size) cut = true;          // resized: histories do not match
        View v = makeView(camera, size, cut ? nullptr : &prev, frame);
        renderer.render(v);
        prev = v;
        cut = false;

        auto imgs = view::displayImages(renderer);
        const view::DisplayImage* shown = imgs.empty() ? nullptr : &imgs.front();
        for (auto& im : imgs)
            if (im.name == imageName) shown = &im;
        if (shown) painter.drawImage(programs, *shown, size, camera.far);

        // Overlay: timings in frame order, smoothed.
        std::vector<std::pair<std::string, double>> latest;
        const auto& lat = profiler.latest();
        for (auto& p : renderer.passes())
            if (auto it = lat.find(p->name()); it != lat.end()) latest.emplace_back(p->name(), it->second);
        if (auto it = lat.find("frame"); it != lat.end()) latest.emplace_back("frame", it->second);
        timings.add(latest);
        std::vector<std::string> lines = {scene.name + "  " + std::to_string(size.x) + "x" + std::to_string(size.y) +
                                              "  timer=" + profiler.timer() + "  image: " +
                                              (shown ? shown->name : std::string("-")) + "   (H: keys)"};
        for (auto& l : configLines(settings)) lines.push_back(l);
        for (auto& [name, ms] : timings.values()) lines.push_back(fmtMs(ms) + " ms  " + name);
        if (!message.empty() && int(frame) - frameMessage < 300) lines.push_back(message);
        if (help)
            for (auto& l : view::keyHelp()) lines.push_back(l);
        painter.drawText(programs, size, lines, size.y >= 900 ? 2.0f : 1.0f);

        bool last = automate && int(frame) + 1 >= cl.run.frames;
        if ((screenshot || (last && !screenshotPath.empty())) && shown) {
            // The displayed image at render resolution (as rtgi-bench writes it) and the window with the overlay.
            std::string file = last && !screenshotPath.empty() ? screenshotPath
                                                               : "rtgi-view-" + std::to_string(shots++) + ".png";
            view::writeScreenshot(file, *shown, camera.far);
            std::string windowFile = file.substr(0, file.size() - (file.size() > 4 && file.substr(file.size() - 4) == ".png" ? 4 : 0)) + ".window.png";
            view::writeWindowScreenshot(windowFile, size);
            say("wrote " + file + " and " + windowFile);
        }
        host->swapBuffers();
        ++frame;
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
        std::fprintf(stderr, "rtgi-view: %s\n", e.what());
        return 3;
    } catch (const ConfigError& e) {
        std::fprintf(stderr, "rtgi-view: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rtgi-view: %s\n", e.what());
        return 4;
    }
}
