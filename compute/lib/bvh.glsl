// BVH traversal over the flattened tree of src/scene/bvh.cpp: closest hit
// and any hit (shadow / AO rays). Stack-based, nearer child first; the
// triangle test is the watertight one of Woop, Benthin and Wald (JCGT 2013),
// the same arithmetic as the CPU side (src/scene/bvh.cpp intersectTriangle).
#pragma once
#include "lib/bvh_shared.h"
#include "lib/visibility_shared.h"  // RTGI_VISIBILITY_SUBPIXEL_BITS

layout(std430, binding = RTGI_SSBO_BVH_NODES) readonly buffer BvhNodeBlock { BvhNode bvhNodes[]; };
layout(std430, binding = RTGI_SSBO_BVH_TRIS) readonly buffer BvhTriBlock { BvhTriangle bvhTris[]; };

struct Hit {
    float t;
    uint triangle;  // original triangle id (GpuScene index buffer order)
    vec2 bary;      // weights of v1, v2
    uint leaf;      // index in bvhTris (leaf order): the vertices the test used
};

const float BVH_MISS = 1e30;

// Robust secondary-ray origin (Wächter & Binder, "A Fast and Robust Method
// for Avoiding Self-Intersection", Ray Tracing Gems ch. 6): p moves off the
// surface along the geometric normal n (facing the side the new ray leaves
// to) by 256 ulps of each coordinate, done on the float's integer bits, so
// the offset follows the point's own floating-point magnitude instead of a
// scene-size constant. W&B switch to a fixed offset (1/65536) for
// coordinates within 1/32 of zero, whose ulps are too small to cover the
// error of the arithmetic that produced them; that error is relative to the
// magnitudes the point was computed from, so here the region and the
// offset are scaled by `magnitude` (the largest |coordinate| involved: the
// point, the ray origin or camera it came from). magnitude = 1 is W&B's
// original; the offset never depends on the scene's size.
vec3 offsetRayOrigin(vec3 p, vec3 n, float magnitude) {
    ivec3 of = ivec3(256.0 * n);
    vec3 pi = intBitsToFloat(floatBitsToInt(p) + mix(of, -of, lessThan(p, vec3(0.0))));
    float m = max(magnitude, max(abs(p.x), max(abs(p.y), abs(p.z))));
    vec3 near0 = p + (m * (1.0 / 65536.0)) * n;
    return mix(pi, near0, lessThan(abs(p), vec3(m * (1.0 / 32.0))));
}
float maxAbs(vec3 v) { return max(abs(v.x), max(abs(v.y), abs(v.z))); }

// Largest distance from c to a point of the scene (the BVH root's box).
float bvhSceneReach(vec3 c) { return length(max(abs(bvhNodes[0].lo - c), abs(bvhNodes[0].hi - c))); }

// Origin of the first ray from a G-buffer point p = C + d·r (linear depth d
// on the view ray r through the pixel centre, depth.glsl; C the camera),
// normal n facing the camera. p can lie under the visible surface, by
// more than ulps of p, C or d (offsetRayOrigin, relative to max(|C|, d)):
// - interpolation: the stored depth is that of Σ b_k P_k, the triangle's
//   vertices interpolated with float barycentrics (the hardware's
//   perspective-correct interpolation; visSurface's homogeneous
//   barycentrics from clip-space cross products). Rounding the b_k moves
//   the point by ~u·max_k |P_k − C| (u = 2^-24) along the triangle however
//   far the pixel is from the vertices, and p inherits the depth change:
//   measured at most 1.2·u·max_k |P_k − C| from the surface along n on
//   llvmpipe (both raster paths) and on NVIDIA's compute path, but 13.4·u
//   on NVIDIA's hardware rasterizer (H200, driver 580: its interpolation
//   is coarser). The G-buffer keeps no triangle: max_k |P_k − C| ≤ the
//   scene's reach from C, and p moves by 16·u·reach.
// - coverage: both rasterizers test coverage with vertices snapped to
//   2^-RTGI_VISIBILITY_SUBPIXEL_BITS pixel, so a pixel centre up to
//   δ = √2·2^-(bits+1) pixel outside a triangle B can show B's plane
//   extended, where the neighbour A sharing that edge is the visible
//   surface. In a concave crease B's extension lies under A, by the world
//   length on B of δ pixels times the sine of the crease angle:
//   d·pixelAngle·δ·sin(crease)/cos θ_B (θ_B between B's normal and the
//   view ray; pixelAngle = 2·tan(fovY/2)/height). p moves by
//   d·pixelAngle·δ, i.e. sin(crease) ≤ cos θ_B is assumed: sharper creases
//   seen at grazing angles are not covered (the 1/cos θ_B bound brightens
//   contact AO for no measured gain).
// docs/reference.md "Ray origins" has the measurements.
const float GBUFFER_INTERPOLATION_ULPS = 16.0 * 5.9604645e-8;  // 16 u: the worst measured, 13.4 u (NVIDIA hardware path)
// The two terms above: a bound on p's distance from its surface along n.
float gbufferPointError(float d, vec3 cameraPos, float pixelAngle) {
    float interpolation = GBUFFER_INTERPOLATION_ULPS * bvhSceneReach(cameraPos);
    const float snap = 1.41421356 / float(2 << RTGI_VISIBILITY_SUBPIXEL_BITS);
    return interpolation + d * pixelAngle * snap;
}
vec3 gbufferRayOrigin(vec3 p, vec3 n, float d, vec3 cameraPos, float pixelAngle) {
    return offsetRayOrigin(p, n, max(maxAbs(cameraPos), d)) + gbufferPointError(d, cameraPos, pixelAngle) * n;
}

