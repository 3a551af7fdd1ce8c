// lpv.propagate (compute): one dispatch per iteration; writes volume k and
// adds it into the accumulated volume in the same dispatch (fused, SPEC 3.5);
// the first step writes accum = step[0] + step[1].
#include "lpv/propagate.glsl"
#include "lib/lpv_shared.h"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

layout(binding = RTGI_LPV_TEX_SRC_R) uniform sampler3D uSrcR;
layout(binding = RTGI_LPV_TEX_SRC_G) uniform sampler3D uSrcG;
layout(binding = RTGI_LPV_TEX_SRC_B) uniform sampler3D uSrcB;
layout(binding = RTGI_LPV_TEX_GEOMETRY) uniform sampler3D uGeometry;
layout(binding = RTGI_LPV_TEX_GEOMETRY_ALBEDO) uniform sampler3D uGeometryAlbedo;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_R) uniform writeonly image3D uDstR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_G) uniform writeonly image3D uDstG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_B) uniform writeonly image3D uDstB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_ACCUM_R) uniform image3D uAccumR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_ACCUM_G) uniform image3D uAccumG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_ACCUM_B) uniform image3D uAccumB;

layout(location = RTGI_LPV_LOC_ITERATION) uniform int uIteration;

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(c, lpv.grid.xyz)) return;
    LpvRgb v = lpvGather(c, uIteration, uSrcR, uSrcG, uSrcB, uGeometry, uGeometryAlbedo);
    v.r = lpvStorable(v.r);
    v.g = lpvStorable(v.g);
    v.b = lpvStorable(v.b);
    imageStore(uDstR, c, v.r);
    imageStore(uDstG, c, v.g);
    imageStore(uDstB, c, v.b);
    // Each invocation owns its cell: the read-modify-write needs no atomics.
    // The first step starts the sum from the injected volume (its source), so
    // lpv.pack writes only step[0].
    bool first = uIteration == 1;
    imageStore(uAccumR, c, lpvStorable((first ? texelFetch(uSrcR, c, 0) : imageLoad(uAccumR, c)) + v.r));
    imageStore(uAccumG, c, lpvStorable((first ? texelFetch(uSrcG, c, 0) : imageLoad(uAccumG, c)) + v.g));
    imageStore(uAccumB, c, lpvStorable((first ? texelFetch(uSrcB, c, 0) : imageLoad(uAccumB, c)) + v.b));
}
