// Hash-based random numbers with fixed seeds and hemisphere sampling.
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

// Orthonormal basis around unit n (Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited").
mat3 basisAround(vec3 n) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float b = n.x * n.y * a;
    vec3 t = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    vec3 bt = vec3(b, s + n.y * n.y * a, -n.y);
    return mat3(t, bt, n);
}

// Cosine-weighted direction around unit n; pdf = cos(theta) / pi (Malley).
vec3 cosineHemisphere(vec2 u, vec3 n) {
    float r = sqrt(u.x);
    float phi = 6.28318530717958647692 * u.y;
    vec3 local = vec3(r * cos(phi), r * sin(phi), sqrt(max(1.0 - u.x, 0.0)));
    return basisAround(n) * local;
}
