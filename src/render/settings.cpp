#include "render/settings.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

namespace rtgi {
namespace {

[[noreturn]] void bad(const std::string& key, const std::string& value, const std::string& expected) {
    throw ConfigError("setting '" + key + "': '" + value + "' is not valid (expected " + expected + ")");
}

int parseInt(const std::string& key, const std::string& v, int lo, int hi) {
    char* end = nullptr;
    long x = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || x < lo || x > hi)
        bad(key, v, "an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
    return int(x);
}

int parseGeometryStride(const std::string& v) {
    int x = parseInt("lpv.geometry_stride", v, 2, 4);
    if (x == 3) bad("lpv.geometry_stride", v, "2 or 4");
    return x;
}

int parseRayRate(const std::string& v) {
    int x = parseInt("ao.ray_rate", v, 1, 4);
    if (x == 3) bad("ao.ray_rate", v, "1, 2 or 4");
    return x;
}

float parseFloat(const std::string& key, const std::string& v, double lo, double hi) {
    char* end = nullptr;
    double x = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !std::isfinite(x) || x < lo || x > hi) {
        std::ostringstream r;
        r << "a finite number in [" << lo << ", " << hi << "]";
        bad(key, v, r.str());
    }
    return float(x);
}

bool parseBool(const std::string& key, const std::string& v) {
    if (v == "on" || v == "true" || v == "1") return true;
    if (v == "off" || v == "false" || v == "0") return false;
    bad(key, v, "on|off");
}

template <class E, std::size_t N>
E parseEnum(const std::string& key, const std::string& v, const char* const (&names)[N]) {
    for (std::size_t i = 0; i < N; ++i)
        if (v == names[i]) return E(i);
    std::string all;
    for (std::size_t i = 0; i < N; ++i) all += (i ? "|" : "") + std::string(names[i]);
    bad(key, v, all);
}

glm::vec3 parseVec3(const std::string& key, const std::string& v) {
    glm::vec3 r;
    std::string s = v;
    std::replace(s.begin(), s.end(), ',', ' ');
    std::istringstream in(s);
    std::string rest;
    if (!(in >> r.x >> r.y >> r.z) || (in >> rest) || !std::isfinite(r.x) || !std::isfinite(r.y) ||
        !std::isfinite(r.z))
        bad(key, v, "three numbers x,y,z");
    return r;
}

glm::ivec3 parseGrid(const std::string& key, const std::string& v) {
    // "N" or "NxMxK"; each 1..512
    glm::ivec3 g;
    auto one = [&](const std::string& s) { return parseInt(key, s, 1, 512); };
    auto a = v.find('x');
    if (a == std::string::npos) return glm::ivec3(one(v));
    auto b = v.find('x', a + 1);
    if (b == std::string::npos) bad(key, v, "N or NxMxK with 1 <= N <= 512");
    g.x = one(v.substr(0, a));
    g.y = one(v.substr(a + 1, b - a - 1));
    g.z = one(v.substr(b + 1));
    return g;
}

std::string fmt(double x) {
    std::ostringstream o;
    o << x;
    return o.str();
}
std::string fmt3(glm::vec3 v) { return fmt(v.x) + "," + fmt(v.y) + "," + fmt(v.z); }
template <class T>
std::string fmtOpt(const std::optional<T>& o) {
    if (!o) return "auto";
    if constexpr (std::is_same_v<T, glm::vec3>)
        return fmt3(*o);
    else
        return fmt(double(*o));
}
const char* onOff(bool b) { return b ? "on" : "off"; }

const char* const kToggle[] = {"auto", "on", "off"};
const char* const kLpvPath[] = {"compute", "raster"};
const char* const kRasterPath[] = {"hardware", "compute", "auto"};
const char* const kLpvFormat[] = {"rgba16f", "rgba32f"};
const char* const kLpvReemit[] = {"face", "flow"};
const char* const kLpvSource[] = {"propagated", "probe"};
const char* const kLpvLookup[] = {"trilinear", "geometry", "visibility"};
const char* const kLpvInjectSide[] = {"offset", "front"};
const char* const kLpvFirstStep[] = {"free", "blocked"};
const char* const kLpvBlocking[] = {"oriented", "two-sided", "visibility"};
const char* const kLpvReflect[] = {"destination", "source"};
const char* const kLpvSky[] = {"ambient", "visibility"};
const char* const kAoVariant[] = {"off", "ssao-disk", "ssao-sphere", "ssao-hemisphere", "vo", "hbao", "gtao", "vbao", "rtao"};
const char* const kAoThicknessMode[] = {"constant", "depth", "infinite"};
const char* const kAoDirectional[] = {"off", "bent-normals", "s3ho"};
const char* const kAoBentNormals[] = {"slices", "rays"};
const char* const kAoRadiusMode[] = {"fixed",    "dual",     "dynamic1", "dynamic2",
                                     "dynamic3", "dynamic4", "dynamic5", "dynamic6"};
const char* const kAoDepthSource[] = {"camera", "light"};
const char* const kAoDualCombine[] = {"product", "min"};
const char* const kAoFilterChain[] = {"blur-temporal", "blur-temporal-blur"};
const char* const kSsrTracer[] = {"auto", "off", "linear", "dda", "hiz"};
const char* const kReference[] = {"off", "ao", "indirect", "full"};
const char* const kCaustics[] = {"on", "off", "regularized"};
const char* const kResolution[] = {"full", "half"};
const char* const kJointSeparate[] = {"joint", "separate"};
const char* const kFaceCell[] = {"face", "cell"};

template <class T>
std::optional<float> optFloat(const std::string& key, const std::string& v, double lo, double hi) {
    if (v == "auto") return std::nullopt;
    return parseFloat(key, v, lo, hi);
}

#define KEY(name, doc, values, parseBody, showBody)                                              \
    SettingKey {                                                                                 \
        name, doc, values, [](Settings& s, const std::string& v) { parseBody; },                 \
            [](const Settings& s) -> std::string { return showBody; }                            \
    }

std::vector<SettingKey> buildKeys() {
    return {
        // ---- camera --------------------------------------------------------
        KEY("camera.position", "camera position in world units (default: scene camera or framed bounds)", "auto|x,y,z",
            s.camera.position = v == "auto" ? std::nullopt : std::optional(parseVec3("camera.position", v)),
            fmtOpt(s.camera.position)),
        KEY("camera.target", "point the camera looks at", "auto|x,y,z",
            s.camera.target = v == "auto" ? std::nullopt : std::optional(parseVec3("camera.target", v)),
            fmtOpt(s.camera.target)),
        KEY("camera.fov", "vertical field of view in degrees", "auto|0.5..175",
            s.camera.fovDeg = optFloat<float>("camera.fov", v, 0.5, 175), fmtOpt(s.camera.fovDeg)),
        KEY("camera.near", "near plane distance", "auto|1e-6..1e6",
            s.camera.nearPlane = optFloat<float>("camera.near", v, 1e-6, 1e6), fmtOpt(s.camera.nearPlane)),
        KEY("camera.far", "far plane distance", "auto|1e-5..1e9",
            s.camera.farPlane = optFloat<float>("camera.far", v, 1e-5, 1e9), fmtOpt(s.camera.farPlane)),
        KEY("view", "named camera view from benchmarks/views/<scene>.json", "name|\"\"", s.camera.view = v,
            s.camera.view),
        // ---- lights --------------------------------------------------------
        KEY("sun.scale", "multiplier on the scene's sun irradiance", "0..1e12",
            s.light.sunScale = parseFloat("sun.scale", v, 0, 1e12), fmt(s.light.sunScale)),
        KEY("sun.irradiance", "sun irradiance E⊥ (overrides the scene's)", "auto|0..1e12",
            s.light.sunIrradiance = optFloat<float>("sun.irradiance", v, 0, 1e12), fmtOpt(s.light.sunIrradiance)),
        KEY("sun.direction", "direction towards the sun (overrides the scene's)", "auto|x,y,z",
            s.light.sunDirection = v == "auto" ? std::nullopt : std::optional(parseVec3("sun.direction", v)),
            fmtOpt(s.light.sunDirection)),
        KEY("sky", "constant sky radiance (overrides the scene's)", "auto|0..1e12",
            s.light.sky = optFloat<float>("sky", v, 0, 1e12), fmtOpt(s.light.sky)),
        KEY("emissive.scale", "multiplier on emissive materials", "0..1e12",
            s.light.emissiveScale = parseFloat("emissive.scale", v, 0, 1e12), fmt(s.light.emissiveScale)),
        KEY("shadow.size", "sun shadow map side in texels", "16..16384",
            s.light.shadowSize = parseInt("shadow.size", v, 16, 16384), fmt(s.light.shadowSize)),
        KEY("shadow.cache", "redraw the sun's shadow map only when its light frustum or the geometry changed (off: every frame)",
            "on|off", s.light.shadowCache = parseBool("shadow.cache", v), s.light.shadowCache ? "on" : "off"),
        KEY("shadow.local_size", "side of each spot-light shadow map and point/area-light cube face", "16..8192",
            s.light.localShadowSize = parseInt("shadow.local_size", v, 16, 8192), fmt(s.light.localShadowSize)),
        KEY("emissive.lights", "each connected emissive region becomes a shadowed rectangular area light of the real-time path",
            "on|off", s.light.emissiveLights = parseBool("emissive.lights", v), s.light.emissiveLights ? "on" : "off"),
        KEY("light.radius", "source radius of every point/spot light in scene units: PCSS soft shadows sized by it (auto: each light's own, a builtin scene's 'radius'; 0 = punctual, 3x3 PCF)",
            "auto|0..1e4", s.light.lightRadius = optFloat<float>("light.radius", v, 0, 1e4), fmtOpt(s.light.lightRadius)),
        KEY("emissive.max_lights", "emissive regions that become area lights: the brightest by power; the others only emit (a warning says how many and what share of the power)", "0..4096",
            s.light.maxAreaLights = parseInt("emissive.max_lights", v, 0, 4096), fmt(s.light.maxAreaLights)),
        KEY("emissive.split", "each emissive region's rectangle becomes n x n area lights, each with its own cube shadow map and RSM: soft shadows searched from n^2 origins over the panel (auto: 2 while the pieces stay within emissive.max_lights, else 1; docs/lights.md, \"Penumbrae\")", "auto|1..4",
            s.light.emissiveSplit = v == "auto" ? 0 : parseInt("emissive.split", v, 1, 4),
            s.light.emissiveSplit == 0 ? "auto" : fmt(s.light.emissiveSplit)),
        KEY("light.budget", "local-light faces (spot map, cube face) drawn per frame into shadow maps and RSMs, by priority; the rest reuse their cached maps while static; also bounds the local RSMs' injected texels to budget x lpv.rsm^2 (0: every face every frame, no cache)", "0..100000",
            s.light.budget = parseInt("light.budget", v, 0, 100000), fmt(s.light.budget)),
        // ---- rasterization ----------------------------------------------------
        KEY("raster.path", "which rasterizer draws the views: hardware, compute (every view), or auto: the camera G-buffer on compute where 64-bit atomics exist, light views (shadow maps, sun RSM) on the hardware, faster there", "hardware|compute|auto",
            s.raster.path = parseEnum<RasterSettings::Path>("raster.path", v, kRasterPath), kRasterPath[int(s.raster.path)]),
        KEY("raster.atomic64", "compute rasterizer: one 64-bit depth|id atomicMin (auto: where GL_NV_shader_atomic_int64 exists) or the two-pass 32-bit path", "auto|on|off",
            s.raster.atomic64 = parseEnum<Toggle>("raster.atomic64", v, kToggle), kToggle[int(s.raster.atomic64)]),
        KEY("raster.bin_scale", "compute rasterizer: multiplier on the tile-bin capacities (raise when a bin overflows)", "1..64",
            s.raster.binScale = parseInt("raster.bin_scale", v, 1, 64), fmt(s.raster.binScale)),
        KEY("post.exposure", "exposure multiplier before tonemapping", "1e-12..1e12",
            s.post.exposure = parseFloat("post.exposure", v, 1e-12, 1e12), fmt(s.post.exposure)),
        KEY("profile.dispatches", "time every dispatch in its own scope <pass>/<shader> (sub-step costs; adds a timestamp pair per dispatch)",
            "on|off", s.post.profileDispatches = parseBool("profile.dispatches", v), s.post.profileDispatches ? "on" : "off"),
        KEY("passes.off", "comma-separated pass names forced off", "name,name,...", s.post.passesOff = v,
            s.post.passesOff),
        KEY("floor.roughness", "roughness override for the lowest horizontal surface's material", "auto|0..1",
            s.floorRoughness = optFloat<float>("floor.roughness", v, 0, 1), fmtOpt(s.floorRoughness)),
        // ---- LPV -----------------------------------------------------------
        KEY("lpv", "Light Propagation Volumes (auto: on when the scene has a sun)", "auto|on|off",
            s.lpv.mode = parseEnum<Toggle>("lpv", v, kToggle), kToggle[int(s.lpv.mode)]),
        KEY("lpv.path", "compute dispatches or the seed's raster method", "compute|raster",
            s.lpv.path = parseEnum<LpvSettings::Path>("lpv.path", v, kLpvPath), kLpvPath[int(s.lpv.path)]),
        KEY("lpv.grid", "volume resolution", "N|NxMxK (1..512)", s.lpv.grid = parseGrid("lpv.grid", v),
            s.lpv.grid.x == s.lpv.grid.y && s.lpv.grid.y == s.lpv.grid.z
                ? fmt(s.lpv.grid.x)
                : fmt(s.lpv.grid.x) + "x" + fmt(s.lpv.grid.y) + "x" + fmt(s.lpv.grid.z)),
        KEY("lpv.cell", "cell size in scene units (0 = fit the grid to the scene; > 0: camera-following, snapped)", "0|1e-4..1e4",
            s.lpv.cell = parseFloat("lpv.cell", v, 0, 1e4), fmt(s.lpv.cell)),
        KEY("lpv.snap", "camera-following volumes (lpv.cell > 0, or every cascade but a scene-holding coarsest one) "
            "snap their origin to whole cells (off: the origin follows the camera continuously and light shifts "
            "within the cells as it moves; lpv.temporal keeps no history across such a move; docs/lpv.md, \"Snapping\")",
            "on|off", s.lpv.snap = parseBool("lpv.snap", v), onOff(s.lpv.snap)),
        KEY("lpv.iterations", "propagation iterations", "1..64",
            s.lpv.iterations = parseInt("lpv.iterations", v, 1, 64), fmt(s.lpv.iterations)),
        KEY("lpv.coarse_iterations", "propagation iterations of the coarsest of several cascades (0: lpv.iterations; "
            "auto: 16, or 48 in a closed scene; docs/lpv.md, \"Coarse iterations\", \"Closed scenes\")", "auto|0..64",
            (s.lpv.coarseIterationsAuto = v == "auto",
             s.lpv.coarseIterations = v == "auto" ? LpvSettings{}.coarseIterations
                                                  : parseInt("lpv.coarse_iterations", v, 0, 64)),
            s.lpv.coarseIterationsAuto ? "auto" : fmt(s.lpv.coarseIterations)),
        KEY("lpv.closed_escape", "a scene is closed (lpv.coarse_iterations=auto) when less than "
            "this share of the light its surfaces scatter leaves it unblocked (docs/lpv.md, \"Closed scenes\")", "0..1",
            s.lpv.closedEscape = parseFloat("lpv.closed_escape", v, 0, 1), fmt(s.lpv.closedEscape)),
        KEY("lpv.rsm", "reflective shadow map side", "16..4096", s.lpv.rsm = parseInt("lpv.rsm", v, 16, 4096),
            fmt(s.lpv.rsm)),
        KEY("lpv.format", "propagation volume format", "rgba16f|rgba32f",
            s.lpv.format = parseEnum<LpvSettings::Format>("lpv.format", v, kLpvFormat), kLpvFormat[int(s.lpv.format)]),
        KEY("lpv.occlusion", "geometry-volume occlusion during propagation", "on|off",
            s.lpv.occlusion = parseBool("lpv.occlusion", v), onOff(s.lpv.occlusion)),
        KEY("lpv.bounce", "secondary bounce off the geometry volume", "on|off",
            s.lpv.bounce = parseBool("lpv.bounce", v), onOff(s.lpv.bounce)),
        KEY("lpv.specular", "LPV specular (auto: when a material is glossy)", "auto|on|off",
            s.lpv.specular = parseEnum<Toggle>("lpv.specular", v, kToggle), kToggle[int(s.lpv.specular)]),
        KEY("lpv.temporal", "blend factor with the previous volume (0 = off)", "0..0.99",
            s.lpv.temporal = parseFloat("lpv.temporal", v, 0, 0.99), fmt(s.lpv.temporal)),
        KEY("lpv.energy_conserving", "renormalize the propagation so free-space flux is conserved", "on|off",
            s.lpv.energyConserving = parseBool("lpv.energy_conserving", v), onOff(s.lpv.energyConserving)),
        KEY("lpv.reemit", "side faces re-emit around their normal (face, KD10) or their flux direction (flow)",
            "face|flow", s.lpv.reemit = parseEnum<LpvSettings::Reemit>("lpv.reemit", v, kLpvReemit),
            kLpvReemit[int(s.lpv.reemit)]),
        KEY("lpv.lookup", "apply: plain trilinear lookup, or geometry-aware (cells behind the surface or blocked by the "
            "geometry volume get weight 0, renormalized; docs/lpv.md, \"Leaks\"), or visibility (the same side test, "
            "each cell weighted by the Chebyshev bound of its ray-traced distance moments towards the lookup point, "
            "as DDGI; docs/lpv.md, \"Visibility moments\")", "trilinear|geometry|visibility",
            s.lpv.lookup = parseEnum<LpvSettings::Lookup>("lpv.lookup", v, kLpvLookup), kLpvLookup[int(s.lpv.lookup)]),
        KEY("lpv.damping", "apply: damp light that is brighter one cell behind the surface than in front of it "
            "(KD10 derivative damping; docs/lpv.md, \"Leaks\")", "on|off",
            s.lpv.damping = parseBool("lpv.damping", v), onOff(s.lpv.damping)),
        KEY("lpv.inject_side", "injection cell: half a cell along the normal (offset), or also moved until its centre "
            "is on the texel's lit side (front; docs/lpv.md, \"Leaks\")", "offset|front",
            s.lpv.injectSide = parseEnum<LpvSettings::InjectSide>("lpv.inject_side", v, kLpvInjectSide),
            kLpvInjectSide[int(s.lpv.injectSide)]),
        KEY("lpv.blocking", "geometry volume blocking: oriented (surfaces facing the light, KD10 band-1 SH) or two-sided "
            "(the area projected across the flow, either side; docs/lpv.md, \"Leaks\") or visibility (oriented, times the "
            "open fraction of the slab between the two cells' centres, ray-traced per cell and axis; the stopped flux is "
            "reflected into the source cell with lpv.reflect=source; docs/lpv.md, \"Leaks, third pass\"; compute path: "
            "the raster baseline blocks as oriented)", "oriented|two-sided|visibility",
            s.lpv.blocking = parseEnum<LpvSettings::Blocking>("lpv.blocking", v, kLpvBlocking),
            kLpvBlocking[int(s.lpv.blocking)]),
        KEY("lpv.sky", "the sky term inside the volume: ambient (sky radiance times AO everywhere) or visibility "
            "(also times the cosine-weighted fraction of rays from the lookup's cells that leave the scene; "
            "docs/lpv.md, \"Sky visibility\")", "ambient|visibility",
            s.lpv.sky = parseEnum<LpvSettings::Sky>("lpv.sky", v, kLpvSky), kLpvSky[int(s.lpv.sky)]),
        KEY("lpv.sky_bounce", "with lpv.sky=visibility (compute path): inject the sky light reflected by the G-buffer's "
            "surfaces (every lpv.geometry_stride-th pixel) into the volume, as the RSM injects the sun's "
            "(docs/lpv.md, \"Sky bounce\")", "on|off",
            s.lpv.skyBounce = parseBool("lpv.sky_bounce", v), onOff(s.lpv.skyBounce)),
        KEY("lpv.visibility_exponent", "lpv.lookup=visibility: power of each cell's Chebyshev visibility bound before "
            "the weights are renormalized (1 = the bound itself, 3 = DDGI's sharpening; docs/lpv.md, \"Leaks, third pass\")",
            "1..8", s.lpv.visibilityExponent = parseInt("lpv.visibility_exponent", v, 1, 8), fmt(s.lpv.visibilityExponent)),
        KEY("lpv.visibility_view_bias", "lpv.lookup=visibility: cells from the lookup point towards the camera to the point "
            "the cells' distance moments are tested against (0 = the lookup point; docs/lpv.md, \"View bias of the "
            "visibility test\")", "0..2",
            s.lpv.visibilityViewBias = parseFloat("lpv.visibility_view_bias", v, 0, 2), fmt(s.lpv.visibilityViewBias)),
        KEY("lpv.reflect", "lpv.bounce: the reflected flux goes into the cell behind the blocker (destination, seed 3.5.2) "
            "or back into the cell the light came from (source; docs/lpv.md, \"Leaks\")", "destination|source",
            s.lpv.reflect = parseEnum<LpvSettings::Reflect>("lpv.reflect", v, kLpvReflect), kLpvReflect[int(s.lpv.reflect)]),
        KEY("lpv.first_step", "occlusion of the first propagation step: free (seed 3.5.1) or blocked by surfaces facing "
            "the flow (docs/lpv.md, \"Leaks\"); needs lpv.occlusion or lpv.bounce", "free|blocked",
            s.lpv.firstStepBlocked = parseEnum<int>("lpv.first_step", v, kLpvFirstStep) != 0,
            kLpvFirstStep[s.lpv.firstStepBlocked ? 1 : 0]),
        KEY("lpv.self_correction", "subtract the volume's self-illumination of sunlit surfaces (derived, docs/lpv.md)",
            "on|off", s.lpv.selfCorrection = parseBool("lpv.self_correction", v), onOff(s.lpv.selfCorrection)),
        KEY("lpv.cascades", "nested volumes, each cascade's cells twice the previous (compute path)", "1..6",
            s.lpv.cascades = parseInt("lpv.cascades", v, 1, 6), fmt(s.lpv.cascades)),
        KEY("lpv.source", "accumulated volumes from the propagation or from path-traced probes (stage attribution)",
            "propagated|probe", s.lpv.source = parseEnum<LpvSettings::Source>("lpv.source", v, kLpvSource),
            kLpvSource[int(s.lpv.source)]),
        KEY("lpv.probe_directions", "lpv.source=probe: traced directions per cell", "1..65536",
            s.lpv.probeDirections = parseInt("lpv.probe_directions", v, 1, 65536), fmt(s.lpv.probeDirections)),
        KEY("lpv.sh_order", "SH bands of the light volumes: 1 (4 coefficients, the seed's) or 2 (9; compute path)",
            "1|2", s.lpv.shOrder = parseInt("lpv.sh_order", v, 1, 2), fmt(s.lpv.shOrder)),
        KEY("lpv.apply_resolution", "lpv.apply at full resolution, or at half with depth- and normal-aware upsampling "
            "(docs/lpv.md, \"Half-resolution apply\")", "full|half",
            s.lpv.halfApply = parseEnum<int>("lpv.apply_resolution", v, kResolution) == 1,
            s.lpv.halfApply ? "half" : "full"),
        KEY("lpv.fuse", "propagation iterations per dispatch (compute path, band 1; a tile plus halo in shared memory, "
            "docs/lpv.md, \"Fused propagation\")", "1..2",
            s.lpv.fuse = parseInt("lpv.fuse", v, 1, 2), fmt(s.lpv.fuse)),
        KEY("lpv.propagate_kernel", "invocations of an unfused band-1 propagation step: one per cell, neighbour face and "
            "colour (face: 18 per cell, summed in shared memory) or one per cell (cell; docs/lpv.md, \"Per-face "
            "propagation kernel\")", "face|cell",
            s.lpv.faceKernel = parseEnum<int>("lpv.propagate_kernel", v, kFaceCell) == 0,
            s.lpv.faceKernel ? "face" : "cell"),
        KEY("lpv.inject_cache", "keep the local lights' injected light per cascade and re-use it while the lights, their "
            "RSM faces, the geometry and the cascade stay (compute path; docs/lights.md, \"Injection cache\"); off: every "
            "face injected every frame", "on|off",
            s.lpv.injectCache = parseBool("lpv.inject_cache", v), onOff(s.lpv.injectCache)),
        KEY("lpv.sun_cache", "keep the sun's RSM and its packed injection while the sun, the geometry and the cascades "
            "stay and nothing else injects (compute path, band 1; docs/lpv.md, \"Sun injection cache\"); off: drawn "
            "and injected every frame", "on|off",
            s.lpv.sunCache = parseBool("lpv.sun_cache", v), onOff(s.lpv.sunCache)),
        KEY("lpv.propagate_cascades", "cascades of one propagation iteration in one dispatch (joint: a stacked volume, "
            "compute path, band 1, lpv.fuse=1) or one dispatch per cascade (docs/lpv.md, \"Joint cascade propagation\")",
            "joint|separate",
            s.lpv.jointCascades = parseEnum<int>("lpv.propagate_cascades", v, kJointSeparate) == 0,
            s.lpv.jointCascades ? "joint" : "separate"),
        KEY("lpv.geometry_stride", "G-buffer pixel stride in x and y of the geometry injection: 2 (a quarter of the "
            "pixels, seed 5.2.3) or 4 (a sixteenth, each sample standing for 16 pixels; docs/lpv.md, "
            "\"Geometry injection stride\")", "2|4",
            s.lpv.geometryStride = parseGeometryStride(v), fmt(s.lpv.geometryStride)),
        KEY("lpv.strength", "multiplier on LPV indirect light (1 = physical)", "0..1e6",
            s.lpv.strength = parseFloat("lpv.strength", v, 0, 1e6), fmt(s.lpv.strength)),
        // ---- AO ------------------------------------------------------------
        KEY("ao", "AO variant (screen space, or rtao: rays through the scene BVH)",
            "off|ssao-disk|ssao-sphere|ssao-hemisphere|vo|hbao|gtao|vbao|rtao",
            s.ao.variant = parseEnum<AoSettings::Variant>("ao", v, kAoVariant), kAoVariant[int(s.ao.variant)]),
        KEY("ao.samples", "samples per pixel (hbao/gtao: directions x steps, 8->4x2, 16->4x4, 24->6x4)", "1..64",
            s.ao.samples = parseInt("ao.samples", v, 1, 64), fmt(s.ao.samples)),
        KEY("ao.radius", "AO radius in view-space units", "0..1e6", s.ao.radius = parseFloat("ao.radius", v, 0, 1e6),
            fmt(s.ao.radius)),
        KEY("ao.resolution", "AO resolution", "full|half",
            s.ao.halfResolution = parseEnum<int>("ao.resolution", v, kResolution) == 1,
            s.ao.halfResolution ? "half" : "full"),
        KEY("ao.blur", "edge-preserving separable blur", "on|off", s.ao.blur = parseBool("ao.blur", v),
            onOff(s.ao.blur)),
        KEY("ao.temporal", "temporal reprojection filter", "on|off", s.ao.temporal = parseBool("ao.temporal", v),
            onOff(s.ao.temporal)),
        KEY("ao.upsample", "depth-aware upsampling (half resolution)", "on|off",
            s.ao.upsample = parseBool("ao.upsample", v), onOff(s.ao.upsample)),
        KEY("ao.directional", "directional occlusion for the LPV lookup", "off|bent-normals|s3ho",
            s.ao.directional = parseEnum<AoSettings::Directional>("ao.directional", v, kAoDirectional),
            kAoDirectional[int(s.ao.directional)]),
        KEY("ao.bent_normals", "with ao=gtao: bent normals from GTAO's slices (horizons of their own, a sample at distance t counting 1 - t/R) or from ao.samples extra rays",
            "slices|rays", s.ao.sliceBentNormals = parseEnum<int>("ao.bent_normals", v, kAoBentNormals) == 0,
            kAoBentNormals[s.ao.sliceBentNormals ? 0 : 1]),
        KEY("ao.nearfield", "near-field indirect light strength (0 = off; with ao=vbao gathered through the bitmask)", "0..100",
            s.ao.nearfield = parseFloat("ao.nearfield", v, 0, 100), fmt(s.ao.nearfield)),
        KEY("ao.radius_mode", "fixed, dual radii or dynamic radius algorithm 1..6", "fixed|dual|dynamic1..dynamic6",
            s.ao.radiusMode = parseEnum<AoSettings::RadiusMode>("ao.radius_mode", v, kAoRadiusMode),
            kAoRadiusMode[int(s.ao.radiusMode)]),
        KEY("ao.depth_source", "depth used for AO", "camera|light",
            s.ao.depthSource = parseEnum<AoSettings::DepthSource>("ao.depth_source", v, kAoDepthSource),
            kAoDepthSource[int(s.ao.depthSource)]),
        KEY("ao.edge_highlight_removal", "ssao-disk: clip values above 0.5 and scale by 2", "on|off",
            s.ao.removeEdgeHighlight = parseBool("ao.edge_highlight_removal", v), onOff(s.ao.removeEdgeHighlight)),
        KEY("ao.normals", "hbao: use G-buffer normals", "on|off", s.ao.useNormals = parseBool("ao.normals", v),
            onOff(s.ao.useNormals)),
        KEY("ao.angle_bias", "hbao angle bias in degrees", "0..89",
            s.ao.angleBiasDeg = parseFloat("ao.angle_bias", v, 0, 89), fmt(s.ao.angleBiasDeg)),
        KEY("ao.multibounce", "gtao multi-bounce fit", "on|off", s.ao.multiBounce = parseBool("ao.multibounce", v),
            onOff(s.ao.multiBounce)),
        KEY("ao.thickness", "vbao: thickness behind every visible surface (view units; a fraction of the depth with ao.thickness_mode=depth)",
            "1e-6..1e6", s.ao.thickness = parseFloat("ao.thickness", v, 1e-6f, 1e6f), fmt(s.ao.thickness)),
        KEY("ao.thickness_mode", "vbao: constant thickness, depth-scaled (ao.thickness x sample depth) or infinite (GTAO's horizons)",
            "constant|depth|infinite",
            s.ao.thicknessMode = parseEnum<AoSettings::ThicknessMode>("ao.thickness_mode", v, kAoThicknessMode),
            kAoThicknessMode[int(s.ao.thicknessMode)]),
        KEY("ao.second_layer", "vbao: second depth layer (nearest surface ao.thickness behind the first) adds the hidden surface as an occluder; compute raster path only",
            "on|off", s.ao.secondLayer = parseBool("ao.second_layer", v), onOff(s.ao.secondLayer)),
        KEY("ao.rays", "rtao: rays per AO pixel and frame", "1..4", s.ao.rays = parseInt("ao.rays", v, 1, 4),
            fmt(s.ao.rays)),
        KEY("ao.ray_rate", "rtao: one pixel in ray_rate traces per frame (2: checkerboard, 4: one per 2x2 quad, "
            "rotating with the frame); the others take their compatible traced neighbours' value (docs/ao.md, "
            "\"Sparse rays\")", "1|2|4", s.ao.rayRate = parseRayRate(v), fmt(s.ao.rayRate)),
        KEY("ao.probe", "dynamic radius probe size K", "4|9|20|328",
            s.ao.dynamicProbe = parseInt("ao.probe", v, 4, 328);
            if (s.ao.dynamicProbe != 4 && s.ao.dynamicProbe != 9 && s.ao.dynamicProbe != 20 &&
                s.ao.dynamicProbe != 328) bad("ao.probe", v, "4|9|20|328"),
            fmt(s.ao.dynamicProbe)),
        KEY("ao.dual_combine", "dual radii: combine the two AO values by product or min", "product|min",
            s.ao.dualCombineMin = parseEnum<int>("ao.dual_combine", v, kAoDualCombine) == 1,
            s.ao.dualCombineMin ? "min" : "product"),
        KEY("ao.filter_chain", "blur then temporal, or blur -> temporal -> blur ([Wes14]; needs ao.blur and ao.temporal on)",
            "blur-temporal|blur-temporal-blur",
            s.ao.blurAfterTemporal = parseEnum<int>("ao.filter_chain", v, kAoFilterChain) == 1,
            kAoFilterChain[s.ao.blurAfterTemporal ? 1 : 0]),
        // ---- SSR -----------------------------------------------------------
        KEY("ssr", "screen-space reflection tracer (auto: linear when a material is glossy)",
            "auto|off|linear|dda|hiz",
            s.ssr.tracer = parseEnum<SsrSettings::Tracer>("ssr", v, kSsrTracer), kSsrTracer[int(s.ssr.tracer)]),
        KEY("ssr.steps", "maximum ray-march steps", "1..1024", s.ssr.steps = parseInt("ssr.steps", v, 1, 1024),
            fmt(s.ssr.steps)),
        KEY("ssr.thickness", "depth-buffer thickness in view-space units", "0..1e6",
            s.ssr.thickness = parseFloat("ssr.thickness", v, 0, 1e6), fmt(s.ssr.thickness)),
        KEY("ssr.resolution", "SSR trace resolution", "full|half",
            s.ssr.halfResolution = parseEnum<int>("ssr.resolution", v, kResolution) == 1,
            s.ssr.halfResolution ? "half" : "full"),
        KEY("ssr.diffuse_history", "reflect a diffuse-only history (seed 000 6.2.6)", "on|off",
            s.ssr.diffuseHistory = parseBool("ssr.diffuse_history", v), onOff(s.ssr.diffuseHistory)),
        KEY("ssr.roughness_cutoff", "materials rougher than this get no SSR / LPV specular", "0..1",
            s.ssr.roughnessCutoff = parseFloat("ssr.roughness_cutoff", v, 0, 1), fmt(s.ssr.roughnessCutoff)),
        // ---- reference -----------------------------------------------------
        KEY("reference", "in-framework ray-traced reference", "off|ao|indirect|full",
            s.reference.kind = parseEnum<ReferenceSettings::Kind>("reference", v, kReference),
            kReference[int(s.reference.kind)]),
        KEY("reference.spp", "reference samples (rays or paths) per pixel", "1..65536",
            s.reference.spp = parseInt("reference.spp", v, 1, 65536), fmt(s.reference.spp)),
        KEY("reference.bounces", "maximum path length of the path tracer", "1..64",
            s.reference.bounces = parseInt("reference.bounces", v, 1, 64), fmt(s.reference.bounces)),
        KEY("reference.cache", "directory of cached references (off = always render)", "path|off",
            s.reference.cacheDir = v, s.reference.cacheDir),
        KEY("reference.seed", "seed of the reference's sample sequence (same seed, same image)", "0..2147483647",
            s.reference.seed = parseInt("reference.seed", v, 0, 2147483647), fmt(s.reference.seed)),
        KEY("reference.split", "with reference=full: also the error of the direct and of the indirect part (results.json error.split; traces an indirect reference too)", "on|off",
            s.reference.split = parseBool("reference.split", v), s.reference.split ? "on" : "off"),
        KEY("reference.specular", "GGX lobe in the path tracer (off: Lambert only)", "on|off",
            s.reference.specular = parseBool("reference.specular", v), s.reference.specular ? "on" : "off"),
        KEY("reference.light_sampling",
            "next-event estimation of emissive triangles, MIS with BRDF sampling (off: emitters found by BRDF rays only)",
            "on|off", s.reference.lightSampling = parseBool("reference.light_sampling", v),
            s.reference.lightSampling ? "on" : "off"),
        KEY("reference.caustics",
            "caustic paths (camera, diffuse, glossy, light): on as they are, off removed, regularized (roughened)",
            "on|off|regularized",
            s.reference.caustics = parseEnum<ReferenceSettings::Caustics>("reference.caustics", v, kCaustics),
            kCaustics[int(s.reference.caustics)]),
        KEY("reference.caustic_roughness",
            "roughness floor of glossy vertices after a diffuse one (caustics=regularized; the lobe test of off)",
            "0.01..1",
            s.reference.causticRoughness = parseFloat("reference.caustic_roughness", v, 0.01, 1),
            fmt(s.reference.causticRoughness)),
        KEY("reference.target_noise",
            "trace until the reference's RMS standard error is at most this fraction of the compared error (0 = off)",
            "0..1", s.reference.targetNoise = parseFloat("reference.target_noise", v, 0, 1),
            fmt(s.reference.targetNoise)),
        KEY("reference.target_stderr",
            "trace until the reference's RMS standard error is at most this value (0 = off; with target_noise: the looser)",
            "0..1e6", s.reference.targetStderr = parseFloat("reference.target_stderr", v, 0, 1e6),
            fmt(s.reference.targetStderr)),
        KEY("reference.time_budget", "seconds a converging reference may trace (0 = no limit)", "0..1e6",
            s.reference.timeBudget = parseFloat("reference.time_budget", v, 0, 1e6), fmt(s.reference.timeBudget)),
        KEY("reference.max_spp", "most samples per pixel a converging reference traces", "1..16777216",
            s.reference.maxSpp = parseInt("reference.max_spp", v, 1, 16777216), fmt(s.reference.maxSpp)),
    };
}

}  // namespace

