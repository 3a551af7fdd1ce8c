// SSR against analytic scenes: a mirror floor in front of an emissive wall
// (reflected colour and hit positions from a CPU ray cast of the mirrored
// ray), misses, tracer agreement, the Hi-Z pyramid against a CPU min over
// each cell's footprint, pruning, and robustness (--check counts).
#include "gpu_fixture.h"

#include "bench/reference_compare.h"
#include "render/ssr/ssr_constants.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

using namespace rtgi;
using namespace rtgi::test;

namespace {

const glm::vec3 kWallEmission(0.8f, 0.3f, 0.1f);
constexpr double kWallZ = -3.0, kWallHalfWidth = 1.5, kWallHeight = 4.0;

// Mirror floor (roughness 0, metallic 1, white: F0 = 1, no diffuse) of
// half-size 10 at y = 0, and a black emissive wall at z = -3, x in
// [-1.5, 1.5], y in [0, 4], facing the camera. Sky radiance 0, no lights:
// the wall's radiance is exactly its emission.
Scene mirrorScene() {
    Scene s;
    s.name = "test:mirror";
    Material floor;
    floor.baseColor = glm::vec4(1.0f);
    floor.metallic = 1.0f;
    floor.roughness = 0.0f;
    Material wall;
    wall.baseColor = glm::vec4(0, 0, 0, 1);
    wall.roughness = 1.0f;
    wall.emissive = kWallEmission;
    s.materials = {floor, wall};
    addQuad(s, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, {-10, 0, -10}, 0);
    float w = float(kWallHalfWidth), z = float(kWallZ), h = float(kWallHeight);
    addQuad(s, {-w, 0, z}, {w, 0, z}, {w, h, z}, {-w, h, z}, 1);
    s.sky = glm::vec3(0.0f);
    Camera c;
    c.position = {0, 1, 2};
    c.target = {0, 1, -3};
    c.fovY = glm::radians(60.0f);
    c.near = 0.1f;
    c.far = 50.0f;
    s.cameras.push_back(c);
    return s;
}

// CPU ray cast (double) of full-resolution pixel (x, y): the camera ray hits
// the floor at P, the mirrored ray continues to the wall plane at H.
struct MirrorRay {
    bool floor = false;   // the pixel sees the floor
    bool wall = false;    // the mirrored ray hits the wall (inside `margin` of its edges)
    bool nearWall = false;// ... or passes within `margin` of it (ambiguous: not tested)
    glm::dvec2 hitPixel;  // H projected to full-resolution pixel coordinates
};

MirrorRay castMirror(const Camera& c, glm::ivec2 size, double px, double py, double margin) {
    MirrorRay m;
    glm::dvec3 eye(c.position), f = glm::normalize(glm::dvec3(c.target) - eye);
    glm::dvec3 r = glm::normalize(glm::cross(f, glm::dvec3(0, 1, 0))), u = glm::cross(r, f);
    double t = std::tan(0.5 * double(c.fovY)), aspect = double(size.x) / size.y;
    double nx = px / size.x * 2 - 1, ny = py / size.y * 2 - 1;
    glm::dvec3 d = f + r * (nx * t * aspect) + u * (ny * t);
    if (d.y >= 0) return m;
    glm::dvec3 p = eye + d * (-eye.y / d.y);
    if (p.z < kWallZ || std::abs(p.x) > 10) return m;  // behind the wall or off the floor
    m.floor = true;
    glm::dvec3 dr(d.x, -d.y, d.z);
    if (dr.z >= 0) return m;
    glm::dvec3 h = p + dr * ((kWallZ - p.z) / dr.z);
    bool inside = std::abs(h.x) < kWallHalfWidth - margin && h.y > margin && h.y < kWallHeight - margin;
    bool outside = std::abs(h.x) > kWallHalfWidth + margin || h.y > kWallHeight + margin;
    m.wall = inside;
    m.nearWall = !inside && !outside;
    glm::dvec3 q = h - eye;
    double vz = glm::dot(q, f);
    m.hitPixel = {(glm::dot(q, r) / (vz * t * aspect) * 0.5 + 0.5) * size.x,
                  (glm::dot(q, u) / (vz * t) * 0.5 + 0.5) * size.y};
    return m;
}

const DebugImage* findDebug(const std::vector<DebugImage>& v, const std::string& n) {
    for (auto& d : v)
        if (d.name == n) return &d;
    return nullptr;
}

struct TraceResult {
    FloatImage hit, confidence, specular;
};

TraceResult runMirror(SsrSettings::Tracer tracer, glm::ivec2 size, int steps) {
    gl::Profiler prof(false);
    Scene s = mirrorScene();
    Settings st;
    st.ssr.tracer = tracer;
    st.ssr.steps = steps;
    // 3 frames: frame 0 has no history; frame 1 resolves; frame 2 blends equal values.
    auto r = renderFrames(s, st, size, prof, 3);
    Pass* trace = r->findPass("ssr.trace");
    REQUIRE(trace);
    auto dbg = r->debugImages(*trace);
    TraceResult out;
    out.hit = readTexture(*findDebug(dbg, "ssr.trace.hit_offset")->tex);
    out.confidence = readTexture(*findDebug(dbg, "ssr.trace.hit_mask")->tex);
    out.specular = readTexture(r->resources().specular);
    return out;
}

std::string tracerName(SsrSettings::Tracer t) { return toString(t); }

// The reason a pass was skipped ("" when it ran or is unknown).
std::string skipReason(const Renderer& r, const std::string& pass) {
    for (auto& k : r.skipped())
        if (k.name == pass) return k.reason;
    return "";
}

}  // namespace

