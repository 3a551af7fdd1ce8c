// The G-buffer texel from interpolated attributes: shared by the hardware
// path (raster/gbuffer.frag) and the visibility-buffer resolve
// (visibility/resolve.comp) so both write the same conventions.
#pragma once
#include "lib/common.glsl"
#include "raster/material.glsl"

struct GBufferTexel {
    float linearDepth;  // positive view-space distance along -z
    vec4 normal;        // view-space unit normal, a = 1
    vec4 albedo;
    vec4 material;      // r roughness, g metallic
    vec3 emissive;
    vec2 velocity;      // previous − current projected position in UV
};

// `baseColor`: materialBaseColor at the texel (texture LOD chosen by the caller).
GBufferTexel gbufferTexel(vec3 worldPos, vec3 normal, bool frontFacing, uint material, vec4 baseColor, vec4 curClip,
                          vec4 prevClip) {
    GBufferTexel g;
    vec3 viewPos = (frame.view * vec4(worldPos, 1.0)).xyz;
    g.linearDepth = -viewPos.z;
    vec3 n = normalize(normal);
    // Two-sided: flip normals of back faces so thin geometry shades correctly.
    if (!frontFacing) n = -n;
    vec3 nv = normalize(mat3(frame.view) * n);
    if (any(isnan(nv))) nv = vec3(0.0, 0.0, 1.0);
    g.normal = vec4(nv, 1.0);
    g.albedo = vec4(baseColor.rgb, 1.0);
    g.material = vec4(materials[material].params.x, materials[material].params.y, 0.0, 1.0);
    // A single-sided emitter seen from behind shows no emission (glTF doubleSided = false).
    g.emissive = frontFacing || materials[material].emissive.a != 0.0 ? materials[material].emissive.rgb : vec3(0.0);
    vec2 cur = curClip.xy / curClip.w * 0.5 + 0.5;
    vec2 prev = prevClip.xy / prevClip.w * 0.5 + 0.5;
    g.velocity = prev - cur;
    return g;
}
