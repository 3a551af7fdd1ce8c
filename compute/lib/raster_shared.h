// RASTER family: texture/image units, storage bindings and uniform locations
// shared by C++ (src/) and GLSL (compute/raster/), so neither side holds a literal.
#ifndef RTGI_RASTER_SHARED_H
#define RTGI_RASTER_SHARED_H

// ---- slots of compute/raster/ (docs/architecture.md, "Binding slots") ----
// RTGI_<FAMILY>[_<PASS>]_<TEX|IMG|LOC|SSBO>_<ROLE>; the pass appears only where the
// family's passes give the same role different slots.
// uniform locations
#define RTGI_RASTER_LOC_LIGHT_VIEW_PROJ 0  // raster/scene.vert

#endif