TEST_CASE("SSR on a mirror floor reflects the wall where the mirrored ray hits it, for every tracer") {
    GpuFixture gpu;
    const glm::ivec2 size(64, 64), traceSize = ssrTraceSize(size, true);
    const Camera cam = resolveCamera(mirrorScene(), Settings{});
    std::vector<std::vector<glm::dvec2>> hits;
    for (auto tracer : {SsrSettings::Tracer::Linear, SsrSettings::Tracer::Dda, SsrSettings::Tracer::Hiz}) {
        INFO("tracer " << tracerName(tracer));
        TraceResult res = runMirror(tracer, size, 256);
        std::vector<glm::dvec2> found;
        int hitChecked = 0, missChecked = 0, colourChecked = 0;
        for (int ty = 0; ty < traceSize.y; ++ty)
            for (int tx = 0; tx < traceSize.x; ++tx) {
                // The trace pixel sits on full-resolution pixel (2tx, 2ty).
                double px = 2 * tx + 0.5, py = 2 * ty + 0.5;
                MirrorRay m = castMirror(cam, size, px, py, 0.2);
                INFO("trace pixel " << tx << "," << ty);
                if (!m.floor || m.nearWall) {
                    found.emplace_back(-1, -1);
                    continue;
                }
                float c = res.confidence.at(tx, ty, 0);
                if (!m.wall) {
                    INFO("hit at " << px + res.hit.at(tx, ty, 0) * size.x << "," << py + res.hit.at(tx, ty, 1) * size.y);
                    CHECK(c == 0.0f);  // the mirrored ray leaves the screen / passes the wall: a miss
                    ++missChecked;
                    found.emplace_back(-1, -1);
                    continue;
                }
                glm::dvec2 pix(px + res.hit.at(tx, ty, 0) * size.x, py + res.hit.at(tx, ty, 1) * size.y);
                found.push_back(c > 0 ? pix : glm::dvec2(-1, -1));
                // Hit positions of an edge-faded pixel still hold; the wall is inside the screen here.
                CHECK(c > 0.0f);
                // One pixel: the hit is the first depth sample crossing the wall, which may
                // lie anywhere inside the wall's pixel column/row crossed by the ray.
                CHECK(std::abs(pix.x - m.hitPixel.x) < 1.0);
                CHECK(std::abs(pix.y - m.hitPixel.y) < 1.0);
                ++hitChecked;
            }
        hits.push_back(found);
        CHECK(hitChecked > 40);
        CHECK(missChecked > 20);
        // Final specular at full resolution where the whole filter footprint
        // (blur radius 4 trace pixels = 8 full pixels, + bilinear) reflects the
        // wall's interior, away from screen-edge fades: F0 = 1 and roughness 0
        // make the split-sum factor A + B = 1 up to the LUT's Smith term at
        // alpha = 1e-3 (< 1 %); tolerance 5 % for fp16 storage, the LUT and the
        // temporal blend of two identical frames.
        for (int y = 0; y < size.y; y += 3)
            for (int x = 0; x < size.x; x += 3) {
                bool all = true;
                for (int dy = -10; dy <= 10 && all; dy += 2)
                    for (int dx = -10; dx <= 10 && all; dx += 2) {
                        MirrorRay m = castMirror(cam, size, x + 0.5 + dx, y + 0.5 + dy, 0.2);
                        all = m.floor && m.wall && m.hitPixel.x > 0.12 * size.x && m.hitPixel.x < 0.88 * size.x &&
                              m.hitPixel.y > 0.12 * size.y && m.hitPixel.y < 0.88 * size.y;
                    }
                if (!all) continue;
                INFO("pixel " << x << "," << y);
                for (int ch = 0; ch < 3; ++ch)
                    CHECK(res.specular.at(x, y, ch) == doctest::Approx(kWallEmission[ch]).epsilon(0.05));
                ++colourChecked;
            }
        CHECK(colourChecked > 5);
    }
    // linear, DDA and Hi-Z agree within one pixel where all three hit (the
    // linear tracer's 256 steps + bisection are finer than a pixel here).
    int agreed = 0;
    for (std::size_t i = 0; i < hits[0].size(); ++i) {
        if (hits[0][i].x < 0 || hits[1][i].x < 0 || hits[2][i].x < 0) continue;
        for (int k : {1, 2}) {
            CHECK(std::abs(hits[0][i].x - hits[k][i].x) <= 1.0);
            CHECK(std::abs(hits[0][i].y - hits[k][i].y) <= 1.0);
        }
        ++agreed;
    }
    CHECK(agreed > 40);
}

