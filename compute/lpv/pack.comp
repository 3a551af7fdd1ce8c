// lpv.pack: fp32 atomic accumulation -> propagation format (lpv.format).
// Light (default): the injected volume becomes iteration 0 and the start of
// the accumulated volume. RTGI_LPV_PACK_GEOMETRY: blocking SH and the mean
// albedo of the geometry volume.
#include "lpv/lpv_common.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_3D, local_size_y = RTGI_LPV_LOCAL_3D, local_size_z = RTGI_LPV_LOCAL_3D) in;

#ifdef RTGI_LPV_PACK_GEOMETRY
layout(binding = 0) uniform sampler3D uGeometryAccum;
layout(RTGI_LPV_FORMAT, binding = 0) uniform writeonly image3D uGeometry;
layout(rgba16f, binding = 1) uniform writeonly image3D uGeometryAlbedo;

void main() {
    ivec3 g = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(g, lpv.grid.xyz + 1)) return;
    float a[RTGI_LPV_GV_CHANNELS];
    for (int k = 0; k < RTGI_LPV_GV_CHANNELS; ++k)
        a[k] = texelFetch(uGeometryAccum, ivec3(RTGI_LPV_GV_CHANNELS * g.x + k, g.y, g.z), 0).r;
    imageStore(uGeometry, g, lpvStorable(vec4(a[0], a[1], a[2], a[3])));
    vec3 albedo = a[7] > 0.0 ? clamp(vec3(a[4], a[5], a[6]) / a[7], 0.0, 1.0) : vec3(0.0);
    imageStore(uGeometryAlbedo, g, vec4(albedo, 1.0));
}
#else
layout(binding = 0) uniform sampler3D uInjectR;
layout(binding = 1) uniform sampler3D uInjectG;
layout(binding = 2) uniform sampler3D uInjectB;
layout(RTGI_LPV_FORMAT, binding = 0) uniform writeonly image3D uVolR;
layout(RTGI_LPV_FORMAT, binding = 1) uniform writeonly image3D uVolG;
layout(RTGI_LPV_FORMAT, binding = 2) uniform writeonly image3D uVolB;
layout(RTGI_LPV_FORMAT, binding = 3) uniform writeonly image3D uAccumR;
layout(RTGI_LPV_FORMAT, binding = 4) uniform writeonly image3D uAccumG;
layout(RTGI_LPV_FORMAT, binding = 5) uniform writeonly image3D uAccumB;

vec4 coefficients(sampler3D s, ivec3 c) {
    return vec4(texelFetch(s, ivec3(4 * c.x, c.y, c.z), 0).r, texelFetch(s, ivec3(4 * c.x + 1, c.y, c.z), 0).r,
                texelFetch(s, ivec3(4 * c.x + 2, c.y, c.z), 0).r, texelFetch(s, ivec3(4 * c.x + 3, c.y, c.z), 0).r);
}

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (!lpvInside(c, lpv.grid.xyz)) return;
    vec4 r = lpvStorable(coefficients(uInjectR, c));
    vec4 g = lpvStorable(coefficients(uInjectG, c));
    vec4 b = lpvStorable(coefficients(uInjectB, c));
    imageStore(uVolR, c, r);
    imageStore(uVolG, c, g);
    imageStore(uVolB, c, b);
    imageStore(uAccumR, c, r);
    imageStore(uAccumG, c, g);
    imageStore(uAccumB, c, b);
}
#endif
