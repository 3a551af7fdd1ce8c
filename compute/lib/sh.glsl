// The one SH library (bands 0-1): basis, clamped-cosine lobe, evaluation,
// irradiance, reflection and rotation. Constants from lib/sh_shared.h.
#pragma once
#include "lib/sh_shared.h"

// Basis functions at unit direction d (seed eq. 10, SPEC 3).
vec4 shBasis(vec3 d) { return vec4(RTGI_SH_Y00, -RTGI_SH_Y1 * d.y, RTGI_SH_Y1 * d.z, -RTGI_SH_Y1 * d.x); }

// Projection of max(0, n.w) (clamped cosine around n) [KD10]; not normalized (SPEC 11.2).
vec4 shCosineLobe(vec3 n) {
    return vec4(RTGI_SH_COS_C0, -RTGI_SH_COS_C1 * n.y, RTGI_SH_COS_C1 * n.z, -RTGI_SH_COS_C1 * n.x);
}

// Value of the SH function c at direction d.
float shEvaluate(vec4 c, vec3 d) { return dot(c, shBasis(d)); }

// Integral of f(w) max(0, n.w) over the sphere for band-limited f (exact for bands 0-1).
float shCosineIntegral(vec4 c, vec3 n) { return dot(c, shCosineLobe(n)); }

// f(-w): band 0 is even, band 1 odd.
vec4 shMirror(vec4 c) { return vec4(c.x, -c.yzw); }

// Rotates SH coefficients by the rotation m (band 1 transforms like the vector (x, y, z) = (-c3, -c1, c2)).
vec4 shRotate(vec4 c, mat3 m) {
    vec3 v = m * vec3(-c.w, -c.y, c.z);
    return vec4(c.x, -v.y, v.z, -v.x);
}
