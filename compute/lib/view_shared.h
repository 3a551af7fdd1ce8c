// VIEW family: texture/image units, storage bindings and uniform locations
// shared by C++ (src/) and GLSL (compute/view/), so neither side holds a literal.
#ifndef RTGI_VIEW_SHARED_H
#define RTGI_VIEW_SHARED_H

// ---- slots of compute/view/ (docs/architecture.md, "Binding slots") ----
// RTGI_<FAMILY>[_<PASS>]_<TEX|IMG|LOC|SSBO>_<ROLE>; the pass appears only where the
// family's passes give the same role different slots.
// texture units (sampler bindings)
#define RTGI_VIEW_TEX_IMAGE 0  // view/display.frag
// shader storage bindings
#define RTGI_VIEW_SSBO_POSITIONS 0  // view/text.vert
// uniform locations
#define RTGI_VIEW_LOC_MODE        0  // view/display.frag
#define RTGI_VIEW_LOC_SCALE       1  // view/display.frag
#define RTGI_VIEW_LOC_FAR         2  // view/display.frag
#define RTGI_VIEW_LOC_COLOR       1  // view/text.frag
#define RTGI_VIEW_LOC_WINDOW_SIZE 0  // view/text.vert

#endif
