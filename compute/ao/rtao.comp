// ao.rtao: ray-traced AO at AO resolution through the scene's BVH (the
// reference's traversal, lib/bvh.glsl): ao.rays cosine-weighted rays of
// length R = ao.radius per pixel and frame from the G-buffer surface, the
// estimate of ref.ao's definition (docs/reference.md) with few rays; the
// blur / temporal / upsample chain of the screen-space variants filters it.
// Defines: AO_DIRECTIONAL 0 off, 1 bent normal of the visible rays, 2 S3HO
// band 0-1 SH (pi/N sum V Y, as lib/ao_estimators.glsl aoDirectional).
#include "lib/common.glsl"
#include "lib/bvh_shared.h"
#include "lib/depth.glsl"
#include "lib/ao_shared.h"
#include "lib/ao.glsl"
#include "lib/random.glsl"
#include "lib/sampling.glsl"
#include "lib/bvh.glsl"
#include "lib/sh.glsl"

#ifndef AO_DIRECTIONAL
#define AO_DIRECTIONAL 0
#endif

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, binding = RTGI_UBO_AO) uniform AoBlock { AoParams ao; };
layout(binding = RTGI_AO_TEX_DEPTH) uniform sampler2D uDepth;    // AO-resolution linear depth (0 = sky)
layout(binding = RTGI_AO_TEX_NORMAL) uniform sampler2D uNormal;   // AO-resolution view-space normals
layout(binding = RTGI_AO_RTAO_TEX_FULL_DEPTH) uniform sampler2D uFullDepth;    // G-buffer linear depth
layout(binding = RTGI_AO_RTAO_TEX_FULL_NORMAL) uniform sampler2D uFullNormal;  // G-buffer view-space normals
layout(r16f, binding = RTGI_AO_IMG_AO) uniform writeonly image2D uAo;
layout(rgba16f, binding = RTGI_AO_IMG_DIRECTIONAL) uniform writeonly image2D uDirectional;

const uint RTAO_SEED = 0x52544130u;  // "RTA0": a sequence of its own, not the reference's

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ao.size.xy;
    if (any(greaterThanEqual(p, size))) return;
    // The traced point is a G-buffer texel's own surface point, as ref.ao's.
    // At half resolution that is the full-resolution texel of the 2x2 block
    // that ao.downsample keeps (the nearest non-sky one): the half-resolution
    // point is that texel's depth moved along its tangent plane, which lies
    // under a concave surface by up to a texel's worth of curvature, and rays
    // from there hit the surface itself (measured: bias -0.025 on the dragon).
    ivec2 full = ao.size.zw;
    bool halfRes = any(notEqual(size, full));
    ivec2 q = p;
    float d = 0.0;
    if (halfRes) {
        for (int k = 0; k < 4; ++k) {
            ivec2 c = min(2 * p + ivec2(k & 1, k >> 1), full - 1);
            float z = texelFetch(uFullDepth, c, 0).r;
            if (!isSky(z) && (isSky(d) || z < d)) d = z, q = c;
        }
    } else {
        d = texelFetch(uDepth, p, 0).r;
    }
    if (isSky(d)) {
        imageStore(uAo, p, vec4(1.0));
#if AO_DIRECTIONAL
        imageStore(uDirectional, p, vec4(0.0, 0.0, 0.0, 1.0));
#endif
        return;
    }
    ivec2 grid = halfRes ? full : size;
    float tanHalf = ao.focal.z, aspect = ao.focal.w;
    vec2 uv = (vec2(q) + 0.5) / vec2(grid);
    vec3 P = viewPositionFromDepth(uv, d, tanHalf, aspect);
    vec3 nView = aoSafeNormal(halfRes ? texelFetch(uFullNormal, q, 0).xyz : texelFetch(uNormal, p, 0).xyz, P);
    if (dot(nView, -P) < 0.0) nView = -nView;  // facing the camera, as ref.ao
    vec3 wp = viewToWorldPoint(P), nrm = normalize(viewToWorldDir(nView));
    // The reference's origin offset (bvh.glsl gbufferRayOrigin).
    vec3 origin = gbufferRayOrigin(wp, nrm, d, frame.cameraPos.xyz, 2.0 * tanHalf / float(grid.y));
    int rays = int(ao.bitmask.z);
    float R = ao.radius.x;
    // Stratified over the pixel's rays (2 x 2 strata for 4, 1 x n below), a
    // fresh hash-based offset each frame: the temporal filter averages
    // independent estimates, so a long accumulation converges to ref.ao.
    int sx = rays == 4 ? 2 : 1, sy = rays == 4 ? 2 : rays;
    Rng rng = rngInit(uvec2(p), frameIndex(), RTAO_SEED);
    float visible = 0.0;
    vec3 bent = vec3(0.0);
    vec4 shSum = vec4(0.0);
    for (int s = 0; s < rays; ++s) {
        vec2 u = (vec2(float(s % sx), float(s / sx)) + rngNext2(rng)) / vec2(float(sx), float(sy));
        vec3 dir = cosineHemisphere(u, nrm);
        if (!traceAny(origin, dir, 0.0, R)) {
            visible += 1.0;
            vec3 dv = worldToViewDir(dir);
            bent += dv;
            shSum += shBasis(dv);
        }
    }
    float a = visible / float(rays);
    imageStore(uAo, p, vec4(a));
#if AO_DIRECTIONAL == 1
    imageStore(uDirectional, p, vec4(dot(bent, bent) > 1e-12 ? normalize(bent) : nView, a));
#elif AO_DIRECTIONAL == 2
    imageStore(uDirectional, p, shSum * (PI / float(rays)));
#endif
}
