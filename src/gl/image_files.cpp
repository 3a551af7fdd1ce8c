#include "gl/image_files.h"

#include "gl/input_files.h"
#include "gl/output_files.h"

#include <tinyexr.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <filesystem>
#include <memory>
#include <stdexcept>

namespace rtgi {

namespace {

std::string extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

std::string exrError(const std::string& path, const char* what, const char* err) {
    std::string msg = path + ": " + what + (err ? std::string(" (") + err + ")" : std::string());
    if (err) FreeEXRErrorMessage(err);
    return msg;
}

// IEEE 754 binary32 -> binary16, round to nearest even; overflow -> inf,
// NaN stays NaN (the EXR half type is exactly this format).
std::uint16_t toHalf(float f) {
    std::uint32_t x;
    std::memcpy(&x, &f, 4);
    const std::uint32_t sign = (x >> 16) & 0x8000u;
    const std::uint32_t absx = x & 0x7fffffffu;
    if (absx >= 0x7f800000u) return std::uint16_t(sign | 0x7c00u | (absx > 0x7f800000u ? 0x200u : 0u));
    if (absx >= 0x477ff000u) return std::uint16_t(sign | 0x7c00u);  // rounds to >= 65520: inf
    if (absx < 0x38800000u) {  // subnormal half (or zero)
        if (absx < 0x33000000u) return std::uint16_t(sign);  // < 2^-25: rounds to 0
        const std::uint32_t mant = (absx & 0x7fffffu) | 0x800000u;
        const int shift = 126 - int(absx >> 23);  // 14..24
        std::uint32_t h = mant >> shift;
        const std::uint32_t rem = mant & ((1u << shift) - 1u), halfway = 1u << (shift - 1);
        if (rem > halfway || (rem == halfway && (h & 1u))) ++h;
        return std::uint16_t(sign | h);
    }
    std::uint32_t h = ((absx - 0x38000000u) >> 13);
    const std::uint32_t rem = absx & 0x1fffu;
    if (rem > 0x1000u || (rem == 0x1000u && (h & 1u))) ++h;
    return std::uint16_t(sign | h);
}

}  // namespace

void writeExr(const std::string& path, const FloatImage& img, int channels, ExrPixel pixel) {
    if (channels != 1 && channels != 3 && channels != 4)
        throw std::runtime_error(path + ": EXR output takes 1, 3 or 4 channels");
    if (img.channels < channels) throw std::runtime_error(path + ": the image has fewer channels than requested");
    const std::size_t n = std::size_t(img.width) * std::size_t(img.height);
    // Channels in the file's conventional (alphabetical) order.
    const char* names1[] = {"Y"};
    const char* names3[] = {"B", "G", "R"};
    const char* names4[] = {"A", "B", "G", "R"};
    const int src1[] = {0}, src3[] = {2, 1, 0}, src4[] = {3, 2, 1, 0};
    const char* const* names = channels == 1 ? names1 : channels == 3 ? names3 : names4;
    const int* src = channels == 1 ? src1 : channels == 3 ? src3 : src4;

    const bool half = pixel == ExrPixel::Half;
    const std::size_t bytes = half ? 2 : 4;
    std::vector<std::vector<unsigned char>> planes(std::size_t(channels), std::vector<unsigned char>(n * bytes));
    for (int c = 0; c < channels; ++c)
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                // EXR rows go top to bottom; FloatImage row 0 is the bottom.
                const std::size_t dst = std::size_t(img.height - 1 - y) * std::size_t(img.width) + std::size_t(x);
                const float v = img.at(x, y, src[c]);
                if (half) {
                    std::uint16_t h = toHalf(v);
                    std::memcpy(&planes[std::size_t(c)][dst * 2], &h, 2);
                } else {
                    std::memcpy(&planes[std::size_t(c)][dst * 4], &v, 4);
                }
            }
    std::vector<unsigned char*> ptrs;
    for (auto& p : planes) ptrs.push_back(p.data());