TEST_CASE("SSR Hi-Z pyramid equals a CPU min over each cell's footprint (odd sizes)") {
    GpuFixture gpu;
    for (glm::ivec2 size : {glm::ivec2(45, 29), glm::ivec2(32, 17)}) {
        INFO("size " << size.x << "x" << size.y);
        gl::Profiler prof(false);
        Scene s = mirrorScene();
        Settings st;
        st.ssr.tracer = SsrSettings::Tracer::Hiz;
        st.camera.target = glm::vec3(0.3f, 1.5f, -3.0f);  // sky in the top rows
        auto r = renderFrames(s, st, size, prof, 1);
        FloatImage depth = readTexture(r->resources().gbuffer.linearDepth);
        const Pass* hizPass = r->findPass("ssr.hiz");
        REQUIRE(hizPass);
        const gl::Texture& hiz = *r->debugImages(*hizPass).front().tex;
        const double far = resolveCamera(s, st).far;
        int levels = hizLevelCount(size);
        CHECK(levels == int(std::floor(std::log2(std::max(size.x, size.y)))) + 1);
        bool sawSky = false;
        for (int l = 0; l < levels; ++l) {
            glm::ivec2 ls = hizLevelSize(size, l);
            std::vector<float> gpuLevel(std::size_t(ls.x * ls.y));
            glGetTextureImage(hiz.id(), l, GL_RED, GL_FLOAT, GLsizei(gpuLevel.size() * sizeof(float)),
                              gpuLevel.data());
            for (int y = 0; y < ls.y; ++y)
                for (int x = 0; x < ls.x; ++x) {
                    // Footprint of cell (x, y): pixels [x 2^l, (x+1) 2^l), the last cell up to the edge.
                    int x0 = x << l, y0 = y << l;
                    int x1 = x == ls.x - 1 ? size.x : (x + 1) << l, y1 = y == ls.y - 1 ? size.y : (y + 1) << l;
                    double m = 1e300;
                    for (int yy = y0; yy < y1; ++yy)
                        for (int xx = x0; xx < x1; ++xx) {
                            double d = depth.at(xx, yy, 0);
                            if (!(d > 0)) {
                                d = far;  // sky sits at the far plane
                                sawSky = true;
                            }
                            m = std::min(m, d);
                        }
                    INFO("level " << l << " cell " << x << "," << y);
                    CHECK(double(gpuLevel[std::size_t(y * ls.x + x)]) == doctest::Approx(m).epsilon(1e-6));
                }
        }
        CHECK(sawSky);
    }
}

