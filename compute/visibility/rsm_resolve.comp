// lpv.rsm (compute path): visibility buffer of the light's view -> RSM flux
// and normal (lpv/rsm.glsl, shared with the raster path); empty texels 0.
#include "lib/raster.glsl"
#include "lpv/rsm.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = RTGI_VISIBILITY_IMG_RSM_FLUX, rgba32f) uniform writeonly image2D outFlux;
layout(binding = RTGI_VISIBILITY_IMG_RSM_NORMAL, rgba16f) uniform writeonly image2D outNormal;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, uSize))) return;
    float depth;
    uint id;
    vec4 flux = vec4(0.0), normal = vec4(0.0);
    if (visRead(uint(pixel.y) * uint(uSize.x) + uint(pixel.x), depth, id)) {
        VisSurface s = visSurface(id, pixel);
        rsmTexel(s.normal, s.material, materialBaseColorGrad(s.material, s.uv, s.dUvDx, s.dUvDy), flux, normal);
    }
    imageStore(outFlux, pixel, flux);
    imageStore(outNormal, pixel, normal);
}
