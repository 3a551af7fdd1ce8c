// visibility.resolve: visibility buffer -> today's G-buffer targets (the
// conventions of raster/gbuffer.glsl, shared with the hardware path).
// Burns & Hunt 2013: attributes are fetched again from the triangle id and
// interpolated with perspective-correct barycentrics. Empty pixels get the
// hardware path's clear value 0.
#include "lib/raster.glsl"
#include "raster/gbuffer.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = RTGI_VISIBILITY_IMG_LINEAR_DEPTH, r32f) uniform writeonly image2D outLinearDepth;
layout(binding = RTGI_VISIBILITY_IMG_NORMAL, rgba16f) uniform writeonly image2D outNormal;
layout(binding = RTGI_VISIBILITY_IMG_ALBEDO, rgba8) uniform writeonly image2D outAlbedo;
layout(binding = RTGI_VISIBILITY_IMG_MATERIAL, rgba8) uniform writeonly image2D outMaterial;
layout(binding = RTGI_VISIBILITY_IMG_EMISSIVE, r11f_g11f_b10f) uniform writeonly image2D outEmissive;
layout(binding = RTGI_VISIBILITY_IMG_VELOCITY, rg16f) uniform writeonly image2D outVelocity;
// The previous frame's vertices (GpuScene::previousVertices: the vertex buffer
// itself when nothing moved), for object motion in the velocity.
layout(std430, binding = RTGI_VISIBILITY_SSBO_PREV_VERTICES) readonly buffer VisPrevVertices { float visPrevVertexData[]; };

vec3 prevPosition(uint v) { return vec3(visPrevVertexData[9 * v], visPrevVertexData[9 * v + 1], visPrevVertexData[9 * v + 2]); }

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, uSize))) return;
    float depth;
    uint id;
    GBufferTexel g = GBufferTexel(0.0, vec4(0.0), vec4(0.0), vec4(0.0), vec3(0.0), vec2(0.0));
    if (visRead(uint(pixel.y) * uint(uSize.x) + uint(pixel.x), depth, id)) {
        VisSurface s = visSurface(id, pixel);
        vec4 base = materialBaseColorGrad(s.material, s.uv, s.dUvDx, s.dUvDy);
        // The same barycentrics on the previous positions: the hardware path's
        // interpolated RTGI_ATTR_PREV_POSITION.
        vec3 prev = s.bary.x * prevPosition(s.vertices.x) + s.bary.y * prevPosition(s.vertices.y) +
                    s.bary.z * prevPosition(s.vertices.z);
        g = gbufferTexel(s.position, s.normal, s.front, s.material, base, frame.viewProj * vec4(s.position, 1.0),
                         frame.prevViewProj * vec4(prev, 1.0));
    }
    imageStore(outLinearDepth, pixel, vec4(g.linearDepth));
    imageStore(outNormal, pixel, g.normal);
    imageStore(outAlbedo, pixel, g.albedo);
    imageStore(outMaterial, pixel, g.material);
    imageStore(outEmissive, pixel, vec4(g.emissive, 0.0));
    imageStore(outVelocity, pixel, vec4(g.velocity, 0.0, 0.0));
}
