#include "scene/gltf_schema.h"

#include "render/settings.h"
#include "scene/scene.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <set>
#include <string>
#include <vector>

namespace rtgi {

namespace {

using json = nlohmann::json;

// The member types follow the glTF 2.0 JSON schema (Khronos, glTF 2.0
// specification, section 5 "Properties Reference") and the schemas of the
// extensions rtgi reads (KHR_lights_punctual, KHR_materials_emissive_strength,
// KHR_texture_transform). Unknown members are allowed, as the spec allows.
class Checker {
public:
    Checker(const json& doc, std::string file) : doc_(doc), file_(std::move(file)) {}

    void run() {
        const json& d = doc_;
        topArray("scenes", [&](const json& s, const std::string& p) {
            if (auto* n = member(s, "nodes", p))
                indexArray(*n, p + ".nodes", "nodes", /*unique=*/true, /*nonEmpty=*/false);
            common(s, p);
        });
        if (auto* s = member(d, "scene", "")) index(*s, "scene", "scenes");
        topArray("nodes", [&](const json& n, const std::string& p) { node(n, p); });
        checkTrees();
        topArray("meshes", [&](const json& m, const std::string& p) { mesh(m, p); });
        topArray("accessors", [&](const json& a, const std::string& p) { accessor(a, p); });
        topArray("bufferViews", [&](const json& v, const std::string& p) {
            index(required(v, "buffer", p), p + ".buffer", "buffers");
            integerMember(v, "byteOffset", p, 0);
            integer(required(v, "byteLength", p), p + ".byteLength", 1);
            if (auto* s = member(v, "byteStride", p)) {
                integer(*s, p + ".byteStride", 4);
                if (s->get<double>() > 252) fail(p + ".byteStride", "must be at most 252, found " + text(*s));
            }
            integerMember(v, "target", p, 0);
            common(v, p);
        });
        topArray("buffers", [&](const json& b, const std::string& p) {
            integer(required(b, "byteLength", p), p + ".byteLength", 1);
            stringMember(b, "uri", p);
            common(b, p);
        });
        topArray("materials", [&](const json& m, const std::string& p) { material(m, p); });
        topArray("textures", [&](const json& t, const std::string& p) {
            if (auto* s = member(t, "sampler", p)) index(*s, p + ".sampler", "samplers");
            if (auto* s = member(t, "source", p)) index(*s, p + ".source", "images");
            common(t, p);
        });
        topArray("images", [&](const json& im, const std::string& p) {
            stringMember(im, "uri", p);
            stringMember(im, "mimeType", p);
            if (auto* v = member(im, "bufferView", p)) index(*v, p + ".bufferView", "bufferViews");
            common(im, p);
        });
        topArray("samplers", [&](const json& s, const std::string& p) {
            for (const char* k : {"magFilter", "minFilter", "wrapS", "wrapT"}) integerMember(s, k, p, 0);
            common(s, p);
        });
        topArray("cameras", [&](const json& c, const std::string& p) { camera(c, p); });
        topArray("skins", [&](const json& s, const std::string& p) {
            if (auto* j = member(s, "joints", p)) indexArray(*j, p + ".joints", "nodes", true, true);
            if (auto* k = member(s, "skeleton", p)) index(*k, p + ".skeleton", "nodes");
            if (auto* m = member(s, "inverseBindMatrices", p)) index(*m, p + ".inverseBindMatrices", "accessors");
            common(s, p);
        });
        topArray("animations", [&](const json& a, const std::string& p) { common(a, p); });
        for (const char* k : {"extensionsUsed", "extensionsRequired"})
            if (auto* e = member(d, k, "")) {
                expectArray(*e, k);
                for (std::size_t i = 0; i < e->size(); ++i) expectString((*e)[i], at(k, i));
            }
        extensions(d, "");
        if (auto* lights = extension(d, "KHR_lights_punctual", "")) {
            std::string p = "extensions.KHR_lights_punctual";
            const json& arr = required(*lights, "lights", p);
            expectArray(arr, p + ".lights");
            for (std::size_t i = 0; i < arr.size(); ++i) light(arr[i], at(p + ".lights", i));
        }
    }

private:
    const json& doc_;
    std::string file_;

