// ao.rtao: ray-traced AO at AO resolution through the scene's BVH (the
// reference's traversal, lib/bvh.glsl): ao.rays cosine-weighted rays of
// length R = ao.radius per pixel and frame from the G-buffer surface, the
// estimate of ref.ao's definition (docs/reference.md) with few rays; the
// blur / temporal / upsample chain of the screen-space variants filters it.
// Defines: AO_DIRECTIONAL 0 off, 1 bent normal of the visible rays, 2 S3HO
// band 0-1 SH (pi/N sum V Y, as lib/ao_estimators.glsl aoDirectional).
// RTAO_RAY_RATE (ao.ray_rate) 1 every pixel traces; 2 / 4 one pixel of each
// pair / 2x2 quad traces, rotating with the frame, and the others take the
// mean of their compatible traced neighbours (docs/ao.md, "Sparse rays").
#include "lib/common.glsl"
#include "lib/bvh_shared.h"
#include "lib/depth.glsl"
#include "lib/ao_shared.h"
#include "lib/ao.glsl"
#include "lib/random.glsl"
#include "lib/sampling.glsl"
#include "lib/bvh.glsl"
#include "lib/sh.glsl"
#include "lib/filter.glsl"  // surfaceCompatible

#ifndef AO_DIRECTIONAL
#define AO_DIRECTIONAL 0
#endif
#ifndef RTAO_RAY_RATE
#define RTAO_RAY_RATE 1
#endif

// One invocation per block of RTAO_RAY_RATE pixels: 1x1, a pair 2x1, a quad
// 2x2. Exactly one pixel of a block traces in a frame, so the threads of a
// workgroup all trace (no idle lanes); the tile of a workgroup is 8x8 blocks.
// The C++ side dispatches over blocks of the same size (ao_shared.h).
const ivec2 RTAO_BLOCK = ivec2(RTGI_AO_RTAO_BLOCK_X(RTAO_RAY_RATE), RTGI_AO_RTAO_BLOCK_Y(RTAO_RAY_RATE));

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, binding = RTGI_UBO_AO) uniform AoBlock { AoParams ao; };
layout(binding = RTGI_AO_TEX_DEPTH) uniform sampler2D uDepth;    // AO-resolution linear depth (0 = sky)
layout(binding = RTGI_AO_TEX_NORMAL) uniform sampler2D uNormal;   // AO-resolution view-space normals
layout(binding = RTGI_AO_RTAO_TEX_FULL_DEPTH) uniform sampler2D uFullDepth;    // G-buffer linear depth
layout(binding = RTGI_AO_RTAO_TEX_FULL_NORMAL) uniform sampler2D uFullNormal;  // G-buffer view-space normals
layout(r16f, binding = RTGI_AO_IMG_AO) uniform writeonly image2D uAo;
layout(rgba16f, binding = RTGI_AO_IMG_DIRECTIONAL) uniform writeonly image2D uDirectional;

const uint RTAO_SEED = 0x52544130u;  // "RTA0": a sequence of its own, not the reference's

// The point a pixel traces from: linear depth d (0 = sky), view position P,
// view normal facing the camera.
struct RtaoSurface {
    float d;
    vec3 P;
    vec3 nView;
};

bool rtaoHalfRes() { return any(notEqual(ao.size.xy, ao.size.zw)); }

