#pragma once
// Read-back of textures and image files: PNG (LDR, stb) and PFM (float RGB).
#include "gl/resources.h"

#include <string>
#include <vector>

namespace rtgi {

struct FloatImage {
    int width = 0, height = 0, channels = 4;
    std::vector<float> data;  // row 0 = bottom (GL convention)
    float at(int x, int y, int c) const { return data[std::size_t((y * width + x) * channels + c)]; }
};

// Level 0 of a 2D texture (or one z slice of a 3D texture) as floats.
FloatImage readTexture(const gl::Texture& tex, int slice = -1);
// PNG from an RGBA8 (or float in [0,1]) image, flipped so row 0 is the top.
void writePng(const std::string& path, const FloatImage& img, float scale = 1.0f, bool encodeSrgb = false);
void writePfm(const std::string& path, const FloatImage& img);
FloatImage readPfm(const std::string& path);
// Reads PNG/JPG/... as linear [0,1] floats (no sRGB decoding), row 0 = bottom.
FloatImage readImage(const std::string& path);

}  // namespace rtgi
