// SSR constants shared by C++ (src/render/ssr/ssr_constants.h, which
// static_asserts the size) and the compute/ssr/*.comp passes (std140).
#ifndef RTGI_SSR_SHARED_H
#define RTGI_SSR_SHARED_H
#ifdef RTGI_GLSL
#include "lib/shared.h"
#endif

#ifndef RTGI_GLSL
namespace rtgi::gpu {
#endif

#define RTGI_UBO_SSR 3  // SsrUniforms, bound by every ssr.* pass

// Tracer ids (SsrUniforms.params.y); the trace shader is compiled per tracer
// with RTGI_SSR_TRACER set to one of these.
#define RTGI_SSR_LINEAR 1
#define RTGI_SSR_DDA 2
#define RTGI_SSR_HIZ 3

RTGI_STRUCT(SsrUniforms) {
    ivec4 sizes;    // trace width, trace height, full width, full height
    ivec4 params;   // max steps / iterations, tracer id, Hi-Z levels, full/trace pixel ratio (1 or 2)
    vec4 trace;     // thickness (view units), roughness cutoff, screen-edge fade width (uv), unused
};

#ifndef RTGI_GLSL
}  // namespace rtgi::gpu
#endif

// ---- slots of compute/ssr/ (docs/architecture.md, "Binding slots") ----
// RTGI_<FAMILY>[_<PASS>]_<TEX|IMG|LOC|SSBO>_<ROLE>; the pass appears only where the
// family's passes give the same role different slots.
// texture units (sampler bindings)
#define RTGI_SSR_HIZ_TEX_LINEAR_DEPTH   0  // ssr/hiz.comp
#define RTGI_SSR_TEX_HIT                0  // ssr/resolve.comp
#define RTGI_SSR_TEX_CONFIDENCE         1  // ssr/resolve.comp
#define RTGI_SSR_TEX_VELOCITY           2  // ssr/resolve.comp
#define RTGI_SSR_TEX_HISTORY            3  // ssr/resolve.comp
#define RTGI_SSR_RESOLVE_TEX_LINEAR_DEPTH 4  // ssr/resolve.comp
#define RTGI_SSR_TEX_REFLECTION         0  // ssr/shade.comp (half resolution with RTGI_SSR_SHADE_UPSAMPLE)
#define RTGI_SSR_TEX_BRDF_LUT           1  // ssr/shade.comp
#define RTGI_SSR_SHADE_TEX_LINEAR_DEPTH 2  // ssr/shade.comp
#define RTGI_SSR_SHADE_TEX_NORMAL       3  // ssr/shade.comp
#define RTGI_SSR_TEX_ALBEDO             4  // ssr/shade.comp
#define RTGI_SSR_SHADE_TEX_MATERIAL     5  // ssr/shade.comp
#define RTGI_SSR_SHADE_TEX_LOW_DEPTH    6  // ssr/shade.comp (RTGI_SSR_SHADE_UPSAMPLE): the traced pixels' depth
#define RTGI_SSR_TRACE_TEX_LINEAR_DEPTH 0  // ssr/trace.comp
#define RTGI_SSR_TRACE_TEX_NORMAL       1  // ssr/trace.comp
#define RTGI_SSR_TRACE_TEX_MATERIAL     2  // ssr/trace.comp
#define RTGI_SSR_TEX_HIZ                3  // ssr/trace.comp
#define RTGI_SSR_TEX_NOISE              4  // ssr/trace.comp
// image units
#define RTGI_SSR_IMG_TARGET       0  // ssr/hiz.comp
#define RTGI_SSR_IMG_SOURCE       1  // ssr/hiz.comp
#define RTGI_SSR_IMG_RESOLVED     0  // ssr/resolve.comp
#define RTGI_SSR_IMG_SPECULAR     0  // ssr/shade.comp
#define RTGI_SSR_IMG_OCCLUSION    1  // ssr/shade.comp
#define RTGI_SSR_IMG_HIT          0  // ssr/trace.comp
#define RTGI_SSR_IMG_CONFIDENCE   1  // ssr/trace.comp
#define RTGI_SSR_IMG_HIT_DISTANCE 2  // ssr/trace.comp
#define RTGI_SSR_IMG_TRACE_DEPTH  3  // ssr/trace.comp
#define RTGI_SSR_IMG_TRACE_NORMAL 4  // ssr/trace.comp
// uniform locations
#define RTGI_SSR_LOC_HAVE_HISTORY 0  // ssr/resolve.comp
#define RTGI_SSR_LOC_HAVE_LPV     0  // ssr/shade.comp
#endif
