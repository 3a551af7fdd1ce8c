#pragma once
// User-facing settings (SPEC section 12): typed, with ranges and defaults,
// parsed from --set key=value, --config FILE.json and sweep files through one
// key table (settings.cpp). Unknown keys and bad values are errors naming the
// key. GPU constant blocks are derived from these by pure functions in each
// pass family, never read from here inside shaders.
#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rtgi {

class ConfigError : public std::runtime_error {
    using std::runtime_error::runtime_error;
};

enum class Toggle { Auto, On, Off };

struct CameraSettings {
    std::optional<glm::vec3> position, target;  // unset: scene camera or default
    std::optional<float> fovDeg, nearPlane, farPlane;
    std::string view;  // named view from benchmarks/views/<scene>.json ("" = none)
};

struct LightSettings {
    float sunScale = 1.0f;              // multiplies the scene's sun irradiance
    std::optional<float> sunIrradiance; // overrides it
    std::optional<glm::vec3> sunDirection;  // direction towards the sun (overrides)
    std::optional<float> sky;           // constant sky radiance override
    float emissiveScale = 1.0f;
    int shadowSize = 2048;
    bool shadowCache = true;  // redraw the sun's map only when its frustum or the geometry changed
    // Side of each spot light's shadow map and of each cube face of a point /
    // area light (6 per light); 16 point lights at 2048² would need 1.6 GB.
    int localShadowSize = 512;
    bool emissiveLights = true;  // emissive regions become area lights of the real-time path
    std::optional<float> lightRadius;  // source radius of every point/spot light (overrides the scene's)
    // Emissive regions that become area lights: the brightest by power; the
    // others are left out with a warning (issue 28: an emissive texture of
    // many islands became 120 lights = 720 shadow faces + 720 RSMs).
    int maxAreaLights = 32;
    // Each emissive region's rectangle is cut into split × split area lights
    // (0: auto, 2 while the pieces stay within maxAreaLights, else 1), each
    // with its own cube shadow map and RSM: the penumbrae are searched from
    // split² origins over the panel instead of its centre alone.
    int emissiveSplit = 0;
    // Local-light faces (a spot map or a cube face) drawn per frame into the
    // shadow maps and, with the LPV, into the RSMs; the others keep their
    // cached maps while their light and the scene are static (docs/lights.md
    // "Light budget"). It also bounds the LPV injection of local lights: their
    // RSM side is halved until all faces hold at most budget x lpv.rsm²
    // texels. 0: every face every frame, no cache, full-size RSMs.
    int budget = 48;
};

struct PostSettings {
    float exposure = 1.0f;
    std::string passesOff;  // comma-separated pass names forced off
    bool profileDispatches = false;  // a timer scope per dispatch ("<pass>/<shader>")
};

