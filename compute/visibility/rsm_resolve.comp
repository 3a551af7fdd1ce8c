// lpv.rsm (compute path): visibility buffer of the light's view -> RSM flux
// and normal (lpv/rsm.glsl, shared with the raster path); empty texels 0.
#include "lib/raster.glsl"
#include "lpv/rsm.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = RTGI_VISIBILITY_IMG_RSM_FLUX, rgba32f) uniform writeonly image2D outFlux;
layout(binding = RTGI_VISIBILITY_IMG_RSM_NORMAL, rgba16f) uniform writeonly image2D outNormal;
#ifdef RTGI_RSM_LOCAL
// A face of a spot / point / area light's RSM (the same texel as lpv/rsm.frag's local path).
layout(location = RTGI_VISIBILITY_LOC_RSM_LIGHT) uniform vec4 uLight[4];  // the GpuLight
layout(location = RTGI_VISIBILITY_LOC_RSM_FACE) uniform vec2 uFace;       // tan(half field of view), RSM side
#endif

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, uSize))) return;
    float depth;
    uint id;
    vec4 flux = vec4(0.0), normal = vec4(0.0);
    if (visRead(uint(pixel.y) * uint(uSize.x) + uint(pixel.x), depth, id)) {
        VisSurface s = visSurface(id, pixel);
        vec4 baseColor = materialBaseColorGrad(s.material, s.uv, s.dUvDx, s.dUvDy);
#ifdef RTGI_RSM_LOCAL
        GpuLight g = GpuLight(uLight[0], uLight[1], uLight[2], uLight[3]);
        rsmTexelLocal(g, s.position, s.normal, s.material, baseColor, vec2(pixel), uFace, flux, normal);
#else
        rsmTexel(s.normal, s.material, baseColor, flux, normal);
#endif
    }
    imageStore(outFlux, pixel, flux);
    imageStore(outNormal, pixel, normal);
}
