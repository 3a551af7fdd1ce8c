// The one SH library (bands 0-1, and 0-2 as mat3 below): basis, clamped-cosine lobe, evaluation,
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

// ---- Band 2 (9 coefficients; lpv.sh_order=2, docs/lpv.md "Second-order SH") ----
// An SH of bands 0-2 is a mat3: coefficient k in column k / 3, row k % 3, so +, - and
// scalar * are the SH's own operations. Order: band 0-1 as above, then
// (Y2-2, Y2-1, Y20, Y21, Y22) with the signs of lib/sh_shared.h.
mat3 shBasis9(vec3 d) {
    return mat3(RTGI_SH_Y00, -RTGI_SH_Y1 * d.y, RTGI_SH_Y1 * d.z,                       //
                -RTGI_SH_Y1 * d.x, RTGI_SH_Y2 * d.x * d.y, -RTGI_SH_Y2 * d.y * d.z,      //
                RTGI_SH_Y20 * (3.0 * d.z * d.z - 1.0), -RTGI_SH_Y2 * d.x * d.z, RTGI_SH_Y22 * (d.x * d.x - d.y * d.y));
}

// Projection of max(0, n.w) onto bands 0-2: A_l Y_lm(n) (Funk-Hecke, A = pi, 2 pi / 3, pi / 4).
mat3 shCosineLobe9(vec3 n) {
    mat3 y = shBasis9(n) * RTGI_SH_COS_A2;
    return mat3(RTGI_SH_COS_C0, -RTGI_SH_COS_C1 * n.y, RTGI_SH_COS_C1 * n.z, -RTGI_SH_COS_C1 * n.x, y[1].yz, y[2]);
}

float shDot(mat3 a, mat3 b) { return dot(a[0], b[0]) + dot(a[1], b[1]) + dot(a[2], b[2]); }
float shEvaluate(mat3 c, vec3 d) { return shDot(c, shBasis9(d)); }
float shBand0(mat3 c) { return c[0][0]; }
float shBand0(vec4 c) { return c.x; }
// Exact for f of bands 0-2.
float shCosineIntegral(mat3 c, vec3 n) { return shDot(c, shCosineLobe9(n)); }
// f(-w): bands 0 and 2 even, band 1 odd.
mat3 shMirror(mat3 c) { return mat3(c[0] * vec3(1.0, -1.0, -1.0), c[1] * vec3(-1.0, 1.0, 1.0), c[2]); }
// Storage as three vec4 (lo = coefficients 0-3, hi = 4-7, last = 8) and back.
mat3 shFromParts(vec4 lo, vec4 hi, float last) { return mat3(lo.xyz, vec3(lo.w, hi.xy), vec3(hi.zw, last)); }
vec4 shLo(mat3 c) { return vec4(c[0], c[1].x); }
vec4 shHi(mat3 c) { return vec4(c[1].yz, c[2].xy); }
float shLast(mat3 c) { return c[2].z; }
