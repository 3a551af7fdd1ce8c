// lpv.pack: fp32 atomic accumulation -> propagation format (lpv.format).
// Light (default): the injected volume becomes iteration 0 (step[0]; the first
// propagation step starts the accumulated volume from it). RTGI_LPV_PACK_GEOMETRY:
// blocking SH and the mean albedo of the geometry volume.
// Both consume their fp32 accumulation: texels that are not zero are zeroed,
// so the next injection starts from zero without a clear of the whole volume
// (docs/lpv.md, "Costs").
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

// The n coefficients of cell c in one accumulation texture (at n x + k), zeroed behind
// (the invocation owns them).
#define LPV_CONSUME_N(img, c, n, out4)                             \
    for (int k = 0; k < n; ++k) {                                  \
        ivec3 t = ivec3(n * c.x + k, c.y, c.z);                    \
        out4[k] = imageLoad(img, t).r;                             \
        if (out4[k] != 0.0) imageStore(img, t, vec4(0.0));         \
    }

#ifdef RTGI_LPV_PACK_GEOMETRY
layout(r32f, binding = RTGI_LPV_PACK_IMG_GEOMETRY_ACCUM) uniform image3D uGeometryAccum;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_GEOMETRY) uniform writeonly image3D uGeometry;
layout(rgba16f, binding = RTGI_LPV_IMG_GEOMETRY_ALBEDO) uniform writeonly image3D uGeometryAlbedo;
#ifdef RTGI_LPV_TWO_SIDED
layout(rgba16f, binding = RTGI_LPV_IMG_GEOMETRY_AXES) uniform writeonly image3D uGeometryAxes;
#endif

void main() {
    ivec3 g = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(g, lpv.grid.xyz + 1)) return;
    float a[RTGI_LPV_GV_CHANNELS];
    for (int k = 0; k < RTGI_LPV_GV_CHANNELS; ++k) {
        ivec3 t = ivec3(RTGI_LPV_GV_CHANNELS * g.x + k, g.y, g.z);
        a[k] = imageLoad(uGeometryAccum, t).r;
        if (a[k] != 0.0) imageStore(uGeometryAccum, t, vec4(0.0));  // each invocation owns its texels
    }
    imageStore(uGeometry, g, lpvStorable(vec4(a[0], a[1], a[2], a[3])));
    vec3 albedo = a[7] > 0.0 ? clamp(vec3(a[4], a[5], a[6]) / a[7], 0.0, 1.0) : vec3(0.0);
    imageStore(uGeometryAlbedo, g, vec4(albedo, 1.0));
#ifdef RTGI_LPV_TWO_SIDED
    imageStore(uGeometryAxes, g, vec4(min(vec3(a[8], a[9], a[10]), vec3(65504.0)), 0.0));
#endif
}
#elif defined(RTGI_LPV_PACK_HI)
// lpv.sh_order=2: coefficients 4-8 (a second dispatch; the first packs 0-3 as for band 1),
// 8 image units in all (docs/lpv.md, "Second-order SH").
layout(r32f, binding = RTGI_LPV_PACK_IMG_INJECT_HI_R) uniform image3D uInjectHiR;
layout(r32f, binding = RTGI_LPV_PACK_IMG_INJECT_HI_G) uniform image3D uInjectHiG;
layout(r32f, binding = RTGI_LPV_PACK_IMG_INJECT_HI_B) uniform image3D uInjectHiB;
layout(r32f, binding = RTGI_LPV_PACK_IMG_INJECT_LAST) uniform image3D uInjectLast;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_PACK_IMG_VOL_HI_R) uniform writeonly image3D uVolHiR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_PACK_IMG_VOL_HI_G) uniform writeonly image3D uVolHiG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_PACK_IMG_VOL_HI_B) uniform writeonly image3D uVolHiB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_PACK_IMG_VOL_LAST) uniform writeonly image3D uVolLast;

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(c, lpv.grid.xyz)) return;
    vec4 r, g, b, last = vec4(0.0);
    LPV_CONSUME_N(uInjectHiR, c, 4, r)
    LPV_CONSUME_N(uInjectHiG, c, 4, g)
    LPV_CONSUME_N(uInjectHiB, c, 4, b)
    LPV_CONSUME_N(uInjectLast, c, 3, last)
    imageStore(uVolHiR, c, lpvStorable(r));
    imageStore(uVolHiG, c, lpvStorable(g));
    imageStore(uVolHiB, c, lpvStorable(b));
    imageStore(uVolLast, c, lpvStorable(last));
}
#else
layout(r32f, binding = RTGI_LPV_PACK_IMG_INJECT_R) uniform image3D uInjectR;
layout(r32f, binding = RTGI_LPV_PACK_IMG_INJECT_G) uniform image3D uInjectG;
layout(r32f, binding = RTGI_LPV_PACK_IMG_INJECT_B) uniform image3D uInjectB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_VOL_R) uniform writeonly image3D uVolR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_VOL_G) uniform writeonly image3D uVolG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_VOL_B) uniform writeonly image3D uVolB;

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(c, lpv.grid.xyz)) return;
    vec4 r, g, b;
    LPV_CONSUME_N(uInjectR, c, 4, r)
    LPV_CONSUME_N(uInjectG, c, 4, g)
    LPV_CONSUME_N(uInjectB, c, 4, b)
    imageStore(uVolR, c, lpvStorable(r));
    imageStore(uVolG, c, lpvStorable(g));
    imageStore(uVolB, c, lpvStorable(b));
}
#endif
