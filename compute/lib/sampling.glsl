// The one hemisphere-sampling library: orthonormal frames and cosine-weighted
// directions, used by the AO estimators and the reference tracers.
#pragma once
#include "lib/math.glsl"

// Orthonormal basis around unit n (Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited"); columns (t, b, n).
mat3 basisAround(vec3 n) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float b = n.x * n.y * a;
    vec3 t = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    vec3 bt = vec3(b, s + n.y * n.y * a, -n.y);
    return mat3(t, bt, n);
}

// Cosine-weighted direction on the +z hemisphere for u in [0,1)^2; pdf = cos(theta) / pi (Malley).
vec3 cosineHemisphere(vec2 u) {
    float r = sqrt(u.x), phi = TWO_PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u.x)));
}

// The same around unit n.
vec3 cosineHemisphere(vec2 u, vec3 n) { return basisAround(n) * cosineHemisphere(u); }

// Uniform direction on the unit sphere for u in [0,1)^2 (z = 1 - 2 u.x); pdf = 1 / (4 pi).
vec3 uniformSphere(vec2 u) {
    float z = 1.0 - 2.0 * u.x, r = sqrt(max(0.0, 1.0 - z * z)), phi = TWO_PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}
