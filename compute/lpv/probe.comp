// lpv.source=probe (docs/lpv.md, "Stage attribution"): the accumulated volume
// of one cascade filled with path-traced light instead of the propagated one.
// At each cell centre x the radiance arriving from N directions w (uniform on
// the sphere, jittered m x m strata) is traced with the transport of the
// matching-bounce reference (ref_scene.glsl's refTraceRadiance: Lambert only,
// `bounces` surfaces, no sky seen directly) and projected onto SH bands 0-1:
//   p = (4 pi / N) sum_j L_in(w_j) Y(w_j).
// The volume stores the intensity of the light *flowing* through the cell
// (lpv.apply: L = I / s^2, light arriving from w flows along -w), so the cell
// gets I = s^2 shMirror(p); lpv.apply then computes E(n) = <p, cosLobe(n)>,
// the band-1 irradiance of the traced field at x. lpv.sh_order=2 (RTGI_LPV_SH2):
// bands 0-2 (shBasis9), stored in the 7 volumes of the band-2 layout.
#include "lpv/lpv_common.glsl"
#include "lib/bvh_shared.h"
#include "lib/random.glsl"
#include "lib/sampling.glsl"
#include "lib/bvh.glsl"
#include "lib/ref_scene.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_PROBE_IMG_ACCUM_R) uniform writeonly image3D uAccumR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_PROBE_IMG_ACCUM_G) uniform writeonly image3D uAccumG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_PROBE_IMG_ACCUM_B) uniform writeonly image3D uAccumB;
#ifdef RTGI_LPV_SH2
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_PROBE_IMG_ACCUM_HI_R) uniform writeonly image3D uAccumHiR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_PROBE_IMG_ACCUM_HI_G) uniform writeonly image3D uAccumHiG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_PROBE_IMG_ACCUM_HI_B) uniform writeonly image3D uAccumHiB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_PROBE_IMG_ACCUM_LAST) uniform writeonly image3D uAccumLast;
#define LpvSh mat3
#define lpvProbeBasis shBasis9
#else
#define LpvSh vec4
#define lpvProbeBasis shBasis
#endif
layout(location = RTGI_LPV_PROBE_LOC_PARAMS) uniform uvec4 uParams;  // directions, bounces, seed, first z slice

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID) + ivec3(0, 0, int(uParams.w));
    if (!lpvInside(c, lpv.grid.xyz)) return;
    vec3 x = lpv.origin.xyz + (vec3(c) + 0.5) * lpvCellSize();
    uint n = max(uParams.x, 1u);
    uint m = uint(floor(sqrt(float(n))));
    uint key = lpvKeyOfCell(c, lpv.grid.xyz);
    LpvSh pr = LpvSh(0.0), pg = LpvSh(0.0), pb = LpvSh(0.0);
    for (uint j = 0u; j < n; ++j) {
        Rng rng = rngInit(uvec2(key, uint(lpv.cascade.x)), j, uParams.z);
        vec2 u = rngNext2(rng);
        // Strata j < m^2: cell (j % m, j / m) of the unit square; the rest uniform.
        if (j < m * m) u = (vec2(float(j % m), float(j / m)) + u) / float(m);
        vec3 w = uniformSphere(u);
        vec3 L = refTraceRadiance(x, w, 0.25 * INV_PI, vec3(1.0), uParams.y, true, rng);
        if (any(isnan(L)) || any(isinf(L))) L = vec3(0.0);
        LpvSh y = lpvProbeBasis(w);
        pr += L.r * y;
        pg += L.g * y;
        pb += L.b * y;
    }
    float k = 4.0 * PI / float(n) * lpvCellSize() * lpvCellSize();
#ifdef RTGI_LPV_SH2
    mat3 r = lpvStorable(shMirror(pr) * k), g = lpvStorable(shMirror(pg) * k), b = lpvStorable(shMirror(pb) * k);
    imageStore(uAccumR, c, shLo(r));
    imageStore(uAccumG, c, shLo(g));
    imageStore(uAccumB, c, shLo(b));
    imageStore(uAccumHiR, c, shHi(r));
    imageStore(uAccumHiG, c, shHi(g));
    imageStore(uAccumHiB, c, shHi(b));
    imageStore(uAccumLast, c, vec4(shLast(r), shLast(g), shLast(b), 0.0));
#else
    imageStore(uAccumR, c, lpvStorable(shMirror(pr) * k));
    imageStore(uAccumG, c, lpvStorable(shMirror(pg) * k));
    imageStore(uAccumB, c, lpvStorable(shMirror(pb) * k));
#endif
}
