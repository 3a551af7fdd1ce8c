// Debug view: one z slice of a volume as an image. Light: band-0
// coefficient of R, G, B (the cell's mean intensity) as colour. Geometry
// (RTGI_LPV_SLICE_GEOMETRY): band-0 blocking and the mean albedo.
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"

layout(local_size_x = RTGI_LPV_LOCAL_2D, local_size_y = RTGI_LPV_LOCAL_2D) in;

layout(binding = RTGI_LPV_SLICE_TEX_A) uniform sampler3D uA;
layout(binding = RTGI_LPV_SLICE_TEX_B) uniform sampler3D uB;
layout(binding = RTGI_LPV_SLICE_TEX_C) uniform sampler3D uC;
layout(rgba32f, binding = RTGI_LPV_IMG_SLICE) uniform writeonly image2D uSlice;
layout(location = RTGI_LPV_LOC_Z) uniform int uZ;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(uSlice)))) return;
    ivec3 c = ivec3(p, uZ);
#ifdef RTGI_LPV_SLICE_GEOMETRY
    float b = texelFetch(uA, c, 0).x / (RTGI_SH_Y00 * 4.0 * PI);  // mean of B(w) over the sphere
    imageStore(uSlice, p, vec4(b, texelFetch(uB, c, 0).g, texelFetch(uB, c, 0).r, 1.0));
#else
    imageStore(uSlice, p, vec4(texelFetch(uA, c, 0).x, texelFetch(uB, c, 0).x, texelFetch(uC, c, 0).x, 1.0));
#endif
}
