#include "gl/image_io.h"

#include "gl/input_files.h"
#include "gl/output_files.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace rtgi {

FloatImage readTexture(const gl::Texture& tex, int slice) {
    FloatImage img;
    img.width = tex.width();
    img.height = tex.height();
    img.channels = 4;
    img.data.resize(std::size_t(img.width) * std::size_t(img.height) * 4);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    bool depth = tex.format() == GL_DEPTH_COMPONENT32F || tex.format() == GL_DEPTH_COMPONENT24 ||
                 tex.format() == GL_DEPTH_COMPONENT16;
    if (depth) {
        std::vector<float> d(std::size_t(img.width) * std::size_t(img.height));
        glGetTextureImage(tex.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(d.size() * 4), d.data());
        for (std::size_t i = 0; i < d.size(); ++i) img.data[i * 4] = img.data[i * 4 + 1] = img.data[i * 4 + 2] = d[i];
        return img;
    }
    if (slice >= 0 || tex.desc().target == GL_TEXTURE_3D || tex.desc().target == GL_TEXTURE_2D_ARRAY) {
        int z = std::max(slice, 0);
        glGetTextureSubImage(tex.id(), 0, 0, 0, z, img.width, img.height, 1, GL_RGBA, GL_FLOAT,
                             GLsizei(img.data.size() * 4), img.data.data());
    } else {
        glGetTextureImage(tex.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(img.data.size() * 4), img.data.data());
    }
    // Single/dual-channel formats read back with a = 1 and missing channels 0.
    return img;
}

void writePng(const std::string& path, const FloatImage& img, float scale, bool encodeSrgb) {
    std::vector<unsigned char> px(std::size_t(img.width) * std::size_t(img.height) * 4);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 4; ++c) {
                float v = c < img.channels ? img.at(x, y, c) : 1.0f;
                if (c < 3) v *= scale;
                if (!std::isfinite(v)) v = c == 1 ? 0.0f : 1.0f;  // magenta marks non-finite values
                v = std::clamp(v, 0.0f, 1.0f);
                if (encodeSrgb && c < 3) v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
                if (c == 3) v = 1.0f;
                px[std::size_t(((img.height - 1 - y) * img.width + x) * 4 + c)] = (unsigned char)(v * 255.0f + 0.5f);
            }
    // Encoded in memory, then written atomically (gl/output_files.h).
    std::string png;
    auto append = [](void* ctx, void* data, int size) {
        static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), std::size_t(size));
    };
    if (!stbi_write_png_to_func(append, &png, img.width, img.height, 4, px.data(), img.width * 4))
        throw OutputError(path + ": the PNG could not be encoded");
    writeFileAtomic(path, png);
}

void writePfm(const std::string& path, const FloatImage& img) {
    // little endian, rows bottom to top; written atomically (gl/output_files.h)
    std::string out = "PF\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n-1.0\n";
    std::vector<float> row(std::size_t(img.width) * 3);
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) row[std::size_t(x * 3 + c)] = c < img.channels ? img.at(x, y, c) : 0.0f;
        out.append(reinterpret_cast<const char*>(row.data()), row.size() * 4);
    }
    writeFileAtomic(path, out);
}

FloatImage readPfm(const std::string& path) {
    const std::string bytes = readInputFile(path, InputKind::Image);  // gl/input_files.h: bounded, no FIFOs
    const std::string name = escapeControl(path);
    // Header: "PF" or "Pf", width, height, scale, separated by whitespace, one
    // whitespace byte before the raw floats.
    std::size_t pos = 0;
    auto token = [&]() {
        while (pos < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[pos]))) ++pos;
        std::size_t start = pos;
        while (pos < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[pos])) && pos - start < 32) ++pos;
        return bytes.substr(start, pos - start);
    };
    FloatImage img;
    const std::string magic = token(), w = token(), h = token(), sc = token();
    char* end = nullptr;
    const long wl = std::strtol(w.c_str(), &end, 10);
    const bool wOk = !w.empty() && *end == 0;
    const long hl = std::strtol(h.c_str(), &end, 10);
    const bool hOk = !h.empty() && *end == 0;
    const double scale = std::strtod(sc.c_str(), &end);
    const bool sOk = !sc.empty() && *end == 0;
    if ((magic != "PF" && magic != "Pf") || !wOk || !hOk || !sOk || wl <= 0 || hl <= 0 || scale == 0 ||
        wl > 65536 || hl > 65536 || pos >= bytes.size())
        throw std::runtime_error(name + ": not a valid PFM file");
    if (scale > 0) throw std::runtime_error(name + ": big-endian PFM is not supported");
    ++pos;  // the single whitespace byte after the scale
    img.width = int(wl);
    img.height = int(hl);
    const int ch = magic == "PF" ? 3 : 1;
    std::vector<float> raw(std::size_t(img.width) * std::size_t(img.height) * std::size_t(ch));
    if (bytes.size() - pos < raw.size() * 4) throw std::runtime_error(name + ": PFM data is truncated");
    std::memcpy(raw.data(), bytes.data() + pos, raw.size() * 4);
    img.channels = 4;
    img.data.assign(std::size_t(img.width) * std::size_t(img.height) * 4, 1.0f);
    for (std::size_t i = 0; i < std::size_t(img.width) * std::size_t(img.height); ++i)
        for (int c = 0; c < 3; ++c) img.data[i * 4 + std::size_t(c)] = raw[i * std::size_t(ch) + std::size_t(ch == 3 ? c : 0)];
    return img;
}

FloatImage readImage(const std::string& path) {
    if (path.size() > 4 && path.substr(path.size() - 4) == ".pfm") return readPfm(path);
    const std::string bytes = readInputFile(path, InputKind::Image);
    const std::string name = escapeControl(path);
    if (bytes.size() > std::size_t(INT_MAX)) throw std::runtime_error(name + ": image file is too large for the PNG/JPEG decoder (2 GiB)");
    int w = 0, h = 0, n = 0;
    unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()), int(bytes.size()), &w,
                                              &h, &n, 4);
    if (!px) throw std::runtime_error(name + ": cannot read image (" + std::string(stbi_failure_reason()) + ")");
    FloatImage img;
    img.width = w;
    img.height = h;
    img.data.resize(std::size_t(w) * std::size_t(h) * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 4; ++c)
                img.data[std::size_t(((h - 1 - y) * w + x) * 4 + c)] = px[(y * w + x) * 4 + c] / 255.0f;
    stbi_image_free(px);
    return img;
}

}  // namespace rtgi