// Rays traced by this invocation; a kernel adds it once to the slot of its
// dispatch (slot = the dispatch's first sample index), so a progressive
// reference reads all counters back once at the end, not after every dispatch.
uint bvhRayCount = 0u;
layout(std430, binding = RTGI_SSBO_REF_COUNTER) buffer RayCounterBlock { uint rayCounter[]; };
void bvhCommitRayCount(uint slot) { atomicAdd(rayCounter[slot], bvhRayCount); }

// Slab test; RTGI_BVH_BOX_EXIT_SCALE (bvh_shared.h) keeps rounding from
// rejecting a box that the ray touches.
float bvhBox(uint node, vec3 o, vec3 invD, float tMin, float tMax) {
    vec3 t0 = (bvhNodes[node].lo - o) * invD, t1 = (bvhNodes[node].hi - o) * invD;
    vec3 tn = min(t0, t1), tf = max(t0, t1) * RTGI_BVH_BOX_EXIT_SCALE;
    float enter = max(max(tn.x, tn.y), max(tn.z, tMin));
    float exit = min(min(tf.x, tf.y), min(tf.z, tMax));
    return enter <= exit ? enter : BVH_MISS;
}

// Per-ray constants of the watertight triangle test (Woop, Benthin, Wald,
// "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013, section 3): kz
// is the axis of the largest |d| component, kx and ky follow it cyclically
// and are swapped where d[kz] < 0 (keeps the winding); the shear
// (d[kx]/d[kz], d[ky]/d[kz], 1/d[kz]) turns the ray into +z from (0, 0).
// Same tie-breaking as src/scene/bvh.cpp watertightRay.
struct BvhRay {
    vec3 o;
    ivec3 k;  // kx, ky, kz
    vec3 s;   // sx, sy, sz
};