    [[noreturn]] void fail(const std::string& path, const std::string& what) const {
        throw SceneError(file_ + ": " + (path.empty() ? std::string("the document") : path) + ": " + what);
    }

    static std::string at(const std::string& p, std::size_t i) { return p + "[" + std::to_string(i) + "]"; }
    static std::string sub(const std::string& p, const std::string& k) { return p.empty() ? k : p + "." + k; }

    static std::string typeWord(const json& v) { return jsonTypeWord(v); }
    // A value for the message: numbers as written, strings quoted and short.
    static std::string text(const json& v) {
        if (v.is_number()) {
            char buf[40];
            std::snprintf(buf, sizeof buf, "%.9g", v.get<double>());
            return buf;
        }
        if (v.is_string()) {
            std::string s = v.get<std::string>();
            if (s.size() > 40) s = s.substr(0, 40) + "...";
            return "the string \"" + s + "\"";
        }
        return typeWord(v);
    }

    const json* member(const json& o, const char* k, const std::string&) const {
        auto it = o.find(k);
        return it == o.end() ? nullptr : &*it;
    }
    const json& required(const json& o, const char* k, const std::string& p) const {
        auto it = o.find(k);
        if (it == o.end()) fail(p, std::string("the required member \"") + k + "\" is missing");
        return *it;
    }

    void expectObject(const json& v, const std::string& p) const {
        if (!v.is_object()) fail(p, "expected an object, found " + typeWord(v));
    }
    void expectArray(const json& v, const std::string& p) const {
        if (!v.is_array()) fail(p, "expected an array, found " + typeWord(v));
    }
    void expectString(const json& v, const std::string& p) const {
        if (!v.is_string()) fail(p, "expected a string, found " + text(v));
    }
    void number(const json& v, const std::string& p) const {
        if (!v.is_number()) fail(p, "expected a number, found " + text(v));
    }
    void integer(const json& v, const std::string& p, double minimum) const {
        if (!v.is_number() || v.get<double>() != std::floor(v.get<double>()))
            fail(p, "expected an integer, found " + text(v));
        if (v.get<double>() < minimum)
            fail(p, "must be at least " + std::to_string(std::int64_t(minimum)) + ", found " + text(v));
    }
    void integerMember(const json& o, const char* k, const std::string& p, double minimum) const {
        if (auto* v = member(o, k, p)) integer(*v, sub(p, k), minimum);
    }
    void stringMember(const json& o, const char* k, const std::string& p) const {
        if (auto* v = member(o, k, p)) expectString(*v, sub(p, k));
    }
    void boolMember(const json& o, const char* k, const std::string& p) const {
        if (auto* v = member(o, k, p); v && !v->is_boolean()) fail(sub(p, k), "expected true or false, found " + text(*v));
    }
    void numberMember(const json& o, const char* k, const std::string& p) const {
        if (auto* v = member(o, k, p)) number(*v, sub(p, k));
    }
    // Fixed-length number array (matrix 16, translation 3, colour 3/4, ...).
    void numbers(const json& o, const char* k, const std::string& p, std::size_t lo, std::size_t hi) const {
        auto* v = member(o, k, p);
        if (!v) return;
        std::string q = sub(p, k);
        expectArray(*v, q);
        if (v->size() < lo || v->size() > hi)
            fail(q, "expected " + (lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi)) +
                        " numbers, found " + std::to_string(v->size()));
        for (std::size_t i = 0; i < v->size(); ++i) number((*v)[i], at(q, i));
    }

