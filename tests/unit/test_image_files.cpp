// OpenEXR output and input (gl/image_files.h): float round trip bit-exact,
// half rounding against known binary16 values, single-channel files, errors.
#include "gl/image_files.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

using namespace rtgi;

namespace {

std::string tempFile(const std::string& name) {
    auto dir = std::filesystem::temp_directory_path() / "rtgi-exr-test";
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}

FloatImage randomImage(int w, int h, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> mant(-1.0f, 1.0f);
    std::uniform_int_distribution<int> expo(-30, 30);
    FloatImage img;
    img.width = w;
    img.height = h;
    img.channels = 4;
    img.data.resize(std::size_t(w) * std::size_t(h) * 4);
    for (auto& v : img.data) v = std::ldexp(mant(rng), expo(rng));  // many magnitudes, both signs
    img.data[0] = 0.0f;
    img.data[1] = -0.0f;
    img.data[2] = std::numeric_limits<float>::denorm_min();
    img.data[3] = std::numeric_limits<float>::max();
    return img;
}

}  // namespace

TEST_CASE("EXR float round trip is bit-exact (rgba, rgb and one channel), rows keep their order") {
    FloatImage img = randomImage(37, 23, 7);  // odd sizes: no row/column symmetry hides a flip
    for (int channels : {4, 3, 1}) {
        INFO("channels " << channels);
        const std::string path = tempFile("float" + std::to_string(channels) + ".exr");
        writeExr(path, img, channels, ExrPixel::Float);
        FloatImage back = readImageFile(path);
        REQUIRE(back.width == img.width);
        REQUIRE(back.height == img.height);
        std::size_t mismatches = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x)
                for (int c = 0; c < 4; ++c) {
                    // One channel comes back as grey (r = g = b); alpha 1 when not written.
                    float want = channels == 1 ? (c < 3 ? img.at(x, y, 0) : 1.0f)
                                               : (c < channels ? img.at(x, y, c) : 1.0f);
                    mismatches += bits(back.at(x, y, c)) != bits(want);
                }
        CHECK(mismatches == 0u);
    }
}

TEST_CASE("EXR half output rounds to the nearest binary16 value") {
    // Known binary16 values (IEEE 754): exact ones survive, others round to
    // nearest even, overflow gives inf, below half the smallest subnormal 0.
    const float in[] = {1.0f, 0.5f, -2.0f, 65504.0f, 1.0f / 3.0f, 1e-8f, 5.9604645e-8f, 70000.0f, 1.0009765625f,
                        1.00048828125f /* halfway between 1 and 1+2^-10: ties to even -> 1 */};
    const float want[] = {1.0f, 0.5f, -2.0f, 65504.0f, 0.333251953125f, 0.0f, 5.9604645e-8f,
                          std::numeric_limits<float>::infinity(), 1.0009765625f, 1.0f};
    const int n = int(sizeof(in) / sizeof(in[0]));
    FloatImage img;
    img.width = n;
    img.height = 1;
    img.channels = 4;
    img.data.assign(std::size_t(n) * 4, 0.0f);
    for (int i = 0; i < n; ++i) img.data[std::size_t(i) * 4] = img.data[std::size_t(i) * 4 + 1] = img.data[std::size_t(i) * 4 + 2] = in[i];
    const std::string path = tempFile("half.exr");
    writeExr(path, img, 3, ExrPixel::Half);
    FloatImage back = readExr(path);
    for (int i = 0; i < n; ++i) {
        INFO("value " << in[i]);
        CHECK(back.at(i, 0, 0) == want[i]);
        CHECK(back.at(i, 0, 2) == want[i]);
    }
    // A half file is smaller than the float one of the same image.
    FloatImage big = randomImage(64, 64, 3);
    writeExr(tempFile("h.exr"), big, 3, ExrPixel::Half);
    writeExr(tempFile("f.exr"), big, 3, ExrPixel::Float);
    CHECK(std::filesystem::file_size(tempFile("h.exr")) < std::filesystem::file_size(tempFile("f.exr")));
}

TEST_CASE("EXR and PFM of the same float image read back equal; bad files give one sentence") {
    FloatImage img = randomImage(16, 9, 11);
    writeExr(tempFile("same.exr"), img, 3, ExrPixel::Float);
    writePfm(tempFile("same.pfm"), img);
    FloatImage a = readImageFile(tempFile("same.exr")), b = readImageFile(tempFile("same.pfm"));
    REQUIRE(a.data.size() == b.data.size());
    CHECK(std::memcmp(a.data.data(), b.data.data(), a.data.size() * 4) == 0);
    CHECK(isHdrImageFile("x.EXR"));
    CHECK(isHdrImageFile("x.pfm"));
    CHECK_FALSE(isHdrImageFile("x.png"));
    std::ofstream(tempFile("bad.exr")) << "not an exr";
    try {
        readImageFile(tempFile("bad.exr"));
        FAIL("no error");
    } catch (const std::runtime_error& e) {
        CHECK(std::string(e.what()).find("bad.exr") != std::string::npos);
    }
}
