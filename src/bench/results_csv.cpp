#include "bench/results_csv.h"

#include "render/settings.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace rtgi {

namespace {

// Error metrics with a column each; a run without the metric leaves the cell
// empty (NaN in pandas), so the column stays numeric.
const char* const kErrorColumns[] = {
    "rmse",          "mae",           "bias",           "psnr",          "ssim",
    "rel_rmse",      "pixels",        "interior.rmse",  "interior.mae",  "interior.bias",
    "interior.psnr", "interior.rel_rmse", "interior.pixels", "glossy.rmse", "glossy.mae",
    "glossy.bias",   "glossy.psnr",   "glossy.rel_rmse", "glossy.pixels", "reference.spp",
    "reference.mean_stderr", "reference.from_cache", "heatmap_max",
    // issue 21: the error corrected for the reference's noise, its 95 % interval
    "rmse_debiased", "rmse_ci95.0", "rmse_ci95.1", "interior.rmse_debiased", "interior.rmse_ci95.0",
    "interior.rmse_ci95.1", "reference.noise_ratio",
    // issue 22: 1 − rmse / rmse without the technique (> 0: it helps)
    "gain.lpv.gain", "gain.lpv.interior.gain", "gain.lpv.rmse_without", "gain.nearfield.gain",
    "gain.nearfield.interior.gain"};

std::string number(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

// One cell: numbers bare, booleans as 0/1, strings quoted, null/missing empty.
std::string cell(const nlohmann::json& v) {
    if (v.is_null()) return "";
    if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
    if (v.is_number_integer()) return std::to_string(v.get<long long>());
    if (v.is_number_unsigned()) return std::to_string(v.get<unsigned long long>());
    if (v.is_number()) return number(v.get<double>());
    if (v.is_string()) {
        const std::string s = v.get<std::string>();
        if (s == "inf") return "inf";  // PSNR of identical images, written as a string in JSON
        return csvQuote(s);
    }
    return csvQuote(v.dump());
}

const nlohmann::json* path(const nlohmann::json& j, const std::string& dotted) {
    const nlohmann::json* cur = &j;
    std::size_t start = 0;
    while (true) {
        std::size_t dot = dotted.find('.', start);
        std::string part = dotted.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
        if (cur->is_array()) {  // "rmse_ci95.0": an element of an array
            char* end = nullptr;
            const unsigned long k = std::strtoul(part.c_str(), &end, 10);
            if (part.empty() || *end != '\0' || k >= cur->size()) return nullptr;
            cur = &(*cur)[k];
        } else {
            if (!cur->is_object() || !cur->contains(part)) return nullptr;
            cur = &(*cur)[part];
        }
        if (dot == std::string::npos) return cur;
        start = dot + 1;
    }
}

std::string at(const nlohmann::json& j, const std::string& dotted) {
    const nlohmann::json* v = path(j, dotted);
    return v ? cell(*v) : "";
}

}  // namespace

nlohmann::json typedValue(const std::string& text) {
    if (text.empty()) return text;
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (*end != '\0' || !std::isfinite(x) || text.find_first_of("xX") != std::string::npos) return text;  // 0x10
    if (text.find_first_of(".eE") == std::string::npos && std::abs(x) < 9.0e15) return (long long)(x);
    return x;
}

std::string csvQuote(const std::string& s) {
    std::string o = "\"";
    for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
    return o + "\"";
}

std::string resultsCsvHeader() {
    std::string h = "config_id,sweep,scene_label,scene,resolution,width,height,frames,warmup,timer,device,version,"
                    "pass,median_ms,min_ms,max_ms,mean_ms,dispatches,total_ms,memory_bytes";
    for (auto& k : settingKeys()) h += "," + k.key;
    h += ",error.kind";
    for (const char* e : kErrorColumns) h += std::string(",error.") + e;
    return h;
}

std::vector<std::string> resultsCsvRows(const nlohmann::json& r) {
    if (r.contains("failed") || !r.contains("passes")) return {};
    std::string run;
    run += at(r, "sweep.id") + "," + at(r, "sweep.name") + "," + at(r, "sweep.scene_label") + "," + at(r, "scene") +
           "," + at(r, "resolution") + ",";
    int w = 0, h = 0;
    if (r.contains("resolution") && r["resolution"].is_string() &&
        std::sscanf(r["resolution"].get<std::string>().c_str(), "%dx%d", &w, &h) == 2)
        run += std::to_string(w) + "," + std::to_string(h) + ",";
    else
        run += ",,";
    run += at(r, "frames") + "," + at(r, "warmup") + "," + at(r, "timer") + "," + at(r, "device") + "," +
           at(r, "version");
    std::string tail;
    for (auto& k : settingKeys()) {
        tail += ",";
        if (r.contains("config") && r["config"].contains(k.key)) {
            const auto& cv = r["config"][k.key];
            // Older lines hold every value as a string: type it here as well.
            tail += cv.is_string() ? cell(typedValue(cv.get<std::string>())) : cell(cv);
        }
    }
    tail += "," + at(r, "error.kind");
    for (const char* e : kErrorColumns) tail += "," + at(r, std::string("error.") + e);

    std::vector<std::string> rows;
    for (auto& p : r["passes"]) {
        std::string row = run + "," + cell(p["name"]) + "," + at(p, "gpu_ms.median") + "," + at(p, "gpu_ms.min") + "," +
                          at(p, "gpu_ms.max") + "," + at(p, "gpu_ms.mean") + "," + at(p, "dispatches") + "," +
                          at(r, "total_ms") + "," + at(r, "memory_bytes.total") + tail;
        rows.push_back(row);
    }
    return rows;
}

}  // namespace rtgi
