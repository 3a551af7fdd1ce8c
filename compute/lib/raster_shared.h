// RASTER family: texture/image units, storage bindings and uniform locations
// shared by C++ (src/) and GLSL (compute/raster/), so neither side holds a literal.
#ifndef RTGI_RASTER_SHARED_H
#define RTGI_RASTER_SHARED_H

// ---- slots of compute/raster/ (docs/architecture.md, "Binding slots") ----
// RTGI_<FAMILY>[_<PASS>]_<TEX|IMG|LOC|SSBO>_<ROLE>; the pass appears only where the
// family's passes give the same role different slots.
// uniform locations
#define RTGI_RASTER_LOC_LIGHT_VIEW_PROJ 0  // raster/scene.vert

// stage interfaces of the hardware raster path (varyings and colour outputs;
// an output's index is its GL_COLOR_ATTACHMENTi / glDrawBuffers slot)
#define RTGI_RASTER_VARY_WORLD_POS 0
#define RTGI_RASTER_VARY_NORMAL 1
#define RTGI_RASTER_VARY_UV 2
#define RTGI_RASTER_VARY_MATERIAL 3
#define RTGI_RASTER_VARY_CUR_CLIP 4
#define RTGI_RASTER_VARY_PREV_CLIP 5
#define RTGI_RASTER_OUT_LINEAR_DEPTH 0  // raster/gbuffer.frag
#define RTGI_RASTER_OUT_NORMAL 1
#define RTGI_RASTER_OUT_ALBEDO 2
#define RTGI_RASTER_OUT_MATERIAL 3
#define RTGI_RASTER_OUT_EMISSIVE 4
#define RTGI_RASTER_OUT_VELOCITY 5
#define RTGI_RASTER_RSM_OUT_FLUX 0      // lpv/rsm.frag
#define RTGI_RASTER_RSM_OUT_NORMAL 1
#define RTGI_RASTER_ID_OUT 0            // visibility/hardware_id.frag

#endif
