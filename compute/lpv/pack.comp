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

#ifdef RTGI_LPV_PACK_GEOMETRY
layout(r32f, binding = RTGI_LPV_PACK_IMG_GEOMETRY_ACCUM) uniform image3D uGeometryAccum;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_GEOMETRY) uniform writeonly image3D uGeometry;
layout(rgba16f, binding = RTGI_LPV_IMG_GEOMETRY_ALBEDO) uniform writeonly image3D uGeometryAlbedo;

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
}
#else
layout(r32f, binding = RTGI_LPV_PACK_IMG_INJECT_R) uniform image3D uInjectR;
layout(r32f, binding = RTGI_LPV_PACK_IMG_INJECT_G) uniform image3D uInjectG;
layout(r32f, binding = RTGI_LPV_PACK_IMG_INJECT_B) uniform image3D uInjectB;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_VOL_R) uniform writeonly image3D uVolR;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_VOL_G) uniform writeonly image3D uVolG;
layout(RTGI_LPV_FORMAT, binding = RTGI_LPV_IMG_VOL_B) uniform writeonly image3D uVolB;

// The 4 coefficients of cell c in one accumulation texture, zeroed behind (the invocation owns them).
#define LPV_CONSUME(img, c, out4)                                  \
    for (int k = 0; k < 4; ++k) {                                  \
        ivec3 t = ivec3(4 * c.x + k, c.y, c.z);                    \
        out4[k] = imageLoad(img, t).r;                             \
        if (out4[k] != 0.0) imageStore(img, t, vec4(0.0));         \
    }

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(c, lpv.grid.xyz)) return;
    vec4 r, g, b;
    LPV_CONSUME(uInjectR, c, r)
    LPV_CONSUME(uInjectG, c, g)
    LPV_CONSUME(uInjectB, c, b)
    imageStore(uVolR, c, lpvStorable(r));
    imageStore(uVolG, c, lpvStorable(g));
    imageStore(uVolB, c, lpvStorable(b));
}
#endif