    std::size_t arraySize(const char* top) const {
        auto it = doc_.find(top);
        return it != doc_.end() && it->is_array() ? it->size() : 0;
    }
    // An index into a top-level array: a non-negative integer below its size.
    void index(const json& v, const std::string& p, const char* top) const {
        std::size_t n = arraySize(top);
        std::string range = n == 0 ? std::string("the file has no ") + top
                                   : std::string("0..") + std::to_string(n - 1);
        if (!v.is_number() || v.get<double>() != std::floor(v.get<double>()) || v.get<double>() < 0 ||
            v.get<double>() >= double(n))
            fail(p, std::string("expected an index into ") + top + " (" + range + "), found " + text(v));
    }
    void indexArray(const json& v, const std::string& p, const char* top, bool unique, bool nonEmpty) const {
        expectArray(v, p);
        if (nonEmpty && v.empty()) fail(p, "must not be empty");
        std::set<double> seen;
        for (std::size_t i = 0; i < v.size(); ++i) {
            index(v[i], at(p, i), top);
            if (unique && !seen.insert(v[i].get<double>()).second)
                fail(at(p, i), "lists " + text(v[i]) + " a second time (the entries must be unique)");
        }
    }

    // "extensions": an object of objects; "extras": anything; "name": string.
    void extensions(const json& o, const std::string& p) const {
        auto* e = member(o, "extensions", p);
        if (!e) return;
        std::string q = sub(p, "extensions");
        expectObject(*e, q);
        for (auto it = e->begin(); it != e->end(); ++it) expectObject(it.value(), sub(q, it.key()));
    }
    const json* extension(const json& o, const char* name, const std::string& p) const {
        auto* e = member(o, "extensions", p);
        if (!e || !e->is_object()) return nullptr;
        auto it = e->find(name);
        return it == e->end() ? nullptr : &*it;
    }
    void common(const json& o, const std::string& p) const {
        stringMember(o, "name", p);
        extensions(o, p);
    }

    void topArray(const char* k, const std::function<void(const json&, const std::string&)>& each) const {
        auto* v = member(doc_, k, "");
        if (!v) return;
        expectArray(*v, k);
        for (std::size_t i = 0; i < v->size(); ++i) {
            std::string p = at(k, i);
            expectObject((*v)[i], p);
            each((*v)[i], p);
        }
    }

    void node(const json& n, const std::string& p) const {
        if (auto* c = member(n, "camera", p)) index(*c, p + ".camera", "cameras");
        if (auto* c = member(n, "children", p)) indexArray(*c, p + ".children", "nodes", true, true);
        if (auto* s = member(n, "skin", p)) index(*s, p + ".skin", "skins");
        if (auto* m = member(n, "mesh", p)) index(*m, p + ".mesh", "meshes");
        numbers(n, "matrix", p, 16, 16);
        numbers(n, "rotation", p, 4, 4);
        numbers(n, "scale", p, 3, 3);
        numbers(n, "translation", p, 3, 3);
        if (auto* w = member(n, "weights", p)) {
            expectArray(*w, p + ".weights");
            for (std::size_t i = 0; i < w->size(); ++i) number((*w)[i], at(p + ".weights", i));
        }
        common(n, p);
        if (auto* l = extension(n, "KHR_lights_punctual", p)) {
            std::string q = p + ".extensions.KHR_lights_punctual";
            const json* lights = nullptr;
            if (auto* e = extension(doc_, "KHR_lights_punctual", ""); e && e->is_object())
                if (auto it = e->find("lights"); it != e->end() && it->is_array()) lights = &*it;
            const json& li = required(*l, "light", q);
            std::size_t n2 = lights ? lights->size() : 0;
            if (!li.is_number() || li.get<double>() != std::floor(li.get<double>()) || li.get<double>() < 0 ||
                li.get<double>() >= double(n2))
                fail(q + ".light", "expected an index into extensions.KHR_lights_punctual.lights (" +
                                       (n2 ? "0.." + std::to_string(n2 - 1) : std::string("the file defines none")) +
                                       "), found " + text(li));
        }
    }