struct LpvSettings {
    Toggle mode = Toggle::Auto;          // auto: on when the scene has a sun
    enum class Path { Compute, Raster } path = Path::Compute;
    // Per cascade; 16 since the fifth leak pass (docs/lpv.md, "Fifth pass": chosen with the face openness
    // on the GI suite's minimum gain; the cascades' table of docs/lpv.md measured 24 with the older blocking).
    glm::ivec3 grid{16};
    float cell = 0.0f;                   // 0 = fit the grid to the scene bounds (auto, docs/lpv.md)
    // Camera-following volumes snap their origin to whole cells (seed 000 3.7); off: the origin follows the
    // camera continuously, so light shifts within the cells as the camera moves (docs/lpv.md, "Snapping").
    bool snap = true;
    int iterations = 8;
    // Steps of the coarsest of several cascades (0: lpv.iterations); its near part stays lpv.iterations'
    // (the finer cascade's reach). 16: the coarse cascade crosses the fitted scene (14 usable cells at 16^3),
    // chosen on the GI suite's minimum gain (docs/lpv.md, "Coarse iterations").
    int coarseIterations = 16;
    // lpv.coarse_iterations=auto (the default): coarseIterations above is the open scene's value; a renderer
    // whose scene is closed (measureEnclosure's escaped share of scattered light under closedEscape) uses
    // kClosedCoarseIterations instead (docs/lpv.md, "Closed scenes").
    bool coarseIterationsAuto = true;
    float closedEscape = 0.3f;
    static constexpr int kClosedCoarseIterations = 48;
    int rsm = 256;
    enum class Format { Rgba16f, Rgba32f } format = Format::Rgba16f;
    bool occlusion = true;
    bool bounce = true;
    Toggle specular = Toggle::Auto;
    float temporal = 0.0f;               // blend factor with the previous volume, 0 = off
    bool energyConserving = true;        // measured lower error on cornell and the atrium (docs/lpv.md)
    float strength = 1.0f;               // global multiplier on LPV indirect light (1 = physical)
    // Side faces of a propagation step re-emit around their normal (KD10) or
    // around the mean direction of the flux crossing them (docs/lpv.md).
    enum class Reemit { Face, Flow } reemit = Reemit::Flow;
    bool selfCorrection = true;          // subtract the scheme's self-illumination of lit surfaces (docs/lpv.md)
    int cascades = 2;                    // nested camera-following volumes, cell doubling per cascade (docs/lpv.md)
    // Stage attribution (docs/lpv.md): the accumulated volumes come from the
    // propagation or from path-traced probes at the cell centres.
    enum class Source { Propagated, Probe } source = Source::Propagated;
    int probeDirections = 256;           // lpv.source=probe: traced directions per cell
    int shOrder = 1;                     // SH bands of the light volumes: 1 (4 coefficients, the seed's) or 2 (9)
    // Leak remedies (issue 22, docs/lpv.md "Leaks"; defaults chosen there on the worst view's gain).
    enum class Lookup { Trilinear, Geometry, Visibility } lookup = Lookup::Visibility;
    bool damping = false;                // KD10 derivative damping of the lookup (darkens cornell's far half: docs/lpv.md)
    enum class InjectSide { Offset, Front } injectSide = InjectSide::Front;
    bool firstStepBlocked = true;        // geometry occlusion also in the first propagation step
    // visibility: oriented times the traced face openness (docs/lpv.md, "Leaks, third pass"); the default since
    // the fifth pass with lpv.grid=16 (the raster baseline keeps the oriented blocking).
    enum class Blocking { Oriented, TwoSided, Visibility } blocking = Blocking::Visibility;
    enum class Reflect { Destination, Source } reflect = Reflect::Source;  // where lpv.bounce puts the reflection
    // Compose's sky term: uniform ambient times AO, or also times the cells' ray-traced sky visibility.
    enum class Sky { Ambient, Visibility } sky = Sky::Visibility;
    // With lpv.sky=visibility (compute path): the sky light reflected by the surfaces the camera sees is
    // injected into the volume like an RSM's (docs/lpv.md, "Sky bounce").
    bool skyBounce = false;
    // lpv.lookup=visibility: each cell's Chebyshev bound is raised to this power (DDGI's 3; docs/lpv.md).
    int visibilityExponent = 3;
    // lpv.lookup=visibility: the point the moments are tested against lies this many cells from the lookup
    // point towards the camera (DDGI's view bias; docs/lpv.md, "View bias of the visibility test").
    float visibilityViewBias = 0.35f;
    // lpv.apply at half resolution with joint bilateral upsampling (docs/lpv.md, "Half-resolution apply").
    bool halfApply = true;
    // Propagation iterations per dispatch (docs/lpv.md, "Fused propagation"): 1 = one dispatch per iteration.
    int fuse = 1;
    // lpv.propagate_kernel=face: one invocation per cell, neighbour face and colour (docs/lpv.md,
    // "Per-face propagation kernel"); off (cell): one per cell. Unfused band-1 steps of one cascade.
    bool faceKernel = true;
    // Local lights' injection kept per cascade while nothing it depends on changed (docs/lights.md, "Injection cache").
    bool injectCache = true;
    // lpv.sun_cache: the sun's RSM and its packed injection kept while the sun, the geometry and the
    // cascades stay and nothing else injects (docs/lpv.md, "Sun injection cache").
    bool sunCache = true;
    bool jointCascades = false;  // lpv.propagate_cascades=joint: the cascades of an iteration in one dispatch (2.2x slower on an H100)
    int geometryStride = 4;     // lpv.geometry_stride: G-buffer pixel stride (x and y) of the geometry injection
};

