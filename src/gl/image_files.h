#pragma once
// OpenEXR files (every HDR image: final.exr, references, heat-map inputs) and
// reading any supported image file by its extension. EXR goes through
// tinyexr (Debian libtinyexr-dev, compiled into the binary with zlib, so the
// carried headless binaries need no OpenEXR shared libraries; docs/images.md).
#include "gl/image_io.h"

#include <string>

namespace rtgi {

enum class ExrPixel { Half, Float };

// Writes the first `channels` channels of `img` (1: a single "Y" channel,
// 3: R,G,B, 4: R,G,B,A) as a ZIP-compressed scanline EXR, top row first.
// Half: 16-bit floats (a quarter of the file, 11-bit mantissa, max 65504);
// Float: 32-bit, bit-exact. Throws std::runtime_error naming the file.
void writeExr(const std::string& path, const FloatImage& img, int channels, ExrPixel pixel);
// Reads a scanline EXR (any compression tinyexr supports; half, float or
// uint channels) into RGBA floats, row 0 = bottom. R,G,B,A channels by name;
// a single channel (Y, or any other name) fills r = g = b; missing alpha = 1.
FloatImage readExr(const std::string& path);

// .pfm -> readPfm, .exr -> readExr, else PNG/JPG/... (readImage).
FloatImage readImageFile(const std::string& path);
// Whether the extension names a floating-point format (PFM, EXR).
bool isHdrImageFile(const std::string& path);

}  // namespace rtgi