    // glTF 2.0, "Nodes and Hierarchy": the hierarchy is a set of disjoint
    // strict trees; no node may be a direct descendant of more than one node.
    void checkTrees() const {
        auto* nodes = member(doc_, "nodes", "");
        if (!nodes) return;
        std::vector<long long> parent(nodes->size(), -1);
        for (std::size_t i = 0; i < nodes->size(); ++i) {
            auto it = (*nodes)[i].find("children");
            if (it == (*nodes)[i].end()) continue;
            for (std::size_t k = 0; k < it->size(); ++k) {
                auto c = std::size_t((*it)[k].get<double>());
                if (parent[c] != -1)
                    fail(at(at("nodes", i) + ".children", k),
                         "node " + std::to_string(c) + " is already a child of node " + std::to_string(parent[c]) +
                             " (glTF node hierarchies are disjoint trees: no node has two parents)");
                if (c == i) fail(at(at("nodes", i) + ".children", k), "a node cannot be its own child");
                parent[c] = (long long)i;
            }
        }
    }

    void mesh(const json& m, const std::string& p) const {
        const json& prims = required(m, "primitives", p);
        expectArray(prims, p + ".primitives");
        if (prims.empty()) fail(p + ".primitives", "must not be empty");
        for (std::size_t i = 0; i < prims.size(); ++i) {
            std::string q = at(p + ".primitives", i);
            const json& pr = prims[i];
            expectObject(pr, q);
            const json& attrs = required(pr, "attributes", q);
            expectObject(attrs, q + ".attributes");
            for (auto it = attrs.begin(); it != attrs.end(); ++it)
                index(it.value(), q + ".attributes." + it.key(), "accessors");
            if (auto* x = member(pr, "indices", q)) index(*x, q + ".indices", "accessors");
            if (auto* x = member(pr, "material", q)) index(*x, q + ".material", "materials");
            if (auto* x = member(pr, "mode", q)) {
                integer(*x, q + ".mode", 0);
                if (x->get<double>() > 6) fail(q + ".mode", "expected a primitive mode 0..6, found " + text(*x));
            }
            if (auto* t = member(pr, "targets", q)) {
                expectArray(*t, q + ".targets");
                for (std::size_t k = 0; k < t->size(); ++k) {
                    expectObject((*t)[k], at(q + ".targets", k));
                    for (auto it = (*t)[k].begin(); it != (*t)[k].end(); ++it)
                        index(it.value(), at(q + ".targets", k) + "." + it.key(), "accessors");
                }
            }
            common(pr, q);
        }
        if (auto* w = member(m, "weights", p)) {
            expectArray(*w, p + ".weights");
            for (std::size_t i = 0; i < w->size(); ++i) number((*w)[i], at(p + ".weights", i));
        }
        common(m, p);
    }

