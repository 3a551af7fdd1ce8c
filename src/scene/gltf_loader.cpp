// glTF 2.0 loader (.gltf and .glb) on top of tinygltf.
//
// tinygltf parses the JSON and loads buffers; everything it does not check
// (or checks only with asserts) is checked here before it is used: the GLB
// container, external files, every index into the model's arrays, and the
// byte ranges of accessors, bufferViews and buffers. Images are not decoded
// by tinygltf (its loader would read image bufferViews without a bounds
// check); base-colour images are decoded here with stb_image after their
// bytes have been validated. Every problem becomes one SceneError sentence
// that starts with the file path.
#include "gl/input_files.h"
#include "scene/gltf_schema.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>
#include <stb_image.h>
// Same configuration as src/scene/tinygltf_impl.cpp (the class layout and its
// inline constructor depend on it).
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rtgi {
namespace {

namespace fs = std::filesystem;

constexpr double kMaxTriangles = 1e8;
constexpr double kMaxVertices = 3e8;  // 3 per triangle at most, and far below 2^32
constexpr double kMaxNodeInstances = 1e7;
constexpr int kMaxJsonDepth = 256;
constexpr int kMaxImageSide = 16384;
// World-space coordinates (vertices, lights, cameras) must stay within this
// bound: distances, bounds diagonals and the far plane (1000x the scene size
// when a camera has no zfar) are computed in float, and (2e15)^2 * 3 * 1e6 is
// still far below FLT_MAX (3.4e38); 1e38 itself overflows when squared.
constexpr double kMaxCoordinate = 1e15;

// Light colour x intensity and emission are bounded by kMaxRadiance
// (scene.h); their products with areas and the settings' multipliers are
// checked by checkRadiometricRange (render/lights.h) before the first frame.

// A number that the GPU receives as a float: finite and within float range.
bool floatFinite(double v) { return std::isfinite(v) && std::abs(v) <= double(FLT_MAX); }
std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

constexpr std::string_view kSupportedRequired[] = {
    "KHR_materials_emissive_strength", "KHR_lights_punctual", "KHR_texture_transform"};

std::string str(std::size_t v) { return std::to_string(v); }
std::string str(int v) { return std::to_string(v); }

// File-system callbacks for tinygltf: no path expansion, no directories, no
// unbounded reads, no writes.
bool fsFileExists(const std::string& p, void*) { return inputFileProblem(p, InputKind::SceneData).empty(); }
std::string fsExpandFilePath(const std::string& p, void*) { return p; }
bool fsReadWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& p, void*) {
    std::string why;
    if (readInputBytes(p, InputKind::SceneData, *out, why)) return true;
    if (err) *err += escapeControl(p) + ": " + why + "\n";
    return false;
}
bool fsWriteWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "writing files is disabled\n";
    return false;
}

// Image callback: keep the encoded bytes of URI images for later; ignore the
// bytes tinygltf hands over for bufferView images (not bounds-checked there).
bool deferImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                const unsigned char* bytes, int size, void*) {
    if (image->bufferView != -1) return true;
    if (bytes == nullptr || size <= 0) return false;
    image->image.assign(bytes, bytes + size);
    image->as_is = true;
    return true;
}

std::string percentDecode(const std::string& s) {
    auto hex = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return -1;
    };
    std::string out;
    out.reserve(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '%' && i + 2 < s.size() && hex(s[i + 1]) >= 0 && hex(s[i + 2]) >= 0) {
            out.push_back(char(hex(s[i + 1]) * 16 + hex(s[i + 2])));
            i += 2;
        } else {
            out.push_back(s[i]);
        }
    }
    return out;
}

// Deepest nesting of {} / [] outside strings (tinygltf parses extras
// recursively, so absurd nesting must not reach it).
int jsonDepth(std::string_view text) {
    int depth = 0, maxDepth = 0;
    bool inString = false, escape = false;
    for (char c : text) {
        if (inString) {
            if (escape)
                escape = false;
            else if (c == '\\')
                escape = true;
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '{' || c == '[') {
            maxDepth = std::max(maxDepth, ++depth);
        } else if (c == '}' || c == ']') {
            --depth;
        }
    }
    return maxDepth;
}

// Text from the file may be anything: control characters and invalid bytes
// are escaped (gl/input_files.h), so that messages stay one printable line
// (and can be written into JSON results).
std::string printable(const std::string& s) { return escapeControl(s); }

// Makes one line out of tinygltf's newline-separated messages.
std::string oneLine(const std::string& s, std::size_t maxLen = 300) {
    std::string out;
    for (char c : s) {
        if (c == '\n' || c == '\r') {
            while (!out.empty() && (out.back() == '.' || out.back() == ' ')) out.pop_back();
            if (!out.empty() && out.back() != ';') out += "; ";
        } else {
            out.push_back(c);
        }
    }
    while (!out.empty() && (out.back() == ' ' || out.back() == ';' || out.back() == '.')) out.pop_back();
    if (out.size() > maxLen) out = out.substr(0, maxLen) + "...";
    return out;
}

std::uint32_t readU32(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}

const char* componentName(int ct) {
    switch (ct) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: return "i8";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "u8";
        case TINYGLTF_COMPONENT_TYPE_SHORT: return "i16";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "u16";
        case TINYGLTF_COMPONENT_TYPE_INT: return "i32";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "u32";
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return "float";
        default: return "unknown-component";
    }
}
std::size_t componentSize(int ct) {
    switch (ct) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;  // INT and DOUBLE are not valid in glTF 2.0
    }
}
const char* typeName(int t) {
    switch (t) {
        case TINYGLTF_TYPE_SCALAR: return "SCALAR";
        case TINYGLTF_TYPE_VEC2: return "VEC2";
        case TINYGLTF_TYPE_VEC3: return "VEC3";
        case TINYGLTF_TYPE_VEC4: return "VEC4";
        case TINYGLTF_TYPE_MAT2: return "MAT2";
        case TINYGLTF_TYPE_MAT3: return "MAT3";
        case TINYGLTF_TYPE_MAT4: return "MAT4";
        default: return "unknown-type";
    }
}
std::size_t typeComponents(int t) {
    switch (t) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4:
        case TINYGLTF_TYPE_MAT2: return 4;
        case TINYGLTF_TYPE_MAT3: return 9;
        case TINYGLTF_TYPE_MAT4: return 16;
        default: return 0;
    }
}
const char* modeName(int mode) {
    switch (mode) {
        case TINYGLTF_MODE_POINTS: return "points";
        case TINYGLTF_MODE_LINE: return "lines";
        case TINYGLTF_MODE_LINE_LOOP: return "line loops";
        case TINYGLTF_MODE_LINE_STRIP: return "line strips";
        case TINYGLTF_MODE_TRIANGLE_STRIP: return "triangle strips";
        case TINYGLTF_MODE_TRIANGLE_FAN: return "triangle fans";
        default: return "unknown modes";
    }
}

bool allFinite(const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

// Number-valued member of an extension object, if present.
std::optional<double> extensionNumber(const tinygltf::ExtensionMap& ext, const char* extension, const char* key) {
    auto it = ext.find(extension);
    if (it == ext.end() || !it->second.IsObject() || !it->second.Has(key)) return std::nullopt;
    const tinygltf::Value& v = it->second.Get(key);
    if (!v.IsNumber()) return std::nullopt;
    return v.GetNumberAsDouble();
}

// A validated accessor: `count` elements, element i at data + i*stride.
struct AccessorData {
    const unsigned char* data = nullptr;
    std::size_t stride = 0, count = 0;
    int componentType = 0, type = 0;
    bool normalized = false;

    float component(std::size_t i, std::size_t c) const {
        const unsigned char* p = data + i * stride + c * componentSize(componentType);
        switch (componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: {
                float f;
                std::memcpy(&f, p, 4);
                return f;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? float(*p) / 255.0f : float(*p);
            case TINYGLTF_COMPONENT_TYPE_BYTE: {
                auto v = float(std::int8_t(*p));
                return normalized ? std::max(v / 127.0f, -1.0f) : v;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                std::uint16_t u;
                std::memcpy(&u, p, 2);
                return normalized ? float(u) / 65535.0f : float(u);
            }
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                std::int16_t s;
                std::memcpy(&s, p, 2);
                return normalized ? std::max(float(s) / 32767.0f, -1.0f) : float(s);
            }
            default: {
                std::uint32_t u;
                std::memcpy(&u, p, 4);
                return float(u);
            }
        }
    }
    std::uint32_t index(std::size_t i) const {
        const unsigned char* p = data + i * stride;
        switch (componentType) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                std::uint16_t u;
                std::memcpy(&u, p, 2);
                return u;
            }
            default: {
                std::uint32_t u;
                std::memcpy(&u, p, 4);
                return u;
            }
        }
    }
};