struct AoSettings {
    // Default: GTAO, the lowest error against ray-traced AO in every scene
    // (docs/RESULTS.md, ao-samples / ao-resolution), at half resolution
    // (atrium 1280x720: RMSE 11.1 % vs 11.0 % at full resolution, 0.115 ms vs 0.282 ms on the H200).
    enum class Variant { Off, SsaoDisk, SsaoSphere, SsaoHemisphere, Vo, Hbao, Gtao, Vbao, Rtao } variant = Variant::Gtao;
    int samples = 16;
    float radius = 0.5f;       // view-space units
    bool halfResolution = true;
    bool blur = true;
    bool temporal = true;
    bool upsample = true;
    // Default: bent normals for the LPV lookup (seed 000 5.3), the seeds' system.
    enum class Directional { Off, BentNormals, S3ho } directional = Directional::BentNormals;
    // ao.bent_normals=slices: with ao=gtao, the bent normal is the cosine-weighted mean visible direction of GTAO's
    // own slices (horizons of its own that a sample at distance t raises by the share 1 - t/R, no extra samples;
    // docs/ao.md "Bent normals from the slices"); rays: the
    // ray-sampled point visibility of every other variant.
    bool sliceBentNormals = true;
    float nearfield = 0.0f;    // strength, 0 = off
    enum class RadiusMode { Fixed, Dual, Dynamic1, Dynamic2, Dynamic3, Dynamic4, Dynamic5, Dynamic6 } radiusMode =
        RadiusMode::Fixed;
    enum class DepthSource { Camera, Light } depthSource = DepthSource::Camera;
    bool removeEdgeHighlight = true;  // ssao-disk
    bool useNormals = true;           // hbao with/without normals
    float angleBiasDeg = 30.0f;       // hbao
    bool multiBounce = false;         // gtao
    // vbao: thickness of every visible surface behind it (docs/ao.md "Visibility bitmask"); the
    // default is the lowest worst-case RMSE on the training views (docs/ao.md "Tuning protocol").
    enum class ThicknessMode { Constant, Depth, Infinite } thicknessMode = ThicknessMode::Depth;
    float thickness = 0.08f;          // view units (constant) or a fraction of the sample's depth (depth)
    // vbao: a second depth layer (visibility.layer2, compute raster path) adds hidden surfaces (docs/ao.md "Second depth layer").
    bool secondLayer = false;
    int rays = 2;                     // rtao: rays per AO pixel and frame
    int rayRate = 1;                  // rtao: 1 in rayRate pixels traces per frame (1, 2, 4; docs/ao.md "Sparse rays")
    int dynamicProbe = 9;             // K of the dynamic radius probe: 4, 9, 20, 328
    bool dualCombineMin = false;      // dual radii: min instead of product (Loos & Sloan)
    bool blurAfterTemporal = false;   // ao.filter_chain=blur-temporal-blur ([Wes14])
};

struct SsrSettings {
    enum class Tracer { Auto, Off, Linear, Dda, Hiz } tracer = Tracer::Auto;
    int steps = 64;
    float thickness = 0.2f;
    bool halfResolution = true;
    bool diffuseHistory = false;
    float roughnessCutoff = 0.5f;  // materials rougher than this get no SSR
};

// $XDG_CACHE_HOME/rtgi, else $HOME/.cache/rtgi (XDG Base Directory spec),
// else ./rtgi-cache when neither variable is set (docs/reference.md).
std::string defaultReferenceCacheDir();

