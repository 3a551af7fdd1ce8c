#include "gl/image_io.h"

#include "gl/output_files.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
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
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error(path + ": cannot open");
    std::string magic;
    FloatImage img;
    double scale = 0;
    f >> magic >> img.width >> img.height >> scale;
    f.get();
    if ((magic != "PF" && magic != "Pf") || img.width <= 0 || img.height <= 0 || scale == 0 ||
        img.width > 65536 || img.height > 65536)
        throw std::runtime_error(path + ": not a valid PFM file");
    if (scale > 0) throw std::runtime_error(path + ": big-endian PFM is not supported");
    int ch = magic == "PF" ? 3 : 1;
    std::vector<float> raw(std::size_t(img.width) * std::size_t(img.height) * std::size_t(ch));
    f.read(reinterpret_cast<char*>(raw.data()), std::streamsize(raw.size() * 4));
    if (!f) throw std::runtime_error(path + ": PFM data is truncated");
    img.channels = 4;
    img.data.assign(std::size_t(img.width) * std::size_t(img.height) * 4, 1.0f);
    for (std::size_t i = 0; i < std::size_t(img.width) * std::size_t(img.height); ++i)
        for (int c = 0; c < 3; ++c) img.data[i * 4 + std::size_t(c)] = raw[i * std::size_t(ch) + std::size_t(ch == 3 ? c : 0)];
    return img;
}

FloatImage readImage(const std::string& path) {
    if (path.size() > 4 && path.substr(path.size() - 4) == ".pfm") return readPfm(path);
    int w = 0, h = 0, n = 0;
    unsigned char* px = stbi_load(path.c_str(), &w, &h, &n, 4);
    if (!px) throw std::runtime_error(path + ": cannot read image (" + std::string(stbi_failure_reason()) + ")");
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