// One primitive decoded in its mesh's local space (shared by all instances).
struct LocalPrimitive {
    bool skipped = false;
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> uvs;
    std::vector<std::uint32_t> indices;
    int material = -1;  // glTF material index, -1 = default
};

// Cofactor matrix of the upper 3x3 (= det · inverse-transpose): transforms
// normals and stays finite for singular matrices.
glm::dmat3 cofactor(const glm::dmat3& m) {
    return glm::dmat3(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
}

class GltfLoader {
public:
    explicit GltfLoader(std::string path) : path_(std::move(path)) {}

    Scene load() {
        try {
            return loadImpl();
        } catch (const SceneError&) {
            throw;
        } catch (const std::bad_alloc&) {
            fail("ran out of memory while loading");
        } catch (const std::length_error&) {
            fail("ran out of memory while loading");
        }
    }

private:
    std::string path_, baseDir_;
    std::vector<unsigned char> file_;
    bool binary_ = false;
    std::size_t glbLength_ = 0, glbBinLength_ = 0;
    bool glbHasBin_ = false;
    std::string_view json_;
    tinygltf::Model model_;
    Scene scene_;
    std::vector<std::optional<LocalPrimitive>> primCache_;  // per mesh, per primitive
    std::vector<std::size_t> primCacheOffset_;
    std::map<int, int> imageSlots_;
    int defaultMaterial_ = -1;
    std::map<std::string, std::size_t> skippedModes_;
    std::size_t truncatedIndexLists_ = 0, badUvs_ = 0;
    struct PendingCamera {
        std::size_t index;
        double znear, zfar;
    };
    std::vector<PendingCamera> pendingCameras_;
    // Node animations (issue 23): per glTF node and AnimatedProperty, the
    // index of its track in scene_.animation.tracks (-1: not animated).
    std::vector<std::array<int, 3>> nodeTracks_;
    int currentAnimNode_ = -1;  // the AnimatedNode being walked (-1: the file has no animations)

    [[noreturn]] void fail(const std::string& sentence) const { throw SceneError(printable(path_) + ": " + printable(sentence)); }
    void warn(const std::string& sentence) { scene_.warnings.push_back(printable(path_) + ": " + printable(sentence)); }

    Scene loadImpl() {
        scene_.name = path_;
        std::string why;
        if (!readInputBytes(path_, InputKind::Scene, file_, why)) fail(why);
        if (file_.empty()) fail("file is empty, not a glTF file");
        baseDir_ = fs::path(path_).parent_path().string();

        if (file_.size() >= 4 && std::memcmp(file_.data(), "glTF", 4) == 0) {
            binary_ = true;
            checkGlbContainer();
        } else {
            std::size_t i = 0;
            if (file_.size() >= 3 && file_[0] == 0xEF && file_[1] == 0xBB && file_[2] == 0xBF) i = 3;  // BOM
            while (i < file_.size() && (file_[i] == ' ' || file_[i] == '\t' || file_[i] == '\n' || file_[i] == '\r'))
                ++i;
            if (i >= file_.size() || file_[i] != '{')
                fail("not a glTF file (neither glTF JSON nor binary glTF)");
            json_ = std::string_view(reinterpret_cast<const char*>(file_.data()) + i, file_.size() - i);
        }
        precheckJson();
        parseWithTinygltf();
        checkImagesAvailable();
        convertMaterials();
        readAnimations();
        walkNodes();
        reportWarnings();
        validateAndRepair(scene_, path_);
        finishCameras();
        return std::move(scene_);
    }

    void checkGlbContainer() {
        std::size_t size = file_.size();
        if (size < 20) fail("binary glTF is truncated (shorter than its 20-byte header)");
        std::uint32_t version = readU32(&file_[4]);
        if (version != 2) fail("binary glTF version " + std::to_string(version) + " is not supported (only 2)");
        std::size_t length = readU32(&file_[8]);
        if (length > size)
            fail("binary glTF is truncated: its header declares " + str(length) + " bytes but the file has " +
                 str(size));
        if (length < 20) fail("binary glTF header declares an impossible length of " + str(length) + " bytes");
        std::size_t jsonLen = readU32(&file_[12]);
        if (readU32(&file_[16]) != 0x4E4F534Au) fail("binary glTF does not start with a JSON chunk");
        if (jsonLen == 0 || 20 + jsonLen > length)
            fail("binary glTF is truncated: its JSON chunk extends beyond the end of the data");
        std::size_t pos = 20 + jsonLen;
        if (pos < length) {
            if (pos + 8 > length) fail("binary glTF is truncated inside a chunk header");
            std::size_t binLen = readU32(&file_[pos]);
            if (readU32(&file_[pos + 4]) != 0x004E4942u) fail("binary glTF's second chunk is not a BIN chunk");
            if (pos + 8 + binLen > length)
                fail("binary glTF is truncated: its BIN chunk declares " + str(binLen) + " bytes but only " +
                     str(length - pos - 8) + " remain");
            glbHasBin_ = true;
            glbBinLength_ = binLen;
        }
        glbLength_ = length;
        json_ = std::string_view(reinterpret_cast<const char*>(file_.data()) + 20, jsonLen);
    }

    // Checks that tinygltf cannot do (or reports badly) on the raw JSON: that
    // it is glTF 2.0 at all, required extensions, external files and sizes.
    void precheckJson() {
        const char* what = binary_ ? "binary glTF's JSON chunk" : "file";
        if (jsonDepth(json_) > kMaxJsonDepth)
            fail(std::string(what) + " nests JSON deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        nlohmann::json doc = nlohmann::json::parse(json_.begin(), json_.end(), nullptr, false);
        if (doc.is_discarded()) fail(std::string(what) + " is not valid JSON, so not a glTF file");
        if (!doc.is_object() || !doc.contains("asset") || !doc["asset"].is_object() ||
            !doc["asset"].contains("version") || !doc["asset"]["version"].is_string())
            fail("JSON is not a glTF asset (no \"asset\" object with a \"version\")");
        std::string version = doc["asset"]["version"].get<std::string>();
        if (version.rfind("2.", 0) != 0) fail("glTF version \"" + version + "\" is not supported (only 2.x)");
        // Strict typing before tinygltf, which skips members it cannot read.
        try {
            checkGltfSchema(doc, path_);
        } catch (const SceneError& e) {
            throw SceneError(printable(e.what()));
        }

        if (doc.contains("extensionsRequired")) {
            const auto& req = doc["extensionsRequired"];
            if (!req.is_array()) fail("\"extensionsRequired\" is not an array");
            for (const auto& e : req) {
                if (!e.is_string()) fail("\"extensionsRequired\" contains an entry that is not a string");
                std::string name = e.get<std::string>();
                if (std::find(std::begin(kSupportedRequired), std::end(kSupportedRequired), name) ==
                    std::end(kSupportedRequired))
                    fail("requires the unsupported glTF extension " + name);
            }
        }

        checkLightsJson(doc);

        if (doc.contains("buffers")) {
            const auto& buffers = doc["buffers"];
            if (!buffers.is_array()) fail("\"buffers\" is not an array");
            for (std::size_t b = 0; b < buffers.size(); ++b) checkBufferJson(buffers[b], b);
        }
        if (doc.contains("images")) {
            const auto& images = doc["images"];
            if (!images.is_array()) fail("\"images\" is not an array");
            for (std::size_t i = 0; i < images.size(); ++i) {
                const auto& img = images[i];
                if (!img.is_object() || !img.contains("uri") || !img["uri"].is_string()) continue;
                std::string uri = img["uri"].get<std::string>();
                if (uri.rfind("data:", 0) == 0) continue;
                if (std::string why = inputFileProblem(resolve(uri), InputKind::SceneData); !why.empty())
                    fail("external image '" + uri + "' (image " + str(i) + ") " + externalProblem(why));
            }
        }
    }

    // What tinygltf cannot tell apart or reports with its raw text: a range
    // of 0 (tinygltf's "no range"), a spot light without "spot", a point or
    // directional light with one (glTF types are exclusive).
    void checkLightsJson(const nlohmann::json& doc) {
        if (!doc.contains("extensions") || !doc["extensions"].is_object()) return;
        const auto& ext = doc["extensions"];
        if (!ext.contains("KHR_lights_punctual") || !ext["KHR_lights_punctual"].is_object()) return;
        const auto& kl = ext["KHR_lights_punctual"];
        if (!kl.contains("lights") || !kl["lights"].is_array()) return;
        const auto& lights = kl["lights"];
        for (std::size_t i = 0; i < lights.size(); ++i) {
            const auto& l = lights[i];
            if (!l.is_object() || !l.contains("type") || !l["type"].is_string()) continue;
            const std::string type = l["type"].get<std::string>(), at = "extensions.KHR_lights_punctual.lights[" + str(i) + "]";
            if (type == "spot" && !l.contains("spot"))
                fail(at + " is a spot light without its \"spot\" object (glTF requires it, with the cone angles)");
            if (type != "spot" && l.contains("spot"))
                warn(at + " is a " + type + " light but has a \"spot\" object, which is ignored");
            if (l.contains("range") && l["range"].is_number() && l["range"].get<double>() == 0.0 && type != "directional")
                warn(at + ".range is 0, which glTF does not allow (range must be > 0); the light has no range (infinite)");
        }
    }

    // An external file's problem (gl/input_files.h) in the loader's words.
    static std::string externalProblem(const std::string& why) { return why == "does not exist" ? "is missing" : why; }

    // Same joining rule as tinygltf, so that both look at the same file.
    std::string resolve(const std::string& uri) const {
        std::string decoded = percentDecode(uri);
        if (baseDir_.empty()) return decoded;
        return baseDir_.back() == '/' ? baseDir_ + decoded : baseDir_ + "/" + decoded;
    }

    void checkBufferJson(const nlohmann::json& buf, std::size_t b) {
        std::string which = "buffer " + str(b);
        if (!buf.is_object()) fail(which + " is not a JSON object");
        if (!buf.contains("byteLength") || !buf["byteLength"].is_number_unsigned())
            fail(which + " has no valid byteLength");
        std::uint64_t declared = buf["byteLength"].get<std::uint64_t>();
        if (!buf.contains("uri")) {
            if (!binary_ || b != 0) fail(which + " has no uri (only a binary glTF's first buffer may omit it)");
            if (!glbHasBin_) fail(which + " refers to the binary glTF's BIN chunk, but the file has none");
            if (declared > glbBinLength_)
                fail(which + " declares " + std::to_string(declared) + " bytes but the BIN chunk holds only " +
                     str(glbBinLength_));
            if (glbBinLength_ - declared > 3)
                warn(which + " declares " + std::to_string(declared) + " bytes but the BIN chunk holds " +
                     str(glbBinLength_));
            return;
        }
        if (!buf["uri"].is_string()) fail(which + " has a uri that is not a string");
        std::string uri = buf["uri"].get<std::string>();
        if (uri.rfind("data:", 0) == 0) {
            std::size_t comma = uri.find(',');
            if (!tinygltf::IsDataURI(uri) || comma == std::string::npos)
                fail(which + " has a data URI that is not base64 with a supported media type");
            auto n = std::int64_t(uri.size() - comma - 1), pad = std::int64_t(0);
            for (std::size_t k = uri.size(); k > comma + 1 && uri[k - 1] == '=' && pad < 2; --k) ++pad;
            std::int64_t decoded = std::max<std::int64_t>(n / 4 * 3 + (n % 4 == 0 ? 0 : n % 4 - 1) - pad, 0);
            if (n % 4 == 1 || std::uint64_t(decoded) != declared)
                fail("embedded " + which + " holds " + std::to_string(decoded) +
                     " bytes but declares byteLength " + std::to_string(declared));
            return;
        }
        std::string file = resolve(uri);
        if (std::string why = inputFileProblem(file, InputKind::SceneData); !why.empty())
            fail("external buffer '" + uri + "' (" + which + ") " + externalProblem(why));
        std::error_code ec;
        std::uintmax_t onDisk = fs::file_size(file, ec);
        if (ec) fail("external buffer '" + uri + "' (" + which + ") cannot be read");
        if (onDisk < declared)
            fail("external buffer '" + uri + "' is truncated: " + std::to_string(onDisk) +
                 " bytes on disk but byteLength declares " + std::to_string(declared));
        if (onDisk != declared)
            fail("external buffer '" + uri + "' holds " + std::to_string(onDisk) +
                 " bytes but byteLength declares " + std::to_string(declared));
    }

    void parseWithTinygltf() {
        tinygltf::TinyGLTF gltf;
        gltf.SetFsCallbacks(tinygltf::FsCallbacks{&fsFileExists, &fsExpandFilePath, &fsReadWholeFile,
                                                  &fsWriteWholeFile, nullptr});
        gltf.SetImageLoader(&deferImage, nullptr);
        std::string err, warnings;
        bool ok = false;
        try {
            if (binary_)
                ok = gltf.LoadBinaryFromMemory(&model_, &err, &warnings, file_.data(), unsigned(glbLength_),
                                               baseDir_);
            else
                ok = gltf.LoadASCIIFromString(&model_, &err, &warnings, json_.data(), unsigned(json_.size()),
                                              baseDir_);
        } catch (const std::bad_alloc&) {
            throw;
        } catch (const std::exception& e) {
            fail("invalid glTF: " + oneLine(e.what()));
        }
        if (!ok) fail("invalid glTF: " + oneLine(err.empty() ? std::string("unknown parser error") : err));
        if (!err.empty()) warn("glTF parser: " + oneLine(err));
        if (!warnings.empty()) warn("glTF parser: " + oneLine(warnings));
        file_.clear();
        file_.shrink_to_fit();
        json_ = {};
    }

    void checkImagesAvailable() {
        for (std::size_t i = 0; i < model_.images.size(); ++i) {
            const auto& img = model_.images[i];
            if (img.bufferView != -1 || (img.as_is && !img.image.empty())) continue;
            fail(imageLabel(i) + " could not be read (missing file or unsupported data URI)");
        }
    }

    // ---- byte ranges --------------------------------------------------------

    // Bytes of a bufferView after checking it against its buffer.
    std::pair<const unsigned char*, std::size_t> bufferViewBytes(int v, const std::string& what) const {
        if (v < 0 || std::size_t(v) >= model_.bufferViews.size())
            fail(what + " refers to bufferView " + str(v) + ", which does not exist");
        const auto& bv = model_.bufferViews[std::size_t(v)];
        if (bv.buffer < 0 || std::size_t(bv.buffer) >= model_.buffers.size())
            fail("bufferView " + str(v) + " refers to buffer " + str(bv.buffer) + ", which does not exist");
        const auto& data = model_.buffers[std::size_t(bv.buffer)].data;
        if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
            fail("bufferView " + str(v) + " (bytes " + str(bv.byteOffset) + " to " +
                 std::to_string(std::uint64_t(bv.byteOffset) + bv.byteLength) + ") extends beyond buffer " +
                 str(bv.buffer) + " (" + str(data.size()) + " bytes)");
        return {data.data() + bv.byteOffset, bv.byteLength};
    }

    AccessorData accessor(int a, const std::string& what) const {
        if (a < 0 || std::size_t(a) >= model_.accessors.size())
            fail(what + " refers to accessor " + str(a) + ", which does not exist");
        const auto& acc = model_.accessors[std::size_t(a)];
        std::string name = "accessor " + str(a);
        if (acc.sparse.isSparse) fail(what + " uses sparse " + name + ", which is not supported");
        if (acc.bufferView == -1)
            fail(what + " uses " + name + " without a bufferView, which is not supported");
        std::size_t cs = componentSize(acc.componentType), nc = typeComponents(acc.type);
        if (cs == 0 || nc == 0)
            fail(name + " has an invalid component type (" + str(acc.componentType) + ") or type");
        std::size_t elem = cs * nc;
        auto [bytes, viewLength] = bufferViewBytes(acc.bufferView, name);
        const auto& bv = model_.bufferViews[std::size_t(acc.bufferView)];
        std::size_t stride = bv.byteStride ? bv.byteStride : elem;
        if (stride < elem)
            fail("bufferView " + str(acc.bufferView) + " has byteStride " + str(stride) +
                 ", smaller than the " + str(elem) + "-byte elements of " + name);
        AccessorData d;
        d.stride = stride;
        d.count = acc.count;
        d.componentType = acc.componentType;
        d.type = acc.type;
        d.normalized = acc.normalized;
        if (acc.count == 0) return d;
        bool fits = acc.byteOffset <= viewLength && elem <= viewLength - acc.byteOffset &&
                    (acc.count - 1) <= (viewLength - acc.byteOffset - elem) / stride;
        if (!fits)
            fail(name + " (" + str(acc.count) + " elements of " + str(elem) + " bytes, stride " + str(stride) +
                 ", offset " + str(acc.byteOffset) + ") reads beyond the end of bufferView " +
                 str(acc.bufferView) + " (" + str(viewLength) + " bytes)");
        d.data = bytes + acc.byteOffset;
        return d;
    }

    static std::string describe(const AccessorData& d) {
        return std::string(componentName(d.componentType)) + " " + typeName(d.type);
    }

    // ---- primitives -----------------------------------------------------------

    const LocalPrimitive& primitive(std::size_t mesh, std::size_t prim) {
        if (primCacheOffset_.empty()) {
            std::size_t total = 0;
            for (const auto& m : model_.meshes) {
                primCacheOffset_.push_back(total);
                total += m.primitives.size();
            }
            primCache_.resize(total);
        }
        auto& slot = primCache_[primCacheOffset_[mesh] + prim];
        if (!slot) slot = decodePrimitive(mesh, prim);
        return *slot;
    }

    LocalPrimitive decodePrimitive(std::size_t meshIndex, std::size_t primIndex) {
        const auto& mesh = model_.meshes[meshIndex];
        const auto& p = mesh.primitives[primIndex];
        std::string what = "mesh " + str(meshIndex) + (mesh.name.empty() ? "" : " ('" + mesh.name + "')") +
                           " primitive " + str(primIndex);
        LocalPrimitive out;
        if (p.mode != TINYGLTF_MODE_TRIANGLES) {
            ++skippedModes_[modeName(p.mode)];
            out.skipped = true;
            return out;
        }
        if (p.material != -1) {
            if (p.material < 0 || std::size_t(p.material) >= model_.materials.size())
                fail(what + " refers to material " + str(p.material) + ", which does not exist");
            out.material = p.material;
        }

        auto posIt = p.attributes.find("POSITION");
        if (posIt == p.attributes.end()) fail(what + " has no POSITION attribute");
        AccessorData pos = accessor(posIt->second, what + " POSITION");
        if (pos.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || pos.type != TINYGLTF_TYPE_VEC3)
            fail(what + " POSITION must be a float VEC3 accessor, but accessor " + str(posIt->second) + " is " +
                 describe(pos));
        std::size_t n = pos.count;
        std::vector<glm::vec3> positions(n);
        for (std::size_t i = 0; i < n; ++i)
            positions[i] = glm::vec3(pos.component(i, 0), pos.component(i, 1), pos.component(i, 2));

        std::vector<glm::vec3> normals;
        if (auto it = p.attributes.find("NORMAL"); it != p.attributes.end()) {
            AccessorData nrm = accessor(it->second, what + " NORMAL");
            if (nrm.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || nrm.type != TINYGLTF_TYPE_VEC3)
                fail(what + " NORMAL must be a float VEC3 accessor, but accessor " + str(it->second) + " is " +
                     describe(nrm));
            if (nrm.count != n)
                fail(what + " NORMAL has " + str(nrm.count) + " elements but POSITION has " + str(n));
            normals.resize(n);
            for (std::size_t i = 0; i < n; ++i)
                normals[i] = glm::vec3(nrm.component(i, 0), nrm.component(i, 1), nrm.component(i, 2));
        }

        std::vector<glm::vec2> uvs(n, glm::vec2(0.0f));
        if (auto it = p.attributes.find("TEXCOORD_0"); it != p.attributes.end()) {
            AccessorData uv = accessor(it->second, what + " TEXCOORD_0");
            bool okType = uv.type == TINYGLTF_TYPE_VEC2 &&
                          (uv.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                           (uv.normalized && (uv.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                              uv.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)));
            if (!okType)
                fail(what + " TEXCOORD_0 must be a float or normalized u8/u16 VEC2 accessor, but accessor " +
                     str(it->second) + " is " + describe(uv));
            if (uv.count != n)
                fail(what + " TEXCOORD_0 has " + str(uv.count) + " elements but POSITION has " + str(n));
            for (std::size_t i = 0; i < n; ++i) {
                glm::vec2 t(uv.component(i, 0), uv.component(i, 1));
                if (std::isfinite(t.x) && std::isfinite(t.y))
                    uvs[i] = t;
                else
                    ++badUvs_;
            }
        }

        std::vector<std::uint32_t> indices;
        if (p.indices != -1) {
            AccessorData idx = accessor(p.indices, what + " indices");
            bool okType = idx.type == TINYGLTF_TYPE_SCALAR &&
                          (idx.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                           idx.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                           idx.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
            if (!okType)
                fail(what + " indices must be a u8/u16/u32 SCALAR accessor, but accessor " + str(p.indices) +
                     " is " + describe(idx));
            std::size_t count = idx.count - idx.count % 3;
            if (count != idx.count) ++truncatedIndexLists_;
            indices.resize(count);
            for (std::size_t i = 0; i < count; ++i) {
                std::uint32_t v = idx.index(i);
                if (v >= n)
                    fail(what + " index " + std::to_string(v) + " is out of range (" + str(n) + " vertices)");
                indices[i] = v;
            }
        } else {
            std::size_t count = n - n % 3;
            if (count != n) ++truncatedIndexLists_;
            indices.resize(count);
            for (std::size_t i = 0; i < count; ++i) indices[i] = std::uint32_t(i);
        }

        if (normals.empty()) {
            // glTF: without normals, clients must use flat normals, so every
            // triangle gets its own three vertices.
            out.positions.reserve(indices.size());
            out.normals.reserve(indices.size());
            out.uvs.reserve(indices.size());
            for (std::size_t t = 0; t < indices.size(); t += 3) {
                // In double: the float cross product of edges beyond ~4e9 overflows.
                glm::dvec3 a = positions[indices[t]], b = positions[indices[t + 1]], c = positions[indices[t + 2]];
                glm::dvec3 dn = glm::cross(b - a, c - a);
                double len = glm::length(dn);
                glm::vec3 fn = (len > 0.0 && std::isfinite(len)) ? glm::vec3(dn / len) : glm::vec3(0.0f);
                for (std::size_t k = 0; k < 3; ++k) {
                    out.positions.push_back(positions[indices[t + k]]);
                    out.normals.push_back(fn);
                    out.uvs.push_back(uvs[indices[t + k]]);
                }
            }
            out.indices.resize(indices.size());
            for (std::size_t i = 0; i < indices.size(); ++i) out.indices[i] = std::uint32_t(i);
        } else {
            out.positions = std::move(positions);
            out.normals = std::move(normals);
            out.uvs = std::move(uvs);
            out.indices = std::move(indices);
        }
        return out;
    }

    // ---- materials and images -----------------------------------------------

    void convertMaterials() {
        for (std::size_t i = 0; i < model_.materials.size(); ++i) {
            const auto& gm = model_.materials[i];
            std::string which = "material " + str(i) + (gm.name.empty() ? "" : " ('" + gm.name + "')");
            Material m;
            m.name = gm.name.empty() ? "material" + str(i) : printable(gm.name);
            const auto& pbr = gm.pbrMetallicRoughness;
            if (pbr.baseColorFactor.size() == 4 && allFinite(pbr.baseColorFactor))
                m.baseColor = glm::clamp(glm::vec4(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                                                   float(pbr.baseColorFactor[2]), float(pbr.baseColorFactor[3])),
                                         0.0f, 1.0f);
            else
                warn(which + " has a malformed baseColorFactor; using the default");
            auto unit = [&](double v, const char* name) {
                if (!std::isfinite(v)) {
                    warn(which + " has a non-finite " + name + "; using 1");
                    return 1.0f;
                }
                return float(std::clamp(v, 0.0, 1.0));
            };
            m.metallic = unit(pbr.metallicFactor, "metallicFactor");
            m.roughness = unit(pbr.roughnessFactor, "roughnessFactor");
            std::string at = "materials[" + str(i) + "]";
            for (std::size_t k = 0; k < gm.emissiveFactor.size() && k < 3; ++k)
                if (!floatFinite(gm.emissiveFactor[k]))
                    fail(at + ".emissiveFactor[" + str(k) + "]: " + num(gm.emissiveFactor[k]) +
                         " is not representable as a float");
            glm::vec3 emissive(0.0f);
            if (gm.emissiveFactor.size() == 3 && allFinite(gm.emissiveFactor))
                emissive = glm::max(glm::vec3(float(gm.emissiveFactor[0]), float(gm.emissiveFactor[1]),
                                              float(gm.emissiveFactor[2])),
                                    glm::vec3(0.0f));
            else if (!gm.emissiveFactor.empty())
                warn(which + " has a malformed emissiveFactor; using black");
            if (gm.emissiveFactor.size() == 3 &&
                std::any_of(gm.emissiveFactor.begin(), gm.emissiveFactor.end(), [](double v) { return v < 0.0 || v > 1.0; }))
                warn(at + ".emissiveFactor [" + num(gm.emissiveFactor[0]) + ", " + num(gm.emissiveFactor[1]) + ", " +
                     num(gm.emissiveFactor[2]) + "] is outside 0..1 (glTF; brighter emission goes in "
                     "KHR_materials_emissive_strength): negative components are clamped to 0, the others used as given");
            double strength = 1.0;
            if (auto s = extensionNumber(gm.extensions, "KHR_materials_emissive_strength", "emissiveStrength")) {
                if (std::isfinite(*s) && *s >= 0.0)
                    strength = *s;
                else
                    warn(which + " has an invalid emissiveStrength; using 1");
            }
            double brightestEmission = double(std::max({emissive.x, emissive.y, emissive.z})) * strength;
            if (!(brightestEmission <= kMaxRadiance))
                fail(at + ": emissiveFactor x emissiveStrength = " + num(brightestEmission) + " exceeds " +
                     num(kMaxRadiance) + " (float overflow on the GPU)");
            m.emissive = emissive * float(strength);
            m.doubleSided = gm.doubleSided;
            int tex = pbr.baseColorTexture.index;
            if (tex != -1) {
                if (tex < 0 || std::size_t(tex) >= model_.textures.size())
                    fail(which + " baseColorTexture refers to texture " + str(tex) + ", which does not exist");
                int source = model_.textures[std::size_t(tex)].source;
                if (source == -1) {
                    warn("texture " + str(tex) + " has no image source; " + which + " is left untextured");
                } else {
                    if (source < 0 || std::size_t(source) >= model_.images.size())
                        fail("texture " + str(tex) + " refers to image " + str(source) + ", which does not exist");
                    if (pbr.baseColorTexture.texCoord != 0)
                        warn(which + " samples its base colour with TEXCOORD_" +
                             str(pbr.baseColorTexture.texCoord) + "; TEXCOORD_0 is used instead");
                    m.baseColorTexture = imageSlot(source);
                }
            }
            scene_.materials.push_back(std::move(m));
        }
    }

    std::string imageLabel(std::size_t index) const {
        const auto& gi = model_.images[index];
        std::string which = "image " + str(index);
        if (!gi.uri.empty() && gi.uri.rfind("data:", 0) != 0)
            which += " ('" + gi.uri + "')";
        else if (!gi.name.empty())
            which += " ('" + gi.name + "')";
        else if (!gi.uri.empty())
            which += " (embedded data URI)";
        return which;
    }

    int imageSlot(int index) {
        if (auto it = imageSlots_.find(index); it != imageSlots_.end()) return it->second;
        const auto& gi = model_.images[std::size_t(index)];
        std::string which = imageLabel(std::size_t(index));
        const unsigned char* bytes = nullptr;
        std::size_t size = 0;
        if (gi.bufferView != -1) {
            std::tie(bytes, size) = bufferViewBytes(gi.bufferView, which);
        } else {
            bytes = gi.image.data();
            size = gi.image.size();
        }
        if (size == 0) fail(which + " is empty");
        if (size > std::size_t(INT_MAX)) fail(which + " is too large");
        int w = 0, h = 0, comp = 0;
        if (!stbi_info_from_memory(bytes, int(size), &w, &h, &comp))
            fail(which + " is not a readable PNG, JPEG, BMP or GIF image (" + stbi_failure_reason() + ")");
        if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
            fail(which + " has an unsupported size of " + str(w) + "x" + str(h) + " pixels (at most " +
                 str(kMaxImageSide) + " per side)");
        unsigned char* pixels = stbi_load_from_memory(bytes, int(size), &w, &h, &comp, 4);
        if (!pixels) fail(which + " could not be decoded (" + stbi_failure_reason() + "); it may be truncated");
        Image img;
        img.width = w;
        img.height = h;
        img.name = printable(gi.name.empty() ? gi.uri : gi.name);
        if (img.name.rfind("data:", 0) == 0) img.name = "image" + str(index);
        img.rgba.assign(pixels, pixels + std::size_t(w) * std::size_t(h) * 4);
        stbi_image_free(pixels);
        scene_.images.push_back(std::move(img));
        int slot = int(scene_.images.size()) - 1;
        imageSlots_[index] = slot;
        return slot;
    }

    int defaultMaterial() {
        if (defaultMaterial_ < 0) {
            Material m;
            m.name = "default";
            scene_.materials.push_back(m);
            defaultMaterial_ = int(scene_.materials.size()) - 1;
        }
        return defaultMaterial_;
    }

    // ---- node hierarchy -------------------------------------------------------

    glm::dmat4 localMatrix(std::size_t i) const {
        const auto& node = model_.nodes[i];
        std::string which = "node " + str(i);
        if (!node.matrix.empty()) {
            if (node.matrix.size() != 16 || !allFinite(node.matrix))
                fail(which + " has a malformed matrix (needs 16 finite numbers)");
            return glm::make_mat4(node.matrix.data());  // column-major, like glTF
        }
        glm::dmat4 m(1.0);
        if (!node.translation.empty()) {
            if (node.translation.size() != 3 || !allFinite(node.translation))
                fail(which + " has a malformed translation (needs 3 finite numbers)");
            m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
        }
        if (!node.rotation.empty()) {
            if (node.rotation.size() != 4 || !allFinite(node.rotation))
                fail(which + " has a malformed rotation (needs 4 finite numbers)");
            glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // w, x, y, z
            double len = glm::length(q);
            if (!(len > 1e-12)) fail(which + " has a zero rotation quaternion");
            m = m * glm::mat4_cast(q / len);
        }
        if (!node.scale.empty()) {
            if (node.scale.size() != 3 || !allFinite(node.scale))
                fail(which + " has a malformed scale (needs 3 finite numbers)");
            m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
        }
        return m;
    }

    std::vector<int> rootNodes() const {
        std::size_t n = model_.nodes.size();
        for (std::size_t i = 0; i < n; ++i)
            for (int c : model_.nodes[i].children)
                if (c < 0 || std::size_t(c) >= n)
                    fail("node " + str(i) + " lists child " + str(c) + ", which does not exist");
        const std::vector<int>* roots = nullptr;
        if (model_.defaultScene != -1) {
            if (model_.defaultScene < 0 || std::size_t(model_.defaultScene) >= model_.scenes.size())
                fail("the default scene " + str(model_.defaultScene) + " does not exist");
            roots = &model_.scenes[std::size_t(model_.defaultScene)].nodes;
        } else if (!model_.scenes.empty()) {
            roots = &model_.scenes[0].nodes;
        }
        std::vector<int> out;
        if (roots) {
            for (int r : *roots)
                if (r < 0 || std::size_t(r) >= n) fail("the scene lists node " + str(r) + ", which does not exist");
            out = *roots;
        } else {
            std::vector<char> isChild(n, 0);
            for (const auto& node : model_.nodes)
                for (int c : node.children) isChild[std::size_t(c)] = 1;
            for (std::size_t i = 0; i < n; ++i)
                if (!isChild[i]) out.push_back(int(i));
        }
        return out;
    }

    // Reachable nodes in topological order (parents first); throws on cycles.
    std::vector<int> topologicalOrder(const std::vector<int>& roots) const {
        std::vector<char> state(model_.nodes.size(), 0);  // 0 new, 1 on the current path, 2 done
        std::vector<int> post;
        std::vector<std::pair<int, std::size_t>> stack;
        for (int r : roots) {
            if (state[std::size_t(r)] != 0) continue;
            state[std::size_t(r)] = 1;
            stack.emplace_back(r, 0);
            while (!stack.empty()) {
                int v = stack.back().first;
                std::size_t next = stack.back().second;
                const auto& children = model_.nodes[std::size_t(v)].children;
                if (next < children.size()) {
                    stack.back().second = next + 1;
                    int c = children[next];
                    if (state[std::size_t(c)] == 1)
                        fail("the node hierarchy contains a cycle (node " + str(c) + " is its own ancestor)");
                    if (state[std::size_t(c)] == 0) {
                        state[std::size_t(c)] = 1;
                        stack.emplace_back(c, 0);
                    }
                } else {
                    state[std::size_t(v)] = 2;
                    post.push_back(v);
                    stack.pop_back();
                }
            }
        }
        std::reverse(post.begin(), post.end());
        return post;
    }

    // Triangles and vertices one instance of a mesh adds (the accessors that
    // decide them are range-checked here).
    std::pair<double, double> meshSize(int mesh) const {
        if (mesh == -1) return {0.0, 0.0};
        if (mesh < 0 || std::size_t(mesh) >= model_.meshes.size())
            fail("a node refers to mesh " + str(mesh) + ", which does not exist");
        double tris = 0.0, verts = 0.0;
        const auto& m = model_.meshes[std::size_t(mesh)];
        for (std::size_t pi = 0; pi < m.primitives.size(); ++pi) {
            const auto& p = m.primitives[pi];
            if (p.mode != TINYGLTF_MODE_TRIANGLES) continue;
            std::string what = "mesh " + str(mesh) + " primitive " + str(pi);
            auto pos = p.attributes.find("POSITION");
            if (pos == p.attributes.end()) fail(what + " has no POSITION attribute");
            double positions = double(accessor(pos->second, what + " POSITION").count);
            double t = p.indices == -1 ? std::floor(positions / 3.0)
                                       : double(accessor(p.indices, what + " indices").count / 3);
            tris += t;
            verts += p.attributes.count("NORMAL") ? positions : 3.0 * t;  // flat normals unshare vertices
        }
        return {tris, verts};
    }

    // ---- animations (issue 23) ------------------------------------------------

    // glTF animation samplers as double tracks; every animation plays from
    // t = 0 at once. Morph targets ("weights") are refused, skins in walkNodes.
    void readAnimations() {
        if (model_.animations.empty()) return;
        nodeTracks_.assign(model_.nodes.size(), {-1, -1, -1});
        for (std::size_t ai = 0; ai < model_.animations.size(); ++ai) {
            const auto& anim = model_.animations[ai];
            for (std::size_t ci = 0; ci < anim.channels.size(); ++ci) {
                const auto& ch = anim.channels[ci];
                const std::string at = "animations[" + str(ai) + "].channels[" + str(ci) + "]";
                if (ch.target_path == "weights")
                    fail(at + " animates morph target weights; rtgi plays node animations (translation, rotation, "
                         "scale) only and does not support morph targets");
                int prop = ch.target_path == "translation" ? 0 : ch.target_path == "rotation" ? 1
                           : ch.target_path == "scale"     ? 2 : -1;
                if (prop < 0) fail(at + " has the unknown target path \"" + ch.target_path + "\"");
                if (ch.target_node < 0 || std::size_t(ch.target_node) >= model_.nodes.size())
                    fail(at + " targets node " + str(ch.target_node) + ", which does not exist");
                if (!model_.nodes[std::size_t(ch.target_node)].matrix.empty())
                    fail(at + " animates node " + str(ch.target_node) +
                         ", which has a matrix (glTF: animated nodes use translation/rotation/scale)");
                if (ch.sampler < 0 || std::size_t(ch.sampler) >= anim.samplers.size())
                    fail(at + " refers to sampler " + str(ch.sampler) + ", which does not exist");
                int& slot = nodeTracks_[std::size_t(ch.target_node)][std::size_t(prop)];
                if (slot >= 0) {
                    warn(at + " animates the " + ch.target_path + " of node " + str(ch.target_node) +
                         " again; the first channel that drives a property plays");
                    continue;
                }
                const auto& sm = anim.samplers[std::size_t(ch.sampler)];
                const std::string sat = "animations[" + str(ai) + "].samplers[" + str(ch.sampler) + "]";
                KeyTrack k;
                k.components = prop == 1 ? 4 : 3;
                k.rotation = prop == 1;
                k.interpolation = sm.interpolation == "STEP"          ? Interpolation::Step
                                  : sm.interpolation == "CUBICSPLINE" ? Interpolation::CubicSpline
                                  : sm.interpolation.empty() || sm.interpolation == "LINEAR"
                                      ? Interpolation::Linear
                                      : (fail(sat + " has the unknown interpolation \"" + sm.interpolation + "\""),
                                         Interpolation::Linear);
                AccessorData in = accessor(sm.input, sat + " input");
                if (in.type != TINYGLTF_TYPE_SCALAR || in.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
                    fail(sat + " input must be a float SCALAR accessor (is " + describe(in) + ")");
                AccessorData outA = accessor(sm.output, sat + " output");
                if (typeComponents(outA.type) != std::size_t(k.components))
                    fail(sat + " output must be a VEC" + str(k.components) + " accessor for " + ch.target_path +
                         " (is " + describe(outA) + ")");
                for (std::size_t i = 0; i < in.count; ++i) k.times.push_back(double(in.component(i, 0)));
                for (std::size_t i = 0; i < outA.count; ++i)
                    for (int c = 0; c < k.components; ++c) k.values.push_back(double(outA.component(i, std::size_t(c))));
                try {
                    k.validate(sat);
                } catch (const SceneError& e) {
                    fail(e.what());
                }
                slot = int(scene_.animation.tracks.size());
                scene_.animation.tracks.push_back(std::move(k));
            }
        }
    }

    AnimatedNode animatedNode(int v, int parentInstance) const {
        const auto& node = model_.nodes[std::size_t(v)];
        AnimatedNode a;
        a.parent = parentInstance;
        a.name = printable(node.name.empty() ? "node " + str(v) : node.name);
        if (!node.matrix.empty()) a.matrix = localMatrix(std::size_t(v));  // checked there
        if (node.translation.size() == 3)
            a.rest.translation = {node.translation[0], node.translation[1], node.translation[2]};
        if (node.rotation.size() == 4)
            a.rest.rotation = glm::normalize(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
        if (node.scale.size() == 3) a.rest.scale = {node.scale[0], node.scale[1], node.scale[2]};
        for (int p = 0; p < 3; ++p) a.track[p] = nodeTracks_[std::size_t(v)][std::size_t(p)];
        return a;
    }

    void walkNodes() {
        std::vector<int> roots = rootNodes();
        std::vector<int> order = topologicalOrder(roots);

        // How often every node is instanced, before anything is generated.
        std::vector<double> instances(model_.nodes.size(), 0.0);
        for (int r : roots) instances[std::size_t(r)] += 1.0;
        double totalInstances = 0.0, totalTriangles = 0.0, totalVertices = 0.0;
        for (int v : order) {
            double k = instances[std::size_t(v)];
            totalInstances += k;
            if (k > 0.0) {
                auto [tris, verts] = meshSize(model_.nodes[std::size_t(v)].mesh);
                totalTriangles += k * tris;
                totalVertices += k * verts;
            }
            for (int c : model_.nodes[std::size_t(v)].children) instances[std::size_t(c)] += k;
        }
        if (totalInstances > kMaxNodeInstances)
            fail("the node hierarchy expands to more than " + std::to_string(std::int64_t(kMaxNodeInstances)) +
                 " node instances");
        if (totalTriangles > kMaxTriangles)
            fail("the node hierarchy instances more than " + std::to_string(std::int64_t(kMaxTriangles)) +
                 " triangles");
        if (totalVertices > kMaxVertices)
            fail("the node hierarchy instances more than " + std::to_string(std::int64_t(kMaxVertices)) +
                 " vertices");

        // Host memory of the flattened scene, known before anything is built
        // (Scene copies it once more into the renderer and builds a BVH).
        double hostBytes = totalVertices * double(sizeof(Vertex)) + totalTriangles * 12.0;
        std::uint64_t hostLimit = sceneHostMemoryLimit();
        if (hostBytes > double(hostLimit))
            fail("the node hierarchy instances " + std::to_string(std::int64_t(totalTriangles)) +
                 " triangles, which need about " + num(hostBytes / 1073741824.0) + " GiB of host memory, more than the " +
                 num(double(hostLimit) / 1073741824.0) + " GiB allowed (half of the available memory)");
        scene_.vertices.reserve(std::size_t(totalVertices));
        scene_.indices.reserve(std::size_t(totalTriangles) * 3);

        std::vector<std::optional<glm::dmat4>> local(model_.nodes.size());
        for (int v : order) local[std::size_t(v)] = localMatrix(std::size_t(v));

        bool skinned = false;
        const bool animated = !nodeTracks_.empty();
        struct Entry {
            int node;
            glm::dmat4 parent;
            int parentInstance;  // index into scene_.animation.nodes (animated files only)
        };
        std::vector<Entry> stack;
        for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, glm::dmat4(1.0), -1});
        while (!stack.empty()) {
            auto [v, parent, parentInstance] = stack.back();
            stack.pop_back();
            const auto& node = model_.nodes[std::size_t(v)];
            glm::dmat4 world = parent * *local[std::size_t(v)];
            if (node.skin != -1) skinned = true;
            if (animated) {
                if (node.skin != -1)
                    fail("node " + str(v) + " is skinned; rtgi plays node animations (translation, rotation, scale) "
                         "only and does not support skinning");
                currentAnimNode_ = int(scene_.animation.nodes.size());
                scene_.animation.nodes.push_back(animatedNode(v, parentInstance));
            }
            if (node.mesh != -1) {
                if (node.mesh < 0 || std::size_t(node.mesh) >= model_.meshes.size())
                    fail("node " + str(v) + " refers to mesh " + str(node.mesh) + ", which does not exist");
                appendMesh(v, std::size_t(node.mesh), world);
            }
            if (node.camera != -1) addCamera(v, node.camera, world);
            if (auto it = node.extensions.find("KHR_lights_punctual"); it != node.extensions.end()) {
                const tinygltf::Value& ext = it->second;
                if (!ext.IsObject() || !ext.Has("light") || !ext.Get("light").IsNumber())
                    fail("node " + str(v) + " has a KHR_lights_punctual entry without a light index");
                double li = ext.Get("light").GetNumberAsDouble();
                if (!(li >= 0.0) || li >= double(model_.lights.size()) || li != std::floor(li))
                    fail("node " + str(v) + " refers to light " +
                         (li == std::floor(li) && std::abs(li) < 1e15 ? std::to_string(std::int64_t(li))
                                                                       : std::to_string(li)) +
                         ", which does not exist");
                addLight(v, std::size_t(li), world);
            }
            for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
                stack.push_back({*c, world, currentAnimNode_});
        }
        if (skinned) warn("skins are ignored; skinned meshes are placed by their node transforms");
    }

    void appendMesh(int node, std::size_t meshIndex, const glm::dmat4& world) {
        const auto& mesh = model_.meshes[meshIndex];
        glm::dmat3 linear(world);
        double det = glm::determinant(linear);
        glm::dmat3 cof = cofactor(linear);
        double largest = 0.0;  // rescaled so that tiny or huge scales survive the cast to float
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) largest = std::max(largest, std::abs(cof[c][r]));
        glm::mat3 normalMatrix(largest > 0.0 ? cof * ((det < 0.0 ? -1.0 : 1.0) / largest) : cof);
        bool flip = det < 0.0;
        for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
            const LocalPrimitive& lp = primitive(meshIndex, pi);
            if (lp.skipped || lp.indices.empty()) continue;
            auto base = std::uint32_t(scene_.vertices.size());
            if (currentAnimNode_ >= 0)
                scene_.animation.nodes[std::size_t(currentAnimNode_)].vertexRanges.emplace_back(
                    base, std::uint32_t(lp.positions.size()));
            for (std::size_t i = 0; i < lp.positions.size(); ++i) {
                Vertex vx;
                // Transformed in double, checked, then stored as the float the GPU reads.
                glm::dvec3 wp = glm::dvec3(world * glm::dvec4(glm::dvec3(lp.positions[i]), 1.0));
                if (!(std::abs(wp.x) <= kMaxCoordinate && std::abs(wp.y) <= kMaxCoordinate &&
                      std::abs(wp.z) <= kMaxCoordinate)) {
                    if (!std::isfinite(wp.x + wp.y + wp.z))
                        fail("meshes[" + str(meshIndex) + "].primitives[" + str(pi) +
                             "].attributes.POSITION: a vertex position is NaN or infinite (placed by nodes[" +
                             str(node) + "])");
                    fail("meshes[" + str(meshIndex) + "].primitives[" + str(pi) + "]: nodes[" + str(node) +
                         "] places a vertex at (" + num(wp.x) + ", " + num(wp.y) + ", " + num(wp.z) +
                         "), beyond the supported +-1e15 (float distances and depth would overflow)");
                }
                vx.position = glm::vec3(wp);
                glm::vec3 nn = normalMatrix * lp.normals[i];
                float len = glm::length(nn);
                vx.normal = (len > 0.0f && std::isfinite(len)) ? nn / len : glm::vec3(0.0f);
                vx.uv = lp.uvs[i];
                scene_.vertices.push_back(vx);
            }
            DrawRange d;
            d.firstIndex = std::uint32_t(scene_.indices.size());
            d.indexCount = std::uint32_t(lp.indices.size());
            d.material = lp.material >= 0 ? lp.material : defaultMaterial();
            for (std::size_t t = 0; t < lp.indices.size(); t += 3) {
                scene_.indices.push_back(base + lp.indices[t]);
                scene_.indices.push_back(base + lp.indices[t + (flip ? 2 : 1)]);
                scene_.indices.push_back(base + lp.indices[t + (flip ? 1 : 2)]);
            }
            scene_.draws.push_back(d);
        }
    }

    static glm::vec3 worldDirection(const glm::dmat4& world, glm::dvec3 local, glm::vec3 fallback) {
        glm::dvec3 d = glm::dmat3(world) * local;
        double len = glm::length(d);
        return (len > 1e-300 && std::isfinite(len)) ? glm::vec3(d / len) : fallback;
    }

    // Lights and cameras sit at the node's translation: the same bound as vertices.
    void checkPlacement(int node, const glm::dmat4& world, const std::string& what) const {
        for (int k = 0; k < 3; ++k)
            if (!(std::abs(world[3][k]) <= kMaxCoordinate))
                fail("nodes[" + str(node) + "] places " + what + " at (" + num(world[3][0]) + ", " + num(world[3][1]) +
                     ", " + num(world[3][2]) + "), beyond the supported +-1e15");
    }

    void addCamera(int node, int index, const glm::dmat4& world) {
        if (index < 0 || std::size_t(index) >= model_.cameras.size())
            fail("node " + str(node) + " refers to camera " + str(index) + ", which does not exist");
        const auto& gc = model_.cameras[std::size_t(index)];
        std::string which = "camera " + str(index);
        if (gc.type != "perspective") {
            warn(which + " is " + gc.type + "; only perspective cameras are supported, so it is skipped");
            return;
        }
        checkPlacement(node, world, "cameras[" + str(index) + "]");
        Camera c;
        const std::string& nodeName = model_.nodes[std::size_t(node)].name;
        c.name = printable(!gc.name.empty() ? gc.name : !nodeName.empty() ? nodeName : which);
        c.position = glm::vec3(world[3]);
        glm::vec3 forward = worldDirection(world, glm::dvec3(0, 0, -1), glm::vec3(0, 0, -1));
        c.up = worldDirection(world, glm::dvec3(0, 1, 0), glm::vec3(0, 1, 0));
        c.target = c.position + forward;
        // The ranges of --set camera.fov / camera.near / camera.far (a value
        // that --set rejects is rejected here too, naming the JSON path).
        std::string at = "cameras[" + str(index) + "].perspective.";
        double yfov = gc.perspective.yfov;
        const double kPi = 3.14159265358979323846;
        if (!(yfov >= 0.5 * kPi / 180.0 && yfov <= 175.0 * kPi / 180.0))
            fail(at + "yfov: " + num(yfov) + " radians is outside the supported 0.5..175 degrees (0.00873..3.054)");
        c.fovY = float(yfov);
        double zn = gc.perspective.znear, zf = gc.perspective.zfar;
        if (!(zn >= 1e-6 && zn <= 1e6)) fail(at + "znear: " + num(zn) + " is outside the supported 1e-6..1e6");
        if (zf != 0.0) {  // 0: no zfar in the file (an infinite projection)
            if (!(zf >= 1e-5 && zf <= 1e9)) fail(at + "zfar: " + num(zf) + " is outside the supported 1e-5..1e9");
            if (!(float(zf) > float(zn)))
                fail(at + "zfar: " + num(zf) + " does not lie beyond znear " + num(zn) + " in float precision");
        }
        scene_.cameras.push_back(c);
        if (currentAnimNode_ >= 0)
            scene_.animation.nodes[std::size_t(currentAnimNode_)].cameras.push_back(int(scene_.cameras.size()) - 1);
        pendingCameras_.push_back({scene_.cameras.size() - 1, gc.perspective.znear, gc.perspective.zfar});
    }

    // near/far need the scene's size when they are missing or invalid.
    void finishCameras() {
        Aabb b = scene_.bounds();
        float diag = std::max(glm::length(b.extent()), 1e-3f);
        for (const auto& pc : pendingCameras_) {
            Camera& c = scene_.cameras[pc.index];
            c.near = float(pc.znear);  // ranges checked in addCamera
            if (pc.zfar != 0.0)
                c.far = float(pc.zfar);
            else
                c.far = std::max(1000.0f * diag, 1000.0f * c.near);  // glTF: no zfar = infinite projection
        }
    }

    void addLight(int node, std::size_t index, const glm::dmat4& world) {
        const auto& gl = model_.lights[index];
        std::string which = "light " + str(index);
        Light l;
        if (gl.type == "directional")
            l.type = LightType::Directional;
        else if (gl.type == "point")
            l.type = LightType::Point;
        else if (gl.type == "spot")
            l.type = LightType::Spot;
        else {
            warn(which + " has the unknown type \"" + gl.type + "\" and is skipped");
            return;
        }
        const std::string& nodeName = model_.nodes[std::size_t(node)].name;
        l.name = printable(!gl.name.empty() ? gl.name : !nodeName.empty() ? nodeName : which);
        checkPlacement(node, world, "light " + str(index));
        // Lights ignore the node's scale (KHR_lights_punctual); a scale far
        // outside what a unit change explains is a broken file, not a choice.
        for (int k = 0; k < 3; ++k) {
            const double scale = glm::length(glm::dvec3(world[k]));
            if (!(scale >= 1e-6 && scale <= 1e6)) {
                warn("nodes[" + str(node) + "] scales light " + str(index) + " by " + num(scale) +
                     " (outside 1e-6..1e6); lights are not scaled in glTF, so the scale is ignored");
                break;
            }
        }
        // Every radiometric value reaches the GPU as a float, and is multiplied
        // there (colour x intensity x albedo / pi x area in the RSM flux): each
        // factor and the product colour x intensity must be finite floats.
        std::string at = "extensions.KHR_lights_punctual.lights[" + str(index) + "].";
        if (gl.color.size() == 3) {
            for (std::size_t k = 0; k < 3; ++k)
                if (!floatFinite(gl.color[k]))
                    fail(at + "color[" + str(k) + "]: " + num(gl.color[k]) + " is not representable as a float");
            l.color = glm::max(glm::vec3(float(gl.color[0]), float(gl.color[1]), float(gl.color[2])), glm::vec3(0.0f));
            if (gl.color[0] < 0.0 || gl.color[1] < 0.0 || gl.color[2] < 0.0)
                warn(at + "color [" + num(gl.color[0]) + ", " + num(gl.color[1]) + ", " + num(gl.color[2]) +
                     "] has a negative component (glTF colours are 0..1); clamped to 0");
        } else if (!gl.color.empty()) {
            warn(which + " has a malformed color; using white");
        }
        if (!floatFinite(gl.intensity))
            fail(at + "intensity: " + num(gl.intensity) + " is not representable as a float");
        if (gl.intensity >= 0.0)
            l.intensity = float(gl.intensity);
        else
            warn(at + "intensity is " + num(gl.intensity) + ", which glTF does not allow (intensity must be >= 0); using 1");
        double brightest = double(std::max({l.color.x, l.color.y, l.color.z})) * double(l.intensity);
        if (!(brightest <= kMaxRadiance))
            fail(at + "color x intensity = " + num(brightest) + " exceeds " + num(kMaxRadiance) +
                 " (products with areas and albedo on the GPU would overflow float)");
        if (!floatFinite(gl.range)) fail(at + "range: " + num(gl.range) + " is not representable as a float");
        if (gl.range >= 0.0)
            l.range = float(gl.range);
        else
            warn(at + "range is " + num(gl.range) + ", which glTF does not allow (range must be > 0); the light has no range (infinite)");
        l.position = glm::vec3(world[3]);
        l.direction = worldDirection(world, glm::dvec3(0, 0, -1), glm::vec3(0, 0, -1));
        if (l.type == LightType::Spot) {
            double inner = gl.spot.innerConeAngle, outer = gl.spot.outerConeAngle;
            const double halfPi = 1.5707963267948966;
            if (!(std::isfinite(inner) && std::isfinite(outer) && inner >= 0.0 && inner < outer && outer <= halfPi)) {
                warn(which + " has invalid cone angles; clamping them to 0 <= inner < outer <= pi/2");
                outer = std::isfinite(outer) ? std::clamp(outer, 1e-3, halfPi) : 0.7853981633974483;
                inner = std::isfinite(inner) ? std::clamp(inner, 0.0, outer * 0.999) : 0.0;
            }
            l.innerCone = float(inner);
            l.outerCone = float(outer);
        }
        scene_.lights.push_back(l);
        if (currentAnimNode_ >= 0)
            scene_.animation.nodes[std::size_t(currentAnimNode_)].lights.push_back(int(scene_.lights.size()) - 1);
    }

    void reportWarnings() {
        for (const auto& [mode, count] : skippedModes_)
            warn("skipped " + str(count) + " primitive(s) drawn as " + mode + "; only triangle lists are supported");
        if (truncatedIndexLists_)
            warn(str(truncatedIndexLists_) + " primitive(s) have a vertex or index count that is not a multiple "
                 "of 3; the incomplete last triangle was dropped");
        if (badUvs_) warn("replaced " + str(badUvs_) + " non-finite texture coordinates by 0");
    }
};

}  // namespace

Scene loadGltf(const std::string& path) { return GltfLoader(path).load(); }

}  // namespace rtgi
