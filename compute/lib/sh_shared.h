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

#endif