    void accessor(const json& a, const std::string& p) const {
        if (auto* v = member(a, "bufferView", p)) index(*v, p + ".bufferView", "bufferViews");
        integerMember(a, "byteOffset", p, 0);
        const json& ct = required(a, "componentType", p);
        integer(ct, p + ".componentType", 0);
        double c = ct.get<double>();
        if (c != 5120 && c != 5121 && c != 5122 && c != 5123 && c != 5125 && c != 5126)
            fail(p + ".componentType", "expected 5120, 5121, 5122, 5123, 5125 or 5126, found " + text(ct));
        boolMember(a, "normalized", p);
        integer(required(a, "count", p), p + ".count", 1);
        const json& type = required(a, "type", p);
        expectString(type, p + ".type");
        static const std::set<std::string> types = {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"};
        if (!types.count(type.get<std::string>()))
            fail(p + ".type", "expected SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3 or MAT4, found " + text(type));
        numbers(a, "max", p, 1, 16);
        numbers(a, "min", p, 1, 16);
        if (auto* s = member(a, "sparse", p)) expectObject(*s, p + ".sparse");
        common(a, p);
    }

    void textureInfo(const json& o, const char* k, const std::string& p) const {
        auto* t = member(o, k, p);
        if (!t) return;
        std::string q = sub(p, k);
        expectObject(*t, q);
        index(required(*t, "index", q), q + ".index", "textures");
        integerMember(*t, "texCoord", q, 0);
        numberMember(*t, "scale", q);
        numberMember(*t, "strength", q);
        common(*t, q);
        if (auto* tt = extension(*t, "KHR_texture_transform", q)) {
            std::string r = q + ".extensions.KHR_texture_transform";
            numbers(*tt, "offset", r, 2, 2);
            numbers(*tt, "scale", r, 2, 2);
            numberMember(*tt, "rotation", r);
            integerMember(*tt, "texCoord", r, 0);
        }
    }

    void material(const json& m, const std::string& p) const {
        if (auto* pbr = member(m, "pbrMetallicRoughness", p)) {
            std::string q = p + ".pbrMetallicRoughness";
            expectObject(*pbr, q);
            numbers(*pbr, "baseColorFactor", q, 4, 4);
            textureInfo(*pbr, "baseColorTexture", q);
            numberMember(*pbr, "metallicFactor", q);
            numberMember(*pbr, "roughnessFactor", q);
            textureInfo(*pbr, "metallicRoughnessTexture", q);
            common(*pbr, q);
        }
        textureInfo(m, "normalTexture", p);
        textureInfo(m, "occlusionTexture", p);
        textureInfo(m, "emissiveTexture", p);
        numbers(m, "emissiveFactor", p, 3, 3);
        if (auto* a = member(m, "alphaMode", p)) {
            expectString(*a, p + ".alphaMode");
            std::string s = a->get<std::string>();
            if (s != "OPAQUE" && s != "MASK" && s != "BLEND")
                fail(p + ".alphaMode", "expected OPAQUE, MASK or BLEND, found " + text(*a));
        }
        numberMember(m, "alphaCutoff", p);
        boolMember(m, "doubleSided", p);
        common(m, p);
        if (auto* e = extension(m, "KHR_materials_emissive_strength", p))
            numberMember(*e, "emissiveStrength", p + ".extensions.KHR_materials_emissive_strength");
    }

    void camera(const json& c, const std::string& p) const {
        const json& type = required(c, "type", p);
        expectString(type, p + ".type");
        if (auto* v = member(c, "perspective", p)) {
            std::string q = p + ".perspective";
            expectObject(*v, q);
            number(required(*v, "yfov", q), q + ".yfov");
            number(required(*v, "znear", q), q + ".znear");
            numberMember(*v, "zfar", q);
            numberMember(*v, "aspectRatio", q);
            common(*v, q);
        } else if (type.get<std::string>() == "perspective") {
            fail(p, "a perspective camera needs a \"perspective\" object");
        }
        if (auto* v = member(c, "orthographic", p)) {
            std::string q = p + ".orthographic";
            expectObject(*v, q);
            for (const char* k : {"xmag", "ymag", "zfar", "znear"}) number(required(*v, k, q), sub(q, k));
        }
        common(c, p);
    }

    void light(const json& l, const std::string& p) const {
        expectObject(l, p);
        expectString(required(l, "type", p), p + ".type");
        numbers(l, "color", p, 3, 3);
        numberMember(l, "intensity", p);
        numberMember(l, "range", p);
        if (auto* s = member(l, "spot", p)) {
            expectObject(*s, p + ".spot");
            numberMember(*s, "innerConeAngle", p + ".spot");
            numberMember(*s, "outerConeAngle", p + ".spot");
        }
        common(l, p);
    }
};

}  // namespace

void checkGltfSchema(const nlohmann::json& doc, const std::string& file) {
    if (auto it = doc.find("asset"); it != doc.end() && it->is_object())
        for (const char* k : {"version", "generator", "copyright", "minVersion"})
            if (auto v = it->find(k); v != it->end() && !v->is_string())
                throw SceneError(file + ": asset." + k + ": expected a string");
    Checker(doc, file).run();
}

}  // namespace rtgi