RtaoSurface rtaoSurface(ivec2 p) {
    // The traced point is a G-buffer texel's own surface point, as ref.ao's.
    // At half resolution that is the full-resolution texel of the 2x2 block
    // that ao.downsample keeps (the nearest non-sky one): the half-resolution
    // point is that texel's depth moved along its tangent plane, which lies
    // under a concave surface by up to a texel's worth of curvature, and rays
    // from there hit the surface itself (measured: bias -0.025 on the dragon).
    ivec2 full = ao.size.zw;
    bool halfRes = rtaoHalfRes();
    ivec2 q = p;
    RtaoSurface s;
    s.d = 0.0;
    if (halfRes) {
        for (int k = 0; k < 4; ++k) {
            ivec2 c = min(2 * p + ivec2(k & 1, k >> 1), full - 1);
            float z = texelFetch(uFullDepth, c, 0).r;
            if (!isSky(z) && (isSky(s.d) || z < s.d)) s.d = z, q = c;
        }
    } else {
        s.d = texelFetch(uDepth, p, 0).r;
    }
    s.P = vec3(0.0);
    s.nView = vec3(0.0, 0.0, 1.0);
    if (isSky(s.d)) return s;
    ivec2 grid = halfRes ? full : ao.size.xy;
    vec2 uv = (vec2(q) + 0.5) / vec2(grid);
    s.P = viewPositionFromDepth(uv, s.d, ao.focal.z, ao.focal.w);
    s.nView = aoSafeNormal(halfRes ? texelFetch(uFullNormal, q, 0).xyz : texelFetch(uNormal, p, 0).xyz, s.P);
    if (dot(s.nView, -s.P) < 0.0) s.nView = -s.nView;  // facing the camera, as ref.ao
    return s;
}

// AO and the directional term (AO_DIRECTIONAL 1: bent normal, AO; 2: S3HO)
// of one pixel; sky: unoccluded.
struct RtaoValue {
    float a;
    vec4 dir;
};

RtaoValue rtaoSky() { return RtaoValue(1.0, vec4(0.0, 0.0, 0.0, 1.0)); }

RtaoValue rtaoTrace(ivec2 p, RtaoSurface s) {
    bool halfRes = rtaoHalfRes();
    ivec2 grid = halfRes ? ao.size.zw : ao.size.xy;
    vec3 wp = viewToWorldPoint(s.P), nrm = normalize(viewToWorldDir(s.nView));
    // The reference's origin offset (bvh.glsl gbufferRayOrigin).
    vec3 origin = gbufferRayOrigin(wp, nrm, s.d, frame.cameraPos.xyz, 2.0 * ao.focal.z / float(grid.y));
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
    for (int k = 0; k < rays; ++k) {
        vec2 u = (vec2(float(k % sx), float(k / sx)) + rngNext2(rng)) / vec2(float(sx), float(sy));
        vec3 dir = cosineHemisphere(u, nrm);
        if (!traceAny(origin, dir, 0.0, R)) {
            visible += 1.0;
            vec3 dv = worldToViewDir(dir);
            bent += dv;
            shSum += shBasis(dv);
        }
    }
    RtaoValue v;
    v.a = visible / float(rays);
#if AO_DIRECTIONAL == 1
    v.dir = vec4(dot(bent, bent) > 1e-12 ? normalize(bent) : s.nView, v.a);
#elif AO_DIRECTIONAL == 2
    v.dir = shSum * (PI / float(rays));
#else
    v.dir = vec4(0.0);
#endif
    return v;
}

void rtaoStore(ivec2 p, RtaoValue v) {
    imageStore(uAo, p, vec4(v.a));
#if AO_DIRECTIONAL
    imageStore(uDirectional, p, v.dir);
#endif
}

#if RTAO_RAY_RATE == 1

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ao.size.xy))) return;
    RtaoSurface s = rtaoSurface(p);
    rtaoStore(p, isSky(s.d) ? rtaoSky() : rtaoTrace(p, s));
}

#else

layout(location = RTGI_AO_RTAO_LOC_FILL_DEPTH) uniform float uFillDepth;    // the blur's edge stop (render/filter.h)
layout(location = RTGI_AO_RTAO_LOC_FILL_NORMAL) uniform float uFillNormal;

// The workgroup's tile, one entry per pixel: what a traced pixel lends its
// neighbours (depth 0: nothing to lend, i.e. untraced, sky or outside).
#define RTAO_TILE_PIXELS (64 * RTAO_RAY_RATE)
const ivec2 RTAO_TILE = ivec2(gl_WorkGroupSize.xy) * RTAO_BLOCK;
shared float sDepth[RTAO_TILE_PIXELS];
shared vec3 sNormal[RTAO_TILE_PIXELS];
shared float sAo[RTAO_TILE_PIXELS];
#if AO_DIRECTIONAL
shared vec4 sDir[RTAO_TILE_PIXELS];
#endif

