// lpv.propagate (compute): one dispatch per iteration; writes volume k and
// adds it into the accumulated volume in the same dispatch (fused, SPEC 3.5);
// the first step writes accum = step[0] + step[1]. lpv.sh_order=2 (RTGI_LPV_SH2):
// bands 0-2 in 7 volumes (lo r, g, b + hi r, g, b + last); writing step k and
// accum would need 14 image units (GL guarantees 8), so the sum is added by
// lpv/accumulate.comp after each step.
// lpv.propagate_cascades=joint (RTGI_LPV_JOINT, band 1; docs/lpv.md, "Joint cascade
// propagation"): the step and sum volumes of two cascades stacked along z (cascade k's cell
// c at c + (0, 0, k Z)), one dispatch for both; the workgroups are split by index (the z
// groups of cascade 0, then those of cascade 1), so a workgroup belongs to one cascade and
// reads its own geometry volume. Same arithmetic per cell as the per-cascade dispatch.
#include "lpv/propagate.glsl"
#include "lib/lpv_shared.h"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

layout(binding = RTGI_LPV_TEX_SRC_R) uniform sampler3D uSrcR;
layout(binding = RTGI_LPV_TEX_SRC_G) uniform sampler3D uSrcG;
layout(binding = RTGI_LPV_TEX_SRC_B) uniform sampler3D uSrcB;
layout(binding = RTGI_LPV_TEX_GEOMETRY) uniform sampler3D uGeometry;
layout(binding = RTGI_LPV_TEX_GEOMETRY_ALBEDO) uniform sampler3D uGeometryAlbedo;
layout(binding = RTGI_LPV_TEX_GEOMETRY_AXES) uniform sampler3D uGeometryAxes;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_R) uniform writeonly image3D uDstR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_G) uniform writeonly image3D uDstG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_B) uniform writeonly image3D uDstB;
#ifdef RTGI_LPV_SH2
layout(binding = RTGI_LPV_TEX_SRC_HI_R) uniform sampler3D uSrcHiR;
layout(binding = RTGI_LPV_TEX_SRC_HI_G) uniform sampler3D uSrcHiG;
layout(binding = RTGI_LPV_TEX_SRC_HI_B) uniform sampler3D uSrcHiB;
layout(binding = RTGI_LPV_TEX_SRC_LAST) uniform sampler3D uSrcLast;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_HI_R) uniform writeonly image3D uDstHiR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_HI_G) uniform writeonly image3D uDstHiG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_HI_B) uniform writeonly image3D uDstHiB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_DST_LAST) uniform writeonly image3D uDstLast;

mat3 lpvSource9(vec4 lo, int colour, ivec3 cell) {
    vec4 hi = colour == 0 ? texelFetch(uSrcHiR, cell, 0) : colour == 1 ? texelFetch(uSrcHiG, cell, 0)
                                                                       : texelFetch(uSrcHiB, cell, 0);
    return shFromParts(lo, hi, texelFetch(uSrcLast, cell, 0)[colour]);
}
#else
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_ACCUM_R) uniform image3D uAccumR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_ACCUM_G) uniform image3D uAccumG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_ACCUM_B) uniform image3D uAccumB;
#endif

layout(location = RTGI_LPV_LOC_ITERATION) uniform int uIteration;

#ifdef RTGI_LPV_JOINT
layout(binding = RTGI_LPV_TEX_JOINT_GEOMETRY_1) uniform sampler3D uGeometry1;
layout(binding = RTGI_LPV_TEX_JOINT_GEOMETRY_ALBEDO_1) uniform sampler3D uGeometryAlbedo1;
layout(binding = RTGI_LPV_TEX_JOINT_GEOMETRY_AXES_1) uniform sampler3D uGeometryAxes1;
#endif

void main() {
#ifdef RTGI_LPV_JOINT
    int zGroups = (lpv.grid.z + RTGI_LPV_LOCAL_3D - 1) / RTGI_LPV_LOCAL_3D;
    int cascade = int(gl_WorkGroupID.z) / zGroups;  // uniform in the workgroup
    ivec3 c = ivec3(gl_GlobalInvocationID.xy,
                    (int(gl_WorkGroupID.z) - cascade * zGroups) * RTGI_LPV_LOCAL_3D + int(gl_LocalInvocationID.z));
    lpvSlab = ivec3(0, 0, cascade * lpv.grid.z);
#else
    ivec3 c = ivec3(gl_GlobalInvocationID);
    const ivec3 lpvSlab = ivec3(0);
#endif
    if (!lpvInside(c, lpv.grid.xyz)) return;
    LpvRgb v;
#ifdef RTGI_LPV_JOINT
    if (cascade != 0)
        v = lpvGather(c, uIteration, uSrcR, uSrcG, uSrcB, uGeometry1, uGeometryAlbedo1, uGeometryAxes1);
    else
#endif
        v = lpvGather(c, uIteration, uSrcR, uSrcG, uSrcB, uGeometry, uGeometryAlbedo, uGeometryAxes);
    v.r = lpvStorable(v.r);
    v.g = lpvStorable(v.g);
    v.b = lpvStorable(v.b);
#ifdef RTGI_LPV_SH2
    imageStore(uDstR, c, shLo(v.r));
    imageStore(uDstG, c, shLo(v.g));
    imageStore(uDstB, c, shLo(v.b));
    imageStore(uDstHiR, c, shHi(v.r));
    imageStore(uDstHiG, c, shHi(v.g));
    imageStore(uDstHiB, c, shHi(v.b));
    imageStore(uDstLast, c, vec4(shLast(v.r), shLast(v.g), shLast(v.b), 0.0));
#else
    c += lpvSlab;  // the cell's texel in the (stacked) volumes
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
#endif
}
