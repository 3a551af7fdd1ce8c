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
#endif
