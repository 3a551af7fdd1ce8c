// lpv.visibility (lpv.lookup=visibility; docs/lpv.md, "Visibility moments"): per cell and
// per texel of its N x N octahedral direction map, the mean and mean square of the distance
// (cell units) from the cell centre to the first surface of the scene's BVH, over S x S rays
// through the texel's strata centres (deterministic: the same scene and grid give the same
// moments); a ray that meets nothing within RTGI_LPV_VIS_MAX_DISTANCE cells counts as that
// distance. One invocation per texel of the (X N, Y N, Z) moments image.
// RTGI_LPV_VIS_SKY (lpv.sky=visibility): per cell, band-1 SH of the sky visibility V(w) (1 where
// a ray from the centre leaves the scene without meeting a surface), from K = M x M equal-area
// strata centres of the sphere: p = (4 pi / K) sum_j V(w_j) Y(w_j), as lpv/probe.comp projects
// radiance. One invocation per cell.
#include "lpv/lpv_common.glsl"
#include "lib/bvh_shared.h"
#include "lib/bvh.glsl"
#include "lib/lpv_lookup.glsl"
#include "lib/sampling.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

#if defined(RTGI_LPV_VIS_FACES)
layout(rgba8, binding = RTGI_LPV_VIS_IMG_FACES) uniform writeonly image3D uFaces;

// RTGI_LPV_VIS_FACES (lpv.blocking=visibility; docs/lpv.md, "Face openness"): per cell c and axis
// a = +x, +y, +z, the fraction of F x F rays parallel to a, started at the strata centres of c's
// cross-section through its centre ((-1/2, 1/2)^2 cells) and ending one cell further, at the
// plane of the centre of c + a, that meet no surface: the open fraction of the slab between the
// two centres. Symmetric: the same segments serve the flow c -> c + a and c + a -> c. One
// invocation per cell.
void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(cell, lpv.grid.xyz)) return;
    float s = lpvCellSize();
    vec3 centre = lpv.origin.xyz + (vec3(cell) + 0.5) * s;
    const int f = RTGI_LPV_VIS_FACE_RAYS;
    vec3 open = vec3(0.0);
    for (int a = 0; a < 3; ++a) {
        vec3 d = vec3(a == 0, a == 1, a == 2);
        vec3 u = vec3(a == 1, a == 2, a == 0), v = vec3(a == 2, a == 0, a == 1);
        for (int j = 0; j < f * f; ++j) {
            vec2 o = (vec2(j % f, j / f) + 0.5) / float(f) - 0.5;
            if (!traceAny(centre + s * (o.x * u + o.y * v), d, 0.0, s)) open[a] += 1.0;
        }
    }
    imageStore(uFaces, cell, vec4(open / float(f * f), 0.0));
}
#elif defined(RTGI_LPV_VIS_SKY)
layout(rgba16f, binding = RTGI_LPV_VIS_IMG_SKY) uniform writeonly image3D uSky;

void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(cell, lpv.grid.xyz)) return;
    vec3 o = lpv.origin.xyz + (vec3(cell) + 0.5) * lpvCellSize();
    const int m = RTGI_LPV_SKY_STRATA;
    vec4 p = vec4(0.0);
    for (int j = 0; j < m * m; ++j) {
        vec3 w = uniformSphere((vec2(j % m, j / m) + 0.5) / float(m));
        if (!traceAny(o, w, 0.0, 0.5 * BVH_MISS)) p += shBasis(w);
    }
    imageStore(uSky, cell, p * (4.0 * PI / float(m * m)));
}
#else
layout(rg16f, binding = RTGI_LPV_VIS_IMG_MOMENTS) uniform writeonly image3D uMoments;

void main() {
    ivec3 t = ivec3(gl_GlobalInvocationID);
    const int n = RTGI_LPV_VIS_RES, s = RTGI_LPV_VIS_SUBSAMPLES;
    ivec3 cell = ivec3(t.x / n, t.y / n, t.z);
    if (!lpvInside(cell, lpv.grid.xyz)) return;
    ivec2 bin = t.xy - cell.xy * n;
    vec3 o = lpv.origin.xyz + (vec3(cell) + 0.5) * lpvCellSize();
    float maxT = RTGI_LPV_VIS_MAX_DISTANCE * lpvCellSize();
    vec2 m = vec2(0.0);
    for (int j = 0; j < s * s; ++j) {
        vec2 uv = (vec2(bin) + (vec2(j % s, j / s) + 0.5) / float(s)) / float(n);
        vec3 w = lpvOctDecode(uv);
        Hit hit;
        float d = traceClosest(o, w, 0.0, maxT, hit) ? min(hit.t, maxT) : maxT;
        d /= lpvCellSize();
        m += vec2(d, d * d);
    }
    imageStore(uMoments, t, vec4(m / float(s * s), 0.0, 0.0));
}
#endif