TEST_CASE("SSR pruning: rough scenes skip every ssr pass and ssr=off allocates nothing") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    Scene rough = floorScene(5, glm::vec3(0.5f), false);  // roughness 1 only (like builtin:cornell)
    auto r = renderFrames(rough, Settings{}, {16, 16}, prof, 1);
    for (auto& p : r->passes()) CHECK(p->name().rfind("ssr.", 0) != 0);
    int skipped = 0;
    for (auto& k : r->skipped())
        if (k.name.rfind("ssr.", 0) == 0) {
            CHECK(k.reason.find("glossy") != std::string::npos);
            ++skipped;
        }
    CHECK(skipped >= 5);
    for (auto& [name, bytes] : r->ledger().entries()) CHECK(name.rfind("ssr.", 0) != 0);
    CHECK_FALSE(r->resources().brdfLut);
    // post.history runs only while a pass of the frame reads the previous frame's radiance
    // (derived from the declarations: neither ssr.resolve nor ao.nearfield is in this frame).
    CHECK(skipReason(*r, "post.history").find("no pass in this frame reads history") != std::string::npos);

    // floor.roughness makes the same scene glossy: auto runs the linear tracer.
    Settings glossy;
    glossy.floorRoughness = 0.1f;
    auto g = renderFrames(rough, glossy, {16, 16}, prof, 1);
    CHECK(g->findPass("ssr.trace"));
    CHECK(g->findPass("ssr.shade"));
    CHECK_FALSE(g->findPass("ssr.hiz"));  // only the hiz tracer needs the pyramid
    CHECK_FALSE(g->findPass("ssr.upsample"));  // half resolution: ssr.shade upsamples (no pass of its own)
    CHECK(g->findPass("post.history"));    // ssr.resolve reads the previous frame
    CHECK(g->resources().brdfLut);
    CHECK(g->resources().blueNoise);       // the linear tracer's start jitter

    // The diffuse-only history replaces post.history; full resolution needs no upsampling.
    Settings diffuse = glossy;
    diffuse.ssr.diffuseHistory = true;
    diffuse.ssr.halfResolution = false;
    auto d = renderFrames(rough, diffuse, {16, 16}, prof, 1);
    CHECK(d->findPass("ssr.diffuse_history"));
    CHECK_FALSE(d->findPass("post.history"));
    // ssr.resolve declares readPrevious(diffuseHistory) instead, so nothing reads post.history's output.
    CHECK(skipReason(*d, "post.history").find("no pass in this frame reads history") != std::string::npos);

    glossy.ssr.tracer = SsrSettings::Tracer::Off;
    auto o = renderFrames(rough, glossy, {16, 16}, prof, 1);
    for (auto& [name, bytes] : o->ledger().entries()) CHECK(name.rfind("ssr.", 0) != 0);
    CHECK_FALSE(o->resources().specularOcclusion);
    CHECK(skipReason(*o, "post.history").find("no pass in this frame reads history") != std::string::npos);
}