std::string defaultReferenceCacheDir() {
    // XDG: an unset or empty XDG_CACHE_HOME (or a relative one, which the
    // spec says to ignore) means $HOME/.cache.
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg && *xdg == '/') return std::string(xdg) + "/rtgi";
    const char* home = std::getenv("HOME");
    if (home && *home) return std::string(home) + "/.cache/rtgi";
    return "rtgi-cache";
}

const char* toString(Toggle t) { return kToggle[int(t)]; }
const char* toString(AoSettings::Variant v) { return kAoVariant[int(v)]; }
const char* toString(SsrSettings::Tracer t) { return kSsrTracer[int(t)]; }
const char* toString(RasterSettings::Path p) { return kRasterPath[int(p)]; }

std::string settingDefault(const SettingKey& key) {
    std::string v = key.show(Settings{});
    return v.empty() ? "\"\"" : v;
}

const std::vector<SettingKey>& settingKeys() {
    static const std::vector<SettingKey> keys = buildKeys();
    return keys;
}

void applySetting(Settings& s, const std::string& key, const std::string& value) {
    for (auto& k : settingKeys())
        if (k.key == key) {
            k.parse(s, value);
            return;
        }
    // Suggest the closest key by common prefix (users mistype families).
    std::string hint;
    std::size_t best = 0;
    for (auto& k : settingKeys()) {
        std::size_t n = 0;
        while (n < k.key.size() && n < key.size() && k.key[n] == key[n]) ++n;
        if (n > best) {
            best = n;
            hint = k.key;
        }
    }
    throw ConfigError("unknown setting '" + key + "'" + (best >= 2 ? " (did you mean '" + hint + "'?)" : "") +
                      "; rtgi-bench --help lists every key");
}

