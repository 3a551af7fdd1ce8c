// FILTER family: texture/image units, storage bindings and uniform locations
// shared by C++ (src/) and GLSL (compute/filter/), so neither side holds a literal.
#ifndef RTGI_FILTER_SHARED_H
#define RTGI_FILTER_SHARED_H

// ---- slots of compute/filter/ (docs/architecture.md, "Binding slots") ----
// RTGI_<FAMILY>[_<PASS>]_<TEX|IMG|LOC|SSBO>_<ROLE>; the pass appears only where the
// family's passes give the same role different slots.
// texture units (sampler bindings)
#define RTGI_FILTER_TEX_VALUE          0  // filter/blur.comp
#define RTGI_FILTER_BLUR_TEX_DEPTH     1  // filter/blur.comp
#define RTGI_FILTER_TEX_NORMAL         2  // filter/blur.comp
#define RTGI_FILTER_TEX_CURRENT        0  // filter/temporal.comp
#define RTGI_FILTER_TEX_HISTORY        1  // filter/temporal.comp
#define RTGI_FILTER_TEMPORAL_TEX_DEPTH 2  // filter/temporal.comp
#define RTGI_FILTER_TEX_HISTORY_DEPTH  3  // filter/temporal.comp
#define RTGI_FILTER_TEX_VELOCITY       4  // filter/temporal.comp
#define RTGI_FILTER_TEX_LOW            0  // filter/upsample.comp
#define RTGI_FILTER_TEX_LOW_DEPTH      1  // filter/upsample.comp
#define RTGI_FILTER_TEX_FULL_DEPTH     2  // filter/upsample.comp
// image units
#define RTGI_FILTER_IMG_OUT       0  // filter/blur.comp filter/temporal.comp filter/upsample.comp
#define RTGI_FILTER_IMG_OUT_DEPTH 1  // filter/temporal.comp
// storage buffers
#define RTGI_FILTER_SSBO_COUNTS 3  // filter/temporal.comp: uint disoccluded pixels of the run
// uniform locations
#define RTGI_FILTER_LOC_DIRECTION        0  // filter/blur.comp
#define RTGI_FILTER_LOC_DEPTH_THRESHOLD  1  // filter/blur.comp
#define RTGI_FILTER_LOC_NORMAL_THRESHOLD 2  // filter/blur.comp
#define RTGI_FILTER_LOC_RESET            0  // filter/temporal.comp
#define RTGI_FILTER_LOC_CUR_TO_PREV_VIEW 1  // filter/temporal.comp: mat4, locations 1-4
#define RTGI_FILTER_LOC_PROJ_SCALE       5  // filter/temporal.comp: vec2

#endif