struct ReferenceSettings {
    enum class Kind { Off, Ao, Indirect, Full } kind = Kind::Off;
    int spp = 256;
    int bounces = 4;
    std::string cacheDir = defaultReferenceCacheDir();  // "off" = no cache
    int seed = 1;                         // fixed seed of the sample sequence
    bool specular = true;                 // off: Lambert lobe only (furnace tests, diffuse-only comparisons)
    bool lightSampling = true;            // next-event estimation of emissive triangles with MIS (off: BRDF sampling only)
    bool split = false;                   // full reference: also the direct and indirect parts' errors (error.split)
    // Caustic paths (camera → diffuse → glossy → light, docs/reference.md):
    // kept as they are (on), removed (off) or path-space regularized.
    enum class Caustics { On, Off, Regularized } caustics = Caustics::Regularized;
    float causticRoughness = 0.3f;        // regularized: roughness floor after a diffuse vertex; the lobe test of off
    // Convergence to a noise target (docs/reference.md, "Converging"): 0 = off
    // (exactly `spp` samples). targetNoise is relative to the error the
    // reference is compared with (RMS standard error <= targetNoise × the
    // debiased RMSE), targetStderr absolute; the run stops at the looser of
    // the two, at timeBudget seconds or at maxSpp samples.
    double targetNoise = 0;
    double targetStderr = 0;
    double timeBudget = 300;
    int maxSpp = 65536;
    bool converging() const { return targetNoise > 0 || targetStderr > 0; }
};

// Visibility: hardware rasterization or the compute rasterizer (docs/visibility.md).
struct RasterSettings {
    // auto: compute where GL_NV_shader_atomic_int64 exists (NVIDIA), hardware elsewhere (llvmpipe)
    enum class Path { Hardware, Compute, Auto } path = Path::Auto;
    Toggle atomic64 = Toggle::Auto;  // 64-bit depth|id atomicMin (auto: where GL_NV_shader_atomic_int64 exists)
    int binScale = 1;                // multiplier on the compute rasterizer's bin capacities
};

struct Settings {
    CameraSettings camera;
    RasterSettings raster;
    LightSettings light;
    PostSettings post;
    LpvSettings lpv;
    AoSettings ao;
    SsrSettings ssr;
    ReferenceSettings reference;
    std::optional<float> floorRoughness;  // override for the material of the lowest surface (SSR benchmarks)
};

// One entry of the key table.
struct SettingKey {
    std::string key;
    std::string doc;      // one line, with the range / allowed values
    std::string values;   // "auto|on|off", "1..64", ...
    void (*parse)(Settings&, const std::string&);
    std::string (*show)(const Settings&);
};

const std::vector<SettingKey>& settingKeys();
// The key's value in a default-constructed Settings, as --set takes it ("" shown as "\"\"").
std::string settingDefault(const SettingKey& key);
// nlohmann's exception text without its "[json.exception.parse_error.101] "
// prefix (messages name the file; the library's ids mean nothing to a user).
std::string jsonErrorText(const std::exception& e);
// A JSON value's type in words ("a string", "an array", ...) for messages such
// as "expected a number, found a string" (sweep files, glTF schema).
std::string jsonTypeWord(const nlohmann::json& v);

// Applies key=value; throws ConfigError("--set KEY: ...") for unknown keys / bad values.
void applySetting(Settings& s, const std::string& key, const std::string& value);
// "key=value" form.
void applyAssignment(Settings& s, const std::string& assignment);
// Every key with its effective value (results.json "config").
std::map<std::string, std::string> describe(const Settings& s);
// A JSON object of key -> value (strings, numbers or bools) or nested objects
// whose dotted paths are keys; `source` names the file for errors.
void applyJsonConfig(Settings& s, const std::string& jsonText, const std::string& source);

using Assignments = std::vector<std::pair<std::string, std::string>>;
// The (key, value) pairs of a JSON configuration, in file order (same rules
// as applyJsonConfig; errors name `source`).
Assignments flattenJsonConfig(const std::string& jsonText, const std::string& source);
// Defaults, then the scene's suggested settings, then the explicit
// assignments (config files, --set, sweep axes) in order.
Settings effectiveSettings(const Assignments& sceneSuggestions, const Assignments& explicitAssignments,
                           const std::string& sceneName);

const char* toString(Toggle t);
const char* toString(RasterSettings::Path p);
const char* toString(AoSettings::Variant v);
const char* toString(SsrSettings::Tracer t);

}  // namespace rtgi