void applyAssignment(Settings& s, const std::string& a) {
    auto eq = a.find('=');
    if (eq == std::string::npos || eq == 0)
        throw ConfigError("--set '" + a + "': expected key=value");
    applySetting(s, a.substr(0, eq), a.substr(eq + 1));
}

std::map<std::string, std::string> describe(const Settings& s) {
    std::map<std::string, std::string> m;
    for (auto& k : settingKeys()) m[k.key] = k.show(s);
    return m;
}

std::string jsonErrorText(const std::exception& e) {
    std::string w = e.what();
    if (w.rfind("[json.exception.", 0) == 0) {
        auto close = w.find("] ");
        if (close != std::string::npos) w = w.substr(close + 2);
    }
    return w;
}

std::string jsonTypeWord(const nlohmann::json& v) {
    if (v.is_string()) return "a string";
    if (v.is_boolean()) return "a boolean";
    if (v.is_number()) return "a number";
    if (v.is_array()) return "an array";
    if (v.is_object()) return "an object";
    return "null";
}

Assignments flattenJsonConfig(const std::string& text, const std::string& source) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const std::exception& e) {
        throw ConfigError(source + ": not valid JSON (" + jsonErrorText(e) + ")");
    }
    if (!j.is_object()) throw ConfigError(source + ": the configuration must be a JSON object");
    // Nested objects are flattened into dotted keys; "lpv": {"grid": 32}
    // means lpv.grid, and "lpv": "on" sets the family key itself.
    Assignments out;
    std::set<std::string> given;  // {"lpv": {"cascades": 6}} and "lpv.cascades": 1 name the same key
    std::function<void(const nlohmann::json&, const std::string&)> walk = [&](const nlohmann::json& o,
                                                                             const std::string& prefix) {
        for (auto it = o.begin(); it != o.end(); ++it) {
            std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
            const auto& v = it.value();
            std::string str;
            if (v.is_object()) {
                walk(v, key);
                continue;
            } else if (v.is_string()) {
                str = v.get<std::string>();
            } else if (v.is_boolean()) {
                str = v.get<bool>() ? "on" : "off";
            } else if (v.is_number_integer()) {
                str = std::to_string(v.get<long long>());
            } else if (v.is_number()) {
                std::ostringstream o2;
                o2.precision(9);
                o2 << v.get<double>();
                str = o2.str();
            } else if (v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number()) {
                str = fmt(v[0].get<double>()) + "," + fmt(v[1].get<double>()) + "," + fmt(v[2].get<double>());
            } else {
                throw ConfigError(source + ": value of '" + key + "' must be a string, number, boolean or [x,y,z]");
            }
            if (!given.insert(key).second)
                throw ConfigError(source + ": '" + key + "' is given twice (nested and dotted); give it once");
            out.emplace_back(key, str);
        }
    };
    walk(j, "");
    return out;
}