TEST_CASE("SSR never writes NaN/Inf: grazing view, zero thickness, every tracer, diffuse history") {
    GpuFixture gpu;
    for (auto tracer : {SsrSettings::Tracer::Linear, SsrSettings::Tracer::Dda, SsrSettings::Tracer::Hiz}) {
        INFO("tracer " << tracerName(tracer));
        gl::Profiler prof(false);
        Scene s = mirrorScene();
        s.cameras[0].position = {0.0f, 0.02f, 2.0f};  // grazing: the floor seen at ~0.2 degrees
        Settings st;
        st.ssr.tracer = tracer;
        st.ssr.thickness = 0.0f;
        st.ssr.diffuseHistory = tracer == SsrSettings::Tracer::Dda;
        Renderer r(s, st, prof);
        r.setCheck(true);
        Camera cam = resolveCamera(s, st);
        View prev;
        for (int f = 0; f < 3; ++f) {
            View v = makeView(cam, {24, 24}, f == 0 ? nullptr : &prev, unsigned(f));
            r.render(v);
            prev = v;
        }
        int checked = 0;
        for (auto& fc : r.finiteCounts()) {
            INFO(fc.pass << " " << fc.resource);
            CHECK(fc.nan == 0u);
            CHECK(fc.inf == 0u);
            CHECK(fc.negative == 0u);
            if (fc.pass.rfind("ssr.", 0) == 0) ++checked;
        }
        CHECK(checked >= 6);
    }
}

TEST_CASE("--reference reports the SSR error over the glossy pixels (the mirror floor) beside the whole image") {
    GpuFixture gpu;
    gl::Profiler prof(false);
    const glm::ivec2 size(16, 16);
    Scene s = mirrorScene();
    Settings st;
    st.ssr.tracer = SsrSettings::Tracer::Linear;
    st.ao.variant = AoSettings::Variant::Off;  // with AO on, --reference compares the AO instead
    st.reference.spp = 4;  // only the pixel sets are checked, not the converged values
    st.reference.bounces = 1;
    st.reference.cacheDir = "off";
    // The emissive wall is an area light (docs/lights.md), so lpv=auto would
    // run the LPV and --reference would compare its indirect term instead.
    st.lpv.mode = Toggle::Off;
    auto r = renderFrames(s, st, size, prof, 2);
    const Camera cam = resolveCamera(s, st);
    nlohmann::json e = compareWithReference(*r, cam, size, "", false);
    REQUIRE(e.contains("glossy"));
    // The glossy pixels are those whose centre ray sees the mirror floor first
    // (CPU ray cast in double against the floor and the wall); pixels whose
    // centre ray passes within 0.05 pixel of an edge may go either way in the
    // rasterizer.
    auto seesFloor = [&](double px, double py) {
        glm::dvec3 eye(cam.position), f = glm::normalize(glm::dvec3(cam.target) - eye);
        glm::dvec3 rt = glm::normalize(glm::cross(f, glm::dvec3(0, 1, 0))), up = glm::cross(rt, f);
        double t = std::tan(0.5 * double(cam.fovY)), aspect = double(size.x) / size.y;
        glm::dvec3 d = f + rt * ((px / size.x * 2 - 1) * t * aspect) + up * ((py / size.y * 2 - 1) * t);
        if (d.y >= 0) return false;
        double tFloor = -eye.y / d.y;
        glm::dvec3 p = eye + d * tFloor;
        if (std::abs(p.x) > 10 || std::abs(p.z) > 10) return false;
        double tWall = (kWallZ - eye.z) / d.z;  // the wall hides the floor behind it
        glm::dvec3 w = eye + d * tWall;
        return !(tWall > 0 && tWall < tFloor && std::abs(w.x) <= kWallHalfWidth && w.y >= 0 && w.y <= kWallHeight);
    };
    int sure = 0, maybe = 0;
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
            bool c = seesFloor(x + 0.5, y + 0.5);
            bool any = false, all = true;
            for (double d : {-0.05, 0.05})
                for (double d2 : {-0.05, 0.05}) {
                    bool f = seesFloor(x + 0.5 + d, y + 0.5 + d2);
                    any |= f;
                    all &= f;
                }
            sure += c && all;
            maybe += any && !all;
        }
    const int glossy = e["glossy"]["pixels"].get<int>();
    CHECK(glossy >= sure);
    CHECK(glossy <= sure + maybe);
    CHECK(glossy < e["pixels"].get<int>());  // the wall is geometry but not glossy
    CHECK_FALSE(e["glossy"].contains("ssim"));
    for (const char* k : {"rmse", "mae", "bias", "rel_rmse"}) CHECK(std::isfinite(e["glossy"][k].get<double>()));
}