// The pixel of the block that traces this frame: rate 2 a checkerboard whose
// parity flips each frame; rate 4 the quad's corners in the order (0,0),
// (1,1), (1,0), (0,1) (consecutive frames diagonal). Over rate frames every
// pixel traces once.
ivec2 rtaoTracedOffset(ivec2 block, uint f) {
#if RTAO_RAY_RATE == 2
    return ivec2(int((uint(block.y) + f) & 1u), 0);  // block.x is even: x + y + f even
#else
    const ivec2 order[4] = ivec2[4](ivec2(0, 0), ivec2(1, 1), ivec2(1, 0), ivec2(0, 1));
    return order[f & 3u];
#endif
}

int rtaoTileIndex(ivec2 t) { return t.y * RTAO_TILE.x + t.x; }

void main() {
    ivec2 size = ao.size.xy;
    ivec2 tileOrigin = ivec2(gl_WorkGroupID.xy) * RTAO_TILE;
    ivec2 local = ivec2(gl_LocalInvocationID.xy) * RTAO_BLOCK;  // the block's first pixel in the tile
    ivec2 traced = local + rtaoTracedOffset(tileOrigin + local, frameIndex());
    // 1. Trace the block's traced pixel; every pixel of the block leaves its
    // entry in the tile.
    for (int k = 0; k < RTAO_RAY_RATE; ++k) {
        ivec2 t = local + ivec2(k % RTAO_BLOCK.x, k / RTAO_BLOCK.x);
        sDepth[rtaoTileIndex(t)] = 0.0;
    }
    ivec2 p = tileOrigin + traced;
    bool inside = all(lessThan(p, size));
    RtaoSurface s = inside ? rtaoSurface(p) : RtaoSurface(0.0, vec3(0.0), vec3(0.0, 0.0, 1.0));
    RtaoValue v = isSky(s.d) ? rtaoSky() : rtaoTrace(p, s);
    if (inside) rtaoStore(p, v);
    int i = rtaoTileIndex(traced);
    sDepth[i] = s.d;
    sNormal[i] = s.nView;
    sAo[i] = v.a;
#if AO_DIRECTIONAL
    sDir[i] = v.dir;
#endif
    // The other pixels of the block read what this and the neighbouring blocks' invocations wrote.
    barrier();
    // 2. Fill the block's other pixels from the traced pixels of their 3x3
    // neighbourhood in the tile whose surface continues theirs (the blur's
    // edge stop); a pixel with none (a depth or crease edge, sky around)
    // traces its own rays, so no value crosses an edge.
    for (int k = 0; k < RTAO_RAY_RATE; ++k) {
        ivec2 t = local + ivec2(k % RTAO_BLOCK.x, k / RTAO_BLOCK.x);
        ivec2 u = tileOrigin + t;
        if (t == traced || any(greaterThanEqual(u, size))) continue;
        RtaoSurface su = rtaoSurface(u);
        if (isSky(su.d)) {
            rtaoStore(u, rtaoSky());
            continue;
        }
        RtaoValue sum = RtaoValue(0.0, vec4(0.0));
        int n = 0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                ivec2 o = t + ivec2(dx, dy);
                if (any(lessThan(o, ivec2(0))) || any(greaterThanEqual(o, RTAO_TILE))) continue;
                int j = rtaoTileIndex(o);
                if (!surfaceCompatible(su.d, sDepth[j], su.nView, sNormal[j], uFillDepth, uFillNormal)) continue;
                sum.a += sAo[j];
#if AO_DIRECTIONAL
                sum.dir += sDir[j];
#endif
                ++n;
            }
        RtaoValue w;
        if (n == 0) {
            w = rtaoTrace(u, su);  // fallback: nothing compatible to borrow
        } else {
            w = RtaoValue(sum.a / float(n), sum.dir / float(n));
#if AO_DIRECTIONAL == 1
            w.dir.xyz = dot(w.dir.xyz, w.dir.xyz) > 1e-12 ? normalize(w.dir.xyz) : su.nView;
#endif
        }
        rtaoStore(u, w);
    }
}

#endif