void applyJsonConfig(Settings& s, const std::string& text, const std::string& source) {
    for (auto& [k, v] : flattenJsonConfig(text, source)) {
        try {
            applySetting(s, k, v);
        } catch (const ConfigError& e) {
            throw ConfigError(source + ": " + e.what());
        }
    }
}

Settings effectiveSettings(const Assignments& sceneSuggestions, const Assignments& explicitAssignments,
                           const std::string& sceneName) {
    Settings s;
    for (auto& [k, v] : sceneSuggestions) {
        try {
            applySetting(s, k, v);
        } catch (const ConfigError& e) {
            throw ConfigError(sceneName + ": suggested settings: " + e.what());
        }
    }
    for (auto& [k, v] : explicitAssignments) applySetting(s, k, v);
    // The raster baseline has no traced face openness: it blocks as oriented, and the settings it reports
    // (results.json's config) say so.
    if (s.lpv.path == LpvSettings::Path::Raster && s.lpv.blocking == LpvSettings::Blocking::Visibility)
        s.lpv.blocking = LpvSettings::Blocking::Oriented;
    // Slice bent normals exist only where GTAO writes bent normals from one fixed radius; elsewhere the AO pass
    // samples rays (src/render/ao/ao_passes.cpp), and the reported settings say so.
    if (s.ao.sliceBentNormals &&
        (s.ao.variant != AoSettings::Variant::Gtao || s.ao.directional != AoSettings::Directional::BentNormals ||
         s.ao.radiusMode == AoSettings::RadiusMode::Dual))
        s.ao.sliceBentNormals = false;
    return s;
}

}  // namespace rtgi
