#include "render/reference/reference_cache.h"

#include "gl/input_files.h"
#include "gl/output_files.h"
#include "render/gpu_scene.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rtgi {
namespace {

// FNV-1a, 64 bit: stable across runs and platforms of the same endianness.
struct Hasher {
    std::uint64_t h = 1469598103934665603ull;
    void bytes(const void* p, std::size_t n) {
        auto* b = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
    }
    template <class T>
    void pod(const T& v) { bytes(&v, sizeof(T)); }
    template <class T>
    void vec(const std::vector<T>& v) {
        pod(v.size());
        if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
    }
    void str(const std::string& s) {
        pod(s.size());
        bytes(s.data(), s.size());
    }
};

}  // namespace

std::string referenceCacheKey(const Scene& scene, const Settings& settings, const ReferenceConstants& c,
                              const View& view) {
    Hasher h;
    // Bump when the estimator changes. v4: G-buffer origins cover the interpolation error, running moments,
    // caustics modes; v5: single-sided emitters (glTF doubleSided); v6: the watertight ray/triangle test and
    // conservative box test (bvh.glsl): v5 references can have pixels whose rays slipped through a shared edge
    // (builtin:cornell 96x54 had a black one on an H200), and a cached one would keep serving them; v7: the first
    // vertex is the pixel-centre ray's BVH hit (bvh.glsl gbufferFirstVertex): v6 references can have crease pixels
    // whose G-buffer point lay behind the other wall, so their paths and AO rays started outside the room.
    h.str("rtgi-reference-v7");
    h.str(scene.name);
    h.vec(scene.vertices);
    h.vec(scene.indices);
    for (auto& d : scene.draws) h.pod(d);
    for (auto& m : resolveMaterials(scene, settings)) {
        h.pod(m.baseColor);
        h.pod(m.metallic);
        h.pod(m.roughness);
        h.pod(m.emissive);
        h.pod(m.doubleSided);
        h.pod(m.baseColorTexture);
    }
    for (auto& img : scene.images) h.vec(img.rgba);
    for (auto& l : scene.lights) {
        h.pod(l.type);
        h.pod(l.color);
        h.pod(l.intensity);
        h.pod(l.position);
        h.pod(l.direction);
        h.pod(l.range);
        h.pod(l.innerCone);
        h.pod(l.outerCone);
    }
    if (auto sun = resolveSun(scene, settings)) {
        h.pod(sun->towardSun);
        h.pod(sun->irradiance);
    }
    h.pod(resolveSky(scene, settings));
    h.pod(view.size);
    h.pod(view.view);
    h.pod(view.proj);
    h.str(referenceSettingsJson(c).dump());
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h.h));
    return buf;
}

nlohmann::json referenceSettingsJson(const ReferenceConstants& c) {
    static const char* kinds[] = {"off", "ao", "indirect", "full"};
    static const char* caustics[] = {"on", "off", "regularized"};
    nlohmann::json j = {{"reference", kinds[int(c.kind)]}, {"seed", c.seed}};
    // A converging reference's spp is what it took (results.json
    // error.reference.spp), not a setting: the cache key leaves it out so a
    // later run can resume the entry.
    if (c.converging) j["converging"] = true;
    else j["spp"] = c.spp;
    if (c.kind == ReferenceSettings::Kind::Ao) j["ray_length"] = c.rayLength;
    else {
        j["bounces"] = c.bounces;
        j["specular"] = !c.diffuseOnly;
        j["light_sampling"] = c.lightSampling;
        if (!c.diffuseOnly) {
            j["caustics"] = caustics[int(c.caustics)];
            if (c.caustics != ReferenceSettings::Caustics::On) j["caustic_roughness"] = c.causticRoughness;
        }
        if (c.kind == ReferenceSettings::Kind::Indirect) j["emission_is_direct"] = c.emissionIsDirect;
    }
    return j;
}

std::optional<CachedReference> loadCachedReference(const std::string& dir, const std::string& key) {
    if (dir == "off") return std::nullopt;
    namespace fs = std::filesystem;
    fs::path base = fs::path(dir) / key;
    fs::path mean = base.string() + ".mean.pfm", se = base.string() + ".stderr.pfm", info = base.string() + ".json";
    if (!fs::exists(mean) || !fs::exists(se) || !fs::exists(info)) return std::nullopt;
    try {
        CachedReference r;
        r.mean = readPfm(mean.string());
        r.standardError = readPfm(se.string());
        r.info = nlohmann::json::parse(readInputFile(info.string(), InputKind::Config));
        return r;
    } catch (const std::exception&) {
        return std::nullopt;  // a damaged entry is traced again and overwritten
    }
}

void storeCachedReference(const std::string& dir, const std::string& key, const CachedReference& r) {
    if (dir == "off") return;
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw ConfigError("setting 'reference.cache': cannot create directory '" + dir + "' (" + ec.message() + ")");
    std::string base = (fs::path(dir) / key).string();
    writePfm(base + ".mean.pfm", r.mean);
    writePfm(base + ".stderr.pfm", r.standardError);
    writeFileAtomic(base + ".json", r.info.dump(2) + "\n");
}

}  // namespace rtgi
