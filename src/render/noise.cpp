#include "render/noise.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>

namespace rtgi {

std::vector<float> blueNoiseTile(int size, unsigned seed) {
    const int n = size * size;
    const std::size_t count = std::size_t(n);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    std::vector<float> white(std::size_t(n), 0.0f);
    for (auto& w : white) w = uni(rng);
    // Two passes of a periodic separable Gaussian (sigma 1.5 texels) give the
    // low-pass part; white - lowpass is the high-pass (blue) signal [MG16].
    const int radius = 4;
    std::vector<float> kernel;
    for (int i = -radius; i <= radius; ++i) kernel.push_back(std::exp(-float(i * i) / (2.0f * 1.5f * 1.5f)));
    float ksum = std::accumulate(kernel.begin(), kernel.end(), 0.0f);
    auto wrap = [size](int v) { return (v % size + size) % size; };
    std::vector<float> tmp(count), low(count);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            float a = 0;
            for (int i = -radius; i <= radius; ++i) a += kernel[std::size_t(i + radius)] * white[std::size_t(y * size + wrap(x + i))];
            tmp[std::size_t(y * size + x)] = a / ksum;
        }
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            float a = 0;
            for (int i = -radius; i <= radius; ++i) a += kernel[std::size_t(i + radius)] * tmp[std::size_t(wrap(y + i) * size + x)];
            low[std::size_t(y * size + x)] = a / ksum;
        }
    std::vector<int> order(count);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        return white[std::size_t(a)] - low[std::size_t(a)] < white[std::size_t(b)] - low[std::size_t(b)];
    });
    std::vector<float> out(count);
    for (int r = 0; r < n; ++r) out[std::size_t(order[std::size_t(r)])] = (float(r) + 0.5f) / float(n);
    return out;
}

gl::TextureDesc blueNoiseDesc() {
    return {GL_TEXTURE_2D_ARRAY, GL_RGBA8, kBlueNoiseSize, kBlueNoiseSize, kBlueNoiseVariants};
}

const gl::Texture& ensureBlueNoise(FrameResources& res, gl::MemoryLedger& ledger) {
    if (res.blueNoise) return res.blueNoise;
    const int s = kBlueNoiseSize, layers = kBlueNoiseVariants;
    res.blueNoise.ensure(ledger, "noise.blue", blueNoiseDesc());
    std::vector<std::uint8_t> texels(std::size_t(s * s * layers * 4));
    for (int l = 0; l < layers; ++l)
        for (int c = 0; c < 4; ++c) {
            auto tile = blueNoiseTile(s, unsigned(1000 + 17 * l + c));
            for (int i = 0; i < s * s; ++i)
                texels[std::size_t(((l * s * s) + i) * 4 + c)] = std::uint8_t(std::min(255.0f, tile[std::size_t(i)] * 256.0f));
        }
    glTextureSubImage3D(res.blueNoise.id(), 0, 0, 0, 0, s, s, layers, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
    res.blueNoise.setSampling(GL_NEAREST, GL_NEAREST, GL_REPEAT);
    return res.blueNoise;
}

}  // namespace rtgi
