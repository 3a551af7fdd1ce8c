// Hash-based random numbers with fixed seeds (directions: lib/sampling.glsl).
// Every sample is a pure function of (pixel, sample index, dimension, seed),
// so a reference is bitwise reproducible however its samples are split
// into dispatches. Hash: PCG output permutation (Jarzynski & Olano 2020,
// "Hash Functions for GPU Rendering", pcg), chained over the inputs.
#pragma once

uint pcgHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

struct Rng {
    uint state;
};

Rng rngInit(uvec2 pixel, uint sampleIndex, uint seed) {
    Rng r;
    r.state = pcgHash(pcgHash(pcgHash(pixel.x ^ pcgHash(seed)) ^ pixel.y) ^ sampleIndex);
    return r;
}

// Uniform in [0, 1) with 24 bits.
float rngNext(inout Rng r) {
    r.state = pcgHash(r.state);
    return float(r.state >> 8u) * (1.0 / 16777216.0);
}

vec2 rngNext2(inout Rng r) {
    float a = rngNext(r);
    return vec2(a, rngNext(r));
}