    EXRHeader header;
    InitEXRHeader(&header);
    EXRImage image;
    InitEXRImage(&image);
    image.num_channels = channels;
    image.images = ptrs.data();
    image.width = img.width;
    image.height = img.height;
    std::vector<EXRChannelInfo> info(static_cast<std::size_t>(channels));
    std::vector<int> types(std::size_t(channels), half ? TINYEXR_PIXELTYPE_HALF : TINYEXR_PIXELTYPE_FLOAT);
    for (int c = 0; c < channels; ++c) {
        std::memset(&info[std::size_t(c)], 0, sizeof(EXRChannelInfo));
        std::strncpy(info[std::size_t(c)].name, names[c], 255);
    }
    header.num_channels = channels;
    header.channels = info.data();
    header.pixel_types = types.data();            // what the planes hold
    header.requested_pixel_types = types.data();  // what the file stores
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
    // Encoded in memory, then written like every result file: temporary file,
    // fsync, rename (gl/output_files.h), so a kill never leaves half an EXR.
    const char* err = nullptr;
    unsigned char* mem = nullptr;
    const std::size_t size = SaveEXRImageToMemory(&image, &header, &mem, &err);
    if (size == 0 || !mem) throw std::runtime_error(exrError(path, "could not encode EXR", err));
    std::unique_ptr<unsigned char, void (*)(void*)> memGuard(mem, std::free);
    writeFileAtomic(path, std::string_view(reinterpret_cast<const char*>(mem), size));
}

FloatImage readExr(const std::string& path) {
    std::vector<unsigned char> bytes;
    std::string why;
    if (!readInputBytes(path, InputKind::Image, bytes, why)) throw InputError(escapeControl(path) + ": " + why);
    const std::string name = escapeControl(path);
    EXRVersion version;
    if (ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()) != TINYEXR_SUCCESS)
        throw std::runtime_error(name + ": not an OpenEXR file");
    if (version.multipart || version.non_image)
        throw std::runtime_error(name + ": multi-part and deep EXR files are not supported");
    EXRHeader header;
    InitEXRHeader(&header);
    const char* err = nullptr;
    if (ParseEXRHeaderFromMemory(&header, &version, bytes.data(), bytes.size(), &err) != TINYEXR_SUCCESS)
        throw std::runtime_error(exrError(name, "cannot read the EXR header", err));
    std::unique_ptr<EXRHeader, int (*)(EXRHeader*)> headerGuard(&header, FreeEXRHeader);
    if (header.tiled) throw std::runtime_error(name + ": tiled EXR files are not supported (write scanlines)");
    for (int c = 0; c < header.num_channels; ++c)
        if (header.pixel_types[c] == TINYEXR_PIXELTYPE_HALF) header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
    EXRImage image;
    InitEXRImage(&image);
    if (LoadEXRImageFromMemory(&image, &header, bytes.data(), bytes.size(), &err) != TINYEXR_SUCCESS)
        throw std::runtime_error(exrError(name, "cannot read the EXR pixels", err));
    std::unique_ptr<EXRImage, int (*)(EXRImage*)> imageGuard(&image, FreeEXRImage);

    int idx[4] = {-1, -1, -1, -1};
    for (int c = 0; c < header.num_channels; ++c) {
        std::string nm = header.channels[c].name;
        if (nm == "R") idx[0] = c;
        else if (nm == "G") idx[1] = c;
        else if (nm == "B") idx[2] = c;
        else if (nm == "A") idx[3] = c;
    }
    if (idx[0] < 0 && idx[1] < 0 && idx[2] < 0) {
        if (header.num_channels != 1)
            throw std::runtime_error(path + ": EXR without R, G, B channels and more than one channel");
        idx[0] = idx[1] = idx[2] = 0;  // one channel (Y, or any name): grey
    }
    FloatImage img;
    img.width = image.width;
    img.height = image.height;
    img.channels = 4;
    img.data.assign(std::size_t(img.width) * std::size_t(img.height) * 4, 0.0f);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const std::size_t s = std::size_t(img.height - 1 - y) * std::size_t(img.width) + std::size_t(x);
            for (int c = 0; c < 4; ++c) {
                float v = c == 3 ? 1.0f : 0.0f;
                if (idx[c] >= 0) {
                    const int k = idx[c];
                    const unsigned char* plane = image.images[k];
                    if (header.requested_pixel_types[k] == TINYEXR_PIXELTYPE_UINT) {
                        unsigned u;
                        std::memcpy(&u, plane + s * 4, 4);
                        v = float(u);
                    } else {
                        std::memcpy(&v, plane + s * 4, 4);
                    }
                }
                img.data[(std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 4 + std::size_t(c)] = v;
            }
        }
    return img;
}

FloatImage readImageFile(const std::string& path) {
    const std::string ext = extension(path);
    if (ext == ".pfm") return readPfm(path);
    if (ext == ".exr") return readExr(path);
    return readImage(path);
}

bool isHdrImageFile(const std::string& path) {
    const std::string ext = extension(path);
    return ext == ".pfm" || ext == ".exr";
}

}  // namespace rtgi
