// SH constants shared by C++ and GLSL, apart from any family's bindings:
// lib/sh.glsl includes it (AO's S3HO and the LPV), C++ through
// src/render/lpv/lpv_math.h. Derivations: docs/lpv.md.
#ifndef RTGI_SH_SHARED_H
#define RTGI_SH_SHARED_H

// ---- real SH bands 0-1, order (Y00, Y1-1, Y10, Y11), SPEC 3 / seed eq. 10 ----
#define RTGI_SH_Y00 0.28209479177387814    // 1 / (2 sqrt(pi))
#define RTGI_SH_Y1 0.48860251190291992     // sqrt(3) / (2 sqrt(pi))
#define RTGI_SH_COS_C0 0.88622692545275801  // sqrt(pi) / 2: clamped cosine, band 0 [KD10]
#define RTGI_SH_COS_C1 1.0233267079464885   // sqrt(pi / 3): clamped cosine, band 1

// ---- band 2 (lpv.sh_order=2), order (Y2-2, Y2-1, Y20, Y21, Y22) after band 1, same
// Condon-Shortley signs as band 1 (odd m negative): Y2-2 = K xy, Y2-1 = -K yz,
// Y20 = K0 (3z^2 - 1), Y21 = -K xz, Y22 = K2 (x^2 - y^2). Derivation: docs/lpv.md. ----
#define RTGI_SH_Y2 1.0925484305920792    // K = sqrt(15 / (4 pi))
#define RTGI_SH_Y20 0.31539156525252005  // K0 = sqrt(5 / (16 pi))
#define RTGI_SH_Y22 0.5462742152960396   // K2 = sqrt(15 / (16 pi))
// Clamped cosine (Funk-Hecke): its projection is A_l Y_lm(n) with A_0 = pi, A_1 = 2 pi / 3,
// A_2 = pi / 4 (RTGI_SH_COS_C0 = pi Y00, RTGI_SH_COS_C1 = 2 pi / 3 sqrt(3) / (2 sqrt(pi))).
#define RTGI_SH_COS_A2 0.7853981633974483  // pi / 4

#endif
