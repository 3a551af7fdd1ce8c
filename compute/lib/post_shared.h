// POST family: texture/image units, storage bindings and uniform locations
// shared by C++ (src/) and GLSL (compute/post/), so neither side holds a literal.
#ifndef RTGI_POST_SHARED_H
#define RTGI_POST_SHARED_H

// ---- slots of compute/post/ (docs/architecture.md, "Binding slots") ----
// RTGI_<FAMILY>[_<PASS>]_<TEX|IMG|LOC|SSBO>_<ROLE>; the pass appears only where the
// family's passes give the same role different slots.
// texture units (sampler bindings)
#define RTGI_POST_TEX_DIRECT           0  // post/compose.comp
#define RTGI_POST_COMPOSE_TEX_ALBEDO   1  // post/compose.comp
#define RTGI_POST_COMPOSE_TEX_MATERIAL 2  // post/compose.comp
#define RTGI_POST_TEX_INDIRECT         3  // post/compose.comp
#define RTGI_POST_TEX_SPECULAR         4  // post/compose.comp
#define RTGI_POST_TEX_AO               5  // post/compose.comp
#define RTGI_POST_TEX_SOURCE           0  // post/finite_check.comp
#define RTGI_POST_COMPOSE_TEX_LINEAR_DEPTH 6  // post/compose.comp (RTGI_DIFFUSE_ONLY, RTGI_COMPOSE_HISTORY): depth into a history's alpha
#define RTGI_POST_TEX_LINEAR_DEPTH     0  // post/direct.comp
#define RTGI_POST_TEX_NORMAL           1  // post/direct.comp
#define RTGI_POST_DIRECT_TEX_ALBEDO    2  // post/direct.comp
#define RTGI_POST_DIRECT_TEX_MATERIAL  3  // post/direct.comp
#define RTGI_POST_TEX_EMISSIVE         4  // post/direct.comp
#define RTGI_POST_TEX_SHADOW_MAP       5  // post/direct.comp
#define RTGI_POST_DIRECT_TEX_LOCAL_SHADOWS 6  // post/direct.comp (RTGI_LOCAL_SHADOWS): spot/point/area maps
#define RTGI_POST_DIRECT_TEX_LOCAL_DEPTH 7    // post/direct.comp (RTGI_LOCAL_SHADOWS): the same maps, raw depth (blocker search)
// image units
#define RTGI_POST_IMG_LUT    0  // post/brdf_lut.comp
#define RTGI_POST_IMG_HDR    0  // post/compose.comp
#define RTGI_POST_IMG_LDR    1  // post/compose.comp
#define RTGI_POST_COMPOSE_IMG_HISTORY 2  // post/compose.comp (RTGI_COMPOSE_HISTORY): post.history's image, written here
#define RTGI_POST_IMG_DIRECT 0  // post/direct.comp
// shader storage bindings
#define RTGI_POST_SSBO_COUNTS 0  // post/finite_check.comp
// uniform locations
#define RTGI_POST_LOC_SAMPLES         0  // post/brdf_lut.comp
#define RTGI_POST_LOC_HAVE            0  // post/compose.comp
#define RTGI_POST_LOC_CHANNELS        0  // post/finite_check.comp
#define RTGI_POST_LOC_MAY_BE_NEGATIVE 1  // post/finite_check.comp

#endif
