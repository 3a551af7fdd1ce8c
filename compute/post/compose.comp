// Composition and tonemapping:
//   hdr = direct + diffuseAlbedo·sky·AO·V + indirectDiffuse·AO' + specular
// V = indirectDiffuse.a: the room-scale sky visibility of lpv.sky=visibility (docs/lpv.md), else 1.
// AO' = AO unless the LPV apply already used directional occlusion
// (bent normals / S3HO), so occlusion is never applied twice.
// RTGI_DIFFUSE_ONLY (ssr.diffuse_history): no specular term, no tonemapping,
// the result goes to an RGBA16F history image.
// RTGI_COMPOSE_HISTORY: also writes post.history's image (the radiance in RGBA16F, the linear depth in
// alpha for the readers' disocclusion test), the copy that pass would otherwise dispatch.
#include "lib/common.glsl"
#include "lib/post_shared.h"
#include "lib/brdf.glsl"
#include "lib/tonemap.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = RTGI_POST_TEX_DIRECT) uniform sampler2D uDirect;
layout(binding = RTGI_POST_COMPOSE_TEX_ALBEDO) uniform sampler2D uAlbedo;
layout(binding = RTGI_POST_COMPOSE_TEX_MATERIAL) uniform sampler2D uMaterial;
layout(binding = RTGI_POST_TEX_INDIRECT) uniform sampler2D uIndirect;
layout(binding = RTGI_POST_TEX_SPECULAR) uniform sampler2D uSpecular;
layout(binding = RTGI_POST_TEX_AO) uniform sampler2D uAo;
#ifdef RTGI_DIFFUSE_ONLY
layout(rgba16f, binding = RTGI_POST_IMG_HDR) uniform writeonly image2D uHdr;
layout(binding = RTGI_POST_COMPOSE_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;  // into alpha (disocclusion)
#else
layout(rgba32f, binding = RTGI_POST_IMG_HDR) uniform writeonly image2D uHdr;
layout(rgba8, binding = RTGI_POST_IMG_LDR) uniform writeonly image2D uLdr;
#ifdef RTGI_COMPOSE_HISTORY
layout(rgba16f, binding = RTGI_POST_COMPOSE_IMG_HISTORY) uniform writeonly image2D uHistory;
layout(binding = RTGI_POST_COMPOSE_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
#endif
#endif

layout(location = RTGI_POST_LOC_HAVE) uniform ivec4 uHave;  // indirect, specular, ao, ao already applied to indirect

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, frameSize()))) return;
    vec4 direct = texelFetch(uDirect, p, 0);
    vec3 color = direct.rgb;
    if (direct.a > 0.0) {  // geometry (a = 0 marks sky)
        vec3 albedo = texelFetch(uAlbedo, p, 0).rgb;
        float metallic = texelFetch(uMaterial, p, 0).g;
        float ao = uHave.z != 0 ? clamp(texelFetch(uAo, p, 0).r, 0.0, 1.0) : 1.0;
        vec4 indirect = uHave.x != 0 ? texelFetch(uIndirect, p, 0) : vec4(0.0, 0.0, 0.0, 1.0);
        color += diffuseAlbedo(albedo, metallic) * frame.sky.rgb * ao * clamp(indirect.a, 0.0, 1.0);
        color += indirect.rgb * (uHave.w != 0 ? 1.0 : ao);
#ifndef RTGI_DIFFUSE_ONLY
        if (uHave.y != 0) color += texelFetch(uSpecular, p, 0).rgb;
#endif
    }
#ifdef RTGI_DIFFUSE_ONLY
    imageStore(uHdr, p, vec4(color, texelFetch(uLinearDepth, p, 0).r));
#else
    imageStore(uHdr, p, vec4(color, 1.0));
#endif
#ifndef RTGI_DIFFUSE_ONLY
    imageStore(uLdr, p, vec4(tonemap(color, frame.sky.a), 1.0));
#ifdef RTGI_COMPOSE_HISTORY
    imageStore(uHistory, p, vec4(color, texelFetch(uLinearDepth, p, 0).r));
#endif
#endif
}