BvhRay bvhRay(vec3 o, vec3 d) {
    vec3 a = abs(d);
    int kz = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (d[kz] < 0.0) {
        int x = kx;
        kx = ky;
        ky = x;
    }
    BvhRay r;
    r.o = o;
    r.k = ivec3(kx, ky, kz);
    r.s = vec3(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
    return r;
}

// v[k] by selects: a vector indexed by a run-time int went through memory
// on NVIDIA (the reference traced 37 % fewer rays per second on an H200).
float bvhAxis(vec3 v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }

// Section 4 of the paper: the vertices relative to the origin, sheared into
// 2D; u, v, w are twice the signed areas of (0, B, C), (0, C, A), (0, A, B),
// the unnormalized barycentrics of v0, v1, v2. A neighbour sharing an edge
// computes it from the same sheared vertices in the other order, exactly
// the negated float unless a product is fused into the subtraction:
// `precise` forbids that (and keeps the GPU's arithmetic the CPU's). A ray
// through a shared edge then hits one of the two triangles, never neither.
bool bvhTriangle(uint i, BvhRay r, float tMin, inout Hit hit) {
    vec3 a = bvhTris[i].v0.xyz - r.o, b = bvhTris[i].v1.xyz - r.o, c = bvhTris[i].v2.xyz - r.o;
    float az0 = bvhAxis(a, r.k.z), bz0 = bvhAxis(b, r.k.z), cz0 = bvhAxis(c, r.k.z);
    precise float ax = bvhAxis(a, r.k.x) - r.s.x * az0, ay = bvhAxis(a, r.k.y) - r.s.y * az0;
    precise float bx = bvhAxis(b, r.k.x) - r.s.x * bz0, by = bvhAxis(b, r.k.y) - r.s.y * bz0;
    precise float cx = bvhAxis(c, r.k.x) - r.s.x * cz0, cy = bvhAxis(c, r.k.y) - r.s.y * cz0;
    precise float u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    // An edge function of exactly 0 may be a tie of two rounded products:
    // float products are exact in double, so the difference recomputed there
    // has the true sign (the paper's fallback; GLSL 4.0 core has double).
    if (u == 0.0 || v == 0.0 || w == 0.0) {
        u = float(double(cx) * double(by) - double(cy) * double(bx));
        v = float(double(ax) * double(cy) - double(ay) * double(cx));
        w = float(double(bx) * double(ay) - double(by) * double(ax));
    }
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
    float det = u + v + w;
    if (det == 0.0) return false;  // the ray lies in the triangle's plane
    precise float az = r.s.z * az0, bz = r.s.z * bz0, cz = r.s.z * cz0;
    float inv = 1.0 / det;
    precise float t = (u * az + v * bz + w * cz) * inv;
    if (!(t > tMin && t < hit.t)) return false;
    hit.t = t;
    hit.triangle = floatBitsToUint(bvhTris[i].v0.w);
    hit.bary = vec2(v, w) * inv;
    hit.leaf = i;
    return true;
}

// 1/d with near-zero components replaced by ±1e-20 (no 0·inf in the slab test).
vec3 bvhSafeInverse(vec3 d) {
    vec3 s = vec3(greaterThanEqual(d, vec3(0.0))) * 2.0 - 1.0;
    return 1.0 / mix(d, s * 1e-20, lessThan(abs(d), vec3(1e-20)));
}

// anyHit: stop at the first hit (visibility); otherwise the closest one.
// hit.t carries tMax in and the hit distance out.
bool bvhTrace(vec3 o, vec3 d, float tMin, inout Hit hit, bool anyHit) {
    ++bvhRayCount;
    vec3 invD = bvhSafeInverse(d);
    BvhRay ray = bvhRay(o, d);
    uint stack[RTGI_BVH_STACK];
    int sp = 0;
    uint node = 0u;
    bool found = false;
    if (bvhBox(0u, o, invD, tMin, hit.t) >= BVH_MISS) return false;
    for (;;) {
        uint count = bvhNodes[node].count;
        if (count > 0u) {
            uint first = bvhNodes[node].index;
            for (uint i = first; i < first + count; ++i)
                if (bvhTriangle(i, ray, tMin, hit)) {
                    found = true;
                    if (anyHit) return true;
                }
        } else {
            uint a = bvhNodes[node].index, b = a + 1u;
            float ta = bvhBox(a, o, invD, tMin, hit.t);
            float tb = bvhBox(b, o, invD, tMin, hit.t);
            if (tb < ta) {
                uint x = a; a = b; b = x;
                float y = ta; ta = tb; tb = y;
            }
            if (ta < BVH_MISS) {
                if (tb < BVH_MISS) stack[sp++] = b;
                node = a;
                continue;
            }
        }
        // A pushed child's box was hit when pushed, against hit.t then. An
        // any-hit trace has not changed hit.t since (it returns at its first
        // hit), so the re-test would pass: only closest-hit traces repeat it.
        bool next = false;
        while (sp > 0) {
            node = stack[--sp];
            if (anyHit || bvhBox(node, o, invD, tMin, hit.t) < BVH_MISS) {
                next = true;
                break;
            }
        }
        if (!next) return found;
    }
}

bool traceClosest(vec3 o, vec3 d, float tMin, float tMax, out Hit hit) {
    hit.t = tMax;
    hit.triangle = 0u;
    hit.bary = vec2(0.0);
    hit.leaf = 0u;
    return bvhTrace(o, d, tMin, hit, false);
}

bool traceAny(vec3 o, vec3 d, float tMin, float tMax) {
    Hit hit;
    hit.t = tMax;
    return bvhTrace(o, d, tMin, hit, true);
}

// First vertex x1 of a pixel's paths and AO rays (ref/path.comp, ref/ao.comp;
// docs/reference.md "First rays from the G-buffer"). The G-buffer point
// p = C + d·r can lie behind a surface that the pixel-centre ray r meets
// first: where two surfaces meet in a concave crease, the depth test and
// coverage decide ties in either's favour (depth resolution, snapped
// vertices, interpolation), and a wall that reaches past the crease (rooms
// of planes or overlapping slabs) then shows a point outside the room,
// whose rays start outside it. So the pixel-centre ray is traced from C
// (tMin just past the near plane, which clips the raster): x1 is its
// closest hit unless the G-buffer point lies in front of that hit by more
// than its own error — then the raster shows a surface the ray misses (a
// silhouette extended by coverage) and p, in front of every surface on the
// ray, is kept with gbufferRayOrigin. r has unit view depth, so t is a
// linear depth. The error of p along n, e = gbufferPointError, is
// e/|n·r| in depth (2×, grazing angles capped at |n·r| = |r|/4 past which p
// is kept). The hit point is interpolated from the hit triangle's vertices
// relative to C: its distance from the plane is off by at most ~9u times
// the largest |P_k − C| coordinate (four roundings of each term, the
// weights summing to 1 ± u), hence 16u of it along the hit's geometric
// normal (facing the camera) on top of offsetRayOrigin — but at least e,
// the G-buffer point's offset: with 16u alone the V-groove AO test
// (test_gbuffer_origin.cpp) came out 0.0034 (5 σ) darker than Lambert's
// formula, with e 0.0011 brighter (1.6 σ), as with the G-buffer point; the
// cause of the darkening is not found yet (docs/reference.md). Albedo and
// material stay the G-buffer's (the surface the raster image shows); so
// does the shading normal n, unless p lies off the hit, along r, by more
// than the interpolation error alone: then the raster shows another surface
// than the ray's (a coverage or depth tie: the neighbour's plane extended
// behind a concave crease or in front of a convex edge) and a lobe about its
// n at x1 would partly point into x1's own surface, so x1 takes the hit's
// geometric normal.
struct FirstVertex {
    vec3 position;   // x1
    vec3 origin;     // x1 moved off its surface: where the rays leaving x1 start
    vec3 geometric;  // geometric normal at x1, facing the camera
    vec3 normal;     // shading normal at x1: n, or `geometric` where the raster shows another surface
    bool traced;     // x1 is the traced hit (false: the G-buffer point)
};
const float TRACED_POINT_ULPS = 16.0 * 5.9604645e-8;
FirstVertex gbufferFirstVertex(vec3 cameraPos, vec3 p, vec3 r, float d, vec3 n, float near, float pixelAngle) {
    FirstVertex x;
    float e = gbufferPointError(d, cameraPos, pixelAngle);
    float perDepth = 2.0 / max(abs(dot(n, r)), 0.25 * length(r));  // 2× a distance along n, in depth along r
    float tol = e * perDepth;
    Hit h;
    if (traceClosest(cameraPos, r, near * (1.0 + 1.0 / 1024.0), d + tol, h)) {
        vec3 a = bvhTris[h.leaf].v0.xyz - cameraPos, b = bvhTris[h.leaf].v1.xyz - cameraPos,
             c = bvhTris[h.leaf].v2.xyz - cameraPos;
        x.position = cameraPos + ((1.0 - h.bary.x - h.bary.y) * a + h.bary.x * b + h.bary.y * c);
        vec3 ng = cross(b - a, c - a);
        float len = length(ng);
        ng = len > 0.0 ? ng / len : n;
        if (dot(ng, r) > 0.0) ng = -ng;
        float reach = max(maxAbs(a), max(maxAbs(b), maxAbs(c)));
        x.origin = offsetRayOrigin(x.position, ng, max(maxAbs(cameraPos), h.t)) + max(TRACED_POINT_ULPS * reach, e) * ng;
        x.geometric = ng;
        float interpolation = GBUFFER_INTERPOLATION_ULPS * bvhSceneReach(cameraPos);
        x.normal = abs(d - h.t) > interpolation * perDepth ? ng : n;
        x.traced = true;
    } else {
        x.position = p;
        x.origin = gbufferRayOrigin(p, n, d, cameraPos, pixelAngle);
        x.geometric = n;
        x.normal = n;
        x.traced = false;
    }
    return x;
}
