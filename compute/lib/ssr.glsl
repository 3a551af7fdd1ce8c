// Screen-space reflection tracers (seed 000 4.4, 5.4; SPEC 5) as pure
// functions of their inputs: a view-space ray, the camera, a depth texture
// (linear view depth, full resolution) or its min-depth pyramid.
//
// All three share one hit test: a ray segment whose view depth spans
// [rayNear, rayFar] hits a pixel of depth z when it reaches z and is not
// more than `thickness` behind it (McGuire & Mara 2014, sec. 2.3): with zero
// thickness a segment that crosses the surface still hits.
#pragma once
#include "lib/depth.glsl"

struct SsrCamera {
    float tanHalfFov, aspect, near, far;
    vec2 size;  // depth-buffer size in pixels
};

struct SsrHit {
    bool hit;
    vec2 uv;         // hit position in [0,1]^2
    float rayDepth;  // linear depth of the ray at the hit
};

SsrHit ssrMiss() { return SsrHit(false, vec2(0.0), 0.0); }

// Sky (0 in the G-buffer) sits at the far plane, where rays end.
float ssrSceneDepth(float d, float far) { return d > 0.0 ? d : far; }

bool ssrDepthHit(float rayNear, float rayFar, float sceneDepth, float thickness, float far) {
    return sceneDepth < far && rayFar >= sceneDepth && rayNear <= sceneDepth + thickness;
}

// Largest t with origin + t·dir inside the view frustum (origin inside).
// Side planes ±x ≤ kx·(−z), ±y ≤ ky·(−z); near −z ≥ n; far −z ≤ f.
float ssrFrustumExit(vec3 o, vec3 d, SsrCamera cam) {
    float kx = cam.tanHalfFov * cam.aspect, ky = cam.tanHalfFov;
    float t = 3.0e38;
    vec4 num = vec4(o.x + kx * o.z, -o.x + kx * o.z, o.y + ky * o.z, -o.y + ky * o.z);
    vec4 den = vec4(d.x + kx * d.z, -d.x + kx * d.z, d.y + ky * d.z, -d.y + ky * d.z);
    for (int i = 0; i < 4; ++i)
        if (den[i] > 0.0) t = min(t, -num[i] / den[i]);
    if (d.z > 0.0) t = min(t, (-cam.near - o.z) / d.z);
    if (d.z < 0.0) t = min(t, (-cam.far - o.z) / d.z);
    return max(t, 0.0);
}

// Reflection ray of a G-buffer pixel; false for invalid normals (zero,
// NaN, Inf) and for normals facing away from the viewer.
bool ssrReflectionRay(vec3 viewPos, vec3 normal, out vec3 dir) {
    dir = vec3(0.0, 0.0, -1.0);
    float nn = dot(normal, normal);
    if (!(nn > 1e-12 && nn < 1e12)) return false;  // also false for NaN
    vec3 n = normal * inversesqrt(nn);
    vec3 toEye = -viewPos * inversesqrt(max(dot(viewPos, viewPos), 1e-30));
    if (!(dot(n, toEye) > 0.0)) return false;
    dir = reflect(-toEye, n);
    return true;
}

// Start offset in (0, 1) of the first step from one blue-noise value
// (SPEC 6.1; lib/noise.glsl, an 8-bit UNORM channel k/255): the centre of
// byte k's 1/256 interval, so a ray never starts at its own origin (0) and
// never skips a whole first step (1).
float ssrJitter(float noise) { return (round(clamp(noise, 0.0, 1.0) * 255.0) + 0.5) / 256.0; }

// Confidence of a hit: 1 inside the screen, fading linearly to 0 over
// `edgeFade` (uv) at the borders and for rays that face the camera (their
// hits are back sides the depth buffer does not hold).
float ssrConfidence(SsrHit h, vec3 dir, float edgeFade) {
    if (!h.hit) return 0.0;
    vec2 e = min(h.uv, 1.0 - h.uv);
    float edge = clamp(min(e.x, e.y) / max(edgeFade, 1e-6), 0.0, 1.0);
    float facing = 1.0 - smoothstep(0.25, 0.75, dir.z);
    return edge * facing;
}

float ssrFetchDepth(sampler2D depthTex, vec2 pixel, SsrCamera cam) {
    ivec2 p = clamp(ivec2(floor(pixel)), ivec2(0), ivec2(cam.size) - 1);
    return ssrSceneDepth(texelFetch(depthTex, p, 0).r, cam.far);
}

// ---- linear: the seed's fixed view-space steps --------------------------
// `steps` equal steps along the ray clipped to the frustum, the first one
// shortened by `jitter`; the crossing is refined by 6 bisections.
SsrHit ssrTraceLinear(sampler2D depthTex, vec3 origin, vec3 dir, SsrCamera cam, int steps, float thickness,
                      float jitter) {
    float tMax = ssrFrustumExit(origin, dir, cam);
    if (!(tMax > 0.0)) return ssrMiss();
    ivec2 originPixel = ivec2(floor(uvFromViewPosition(origin, cam.tanHalfFov, cam.aspect).xy * cam.size));
    float dt = tMax / float(max(steps, 1));
    float tPrev = 0.0;
    for (int i = 0; i < steps; ++i) {
        float t = min((float(i) + jitter) * dt, tMax);
        vec3 q = origin + dir * t;
        vec3 uvd = uvFromViewPosition(q, cam.tanHalfFov, cam.aspect);
        vec2 pixel = uvd.xy * cam.size;
        if (ivec2(floor(pixel)) == originPixel) {
            tPrev = t;
            continue;
        }
        float dPrev = -(origin.z + dir.z * tPrev);
        if (ssrDepthHit(min(dPrev, uvd.z), max(dPrev, uvd.z), ssrFetchDepth(depthTex, pixel, cam), thickness,
                        cam.far)) {
            float a = tPrev, b = t;
            for (int k = 0; k < 6; ++k) {
                float m = 0.5 * (a + b);
                vec3 um = uvFromViewPosition(origin + dir * m, cam.tanHalfFov, cam.aspect);
                if (um.z >= ssrFetchDepth(depthTex, um.xy * cam.size, cam)) b = m;
                else a = m;
            }
            // The step's depth range covers everything it passed behind; the
            // crossing found by bisection must itself pass the thickness test,
            // else the ray went behind a thin surface and marches on.
            vec3 ua = uvFromViewPosition(origin + dir * a, cam.tanHalfFov, cam.aspect);
            vec3 ub = uvFromViewPosition(origin + dir * b, cam.tanHalfFov, cam.aspect);
            if (ssrDepthHit(min(ua.z, ub.z), max(ua.z, ub.z), ssrFetchDepth(depthTex, ub.xy * cam.size, cam),
                            thickness, cam.far))
                return SsrHit(true, ub.xy, ub.z);
        }
        tPrev = t;
    }
    return ssrMiss();
}

// ---- screen-space segment shared by DDA and Hi-Z -------------------------
// The clipped ray projected to pixels: P(s) = p0 + s·(p1 − p0), and 1/depth
// linear in s (perspective-correct interpolation).
struct SsrSegment {
    vec2 p0, delta;
    float k0, dk;
};

SsrSegment ssrScreenSegment(vec3 origin, vec3 dir, SsrCamera cam) {
    float tMax = ssrFrustumExit(origin, dir, cam);
    vec3 a = uvFromViewPosition(origin, cam.tanHalfFov, cam.aspect);
    vec3 b = uvFromViewPosition(origin + dir * tMax, cam.tanHalfFov, cam.aspect);
    return SsrSegment(a.xy * cam.size, (b.xy - a.xy) * cam.size, 1.0 / a.z, 1.0 / b.z - 1.0 / a.z);
}

float ssrSegmentDepth(SsrSegment g, float s) { return 1.0 / (g.k0 + g.dk * s); }

// ---- DDA: pixel-exact perspective-correct stepping (McGuire & Mara 2014) --
// Steps along the major axis; stride is one pixel when `steps` covers the
// segment, else the segment is divided into `steps` strides (then the hit is
// refined by bisection inside the last stride). The ray's depth range over
// the pixel is taken at ±half a stride (their eq. for rayZMin/rayZMax).
SsrHit ssrTraceDda(sampler2D depthTex, vec3 origin, vec3 dir, SsrCamera cam, int steps, float thickness,
                   float jitter) {
    SsrSegment g = ssrScreenSegment(origin, dir, cam);
    float len = max(abs(g.delta.x), abs(g.delta.y));
    if (!(len >= 1.0)) return ssrMiss();
    ivec2 originPixel = ivec2(floor(g.p0));
    float stride = max(1.0, len / float(max(steps, 1)));
    float ds = stride / len;
    for (int i = 0; i < steps; ++i) {
        float s = (float(i) + jitter) * ds;
        if (s > 1.0) break;
        vec2 pixel = g.p0 + g.delta * s;
        if (ivec2(floor(pixel)) == originPixel) continue;
        float za = ssrSegmentDepth(g, max(s - 0.5 * ds, 0.0)), zb = ssrSegmentDepth(g, min(s + 0.5 * ds, 1.0));
        float scene = ssrFetchDepth(depthTex, pixel, cam);
        if (ssrDepthHit(min(za, zb), max(za, zb), scene, thickness, cam.far)) {
            if (stride <= 1.0) return SsrHit(true, pixel / cam.size, clamp(scene, min(za, zb), max(za, zb)));
            // Coarse stride: bisect inside it; the crossing must pass the
            // thickness test (else the ray went behind a thin surface).
            float a = max(s - 0.5 * ds, 0.0), b = min(s + 0.5 * ds, 1.0);
            for (int k = 0; k < 6; ++k) {
                float m = 0.5 * (a + b);
                if (ssrSegmentDepth(g, m) >= ssrFetchDepth(depthTex, g.p0 + g.delta * m, cam)) b = m;
                else a = m;
            }
            vec2 pb = g.p0 + g.delta * b;
            float zA = ssrSegmentDepth(g, a), zB = ssrSegmentDepth(g, b);
            if (ssrDepthHit(min(zA, zB), max(zA, zB), ssrFetchDepth(depthTex, pb, cam), thickness, cam.far))
                return SsrHit(true, pb / cam.size, zB);
        }
    }
    return ssrMiss();
}

// ---- Hi-Z: hierarchical min-depth traversal -------------------------------
// `hiz` holds min linear depth per cell (sky = far), level L cell c covering
// pixels [c·2^L, (c+1)·2^L) (the last cell of an odd level also covers the
// left-over pixel). Where the ray stays in front of a cell's minimum it skips
// the cell and climbs a level; otherwise it advances to where it reaches the
// minimum and descends; at level 0 it applies the common hit test and passes
// behind surfaces more than `thickness` thick. `iterations` bounds the cells
// it advances over (descending a level does not count).
SsrHit ssrTraceHiz(sampler2D hiz, int levels, vec3 origin, vec3 dir, SsrCamera cam, int iterations,
                   float thickness) {
    SsrSegment g = ssrScreenSegment(origin, dir, cam);
    float len = max(abs(g.delta.x), abs(g.delta.y));
    if (!(len >= 1.0)) return ssrMiss();
    const float kCross = 0.02;  // pixels past a cell boundary, so the next floor() lands in the next cell
    vec2 invDelta = vec2(abs(g.delta.x) > 1e-6 ? 1.0 / g.delta.x : 3.0e38,
                         abs(g.delta.y) > 1e-6 ? 1.0 / g.delta.y : 3.0e38);
    float s = 1.0 / len;  // one pixel along the major axis: out of the origin pixel
    int level = 0, advances = 0;
    // `iterations` bounds the cells the ray advances over; descents are free
    // (at most `levels` between two advances), so the loop ends.
    for (int i = 0; advances < iterations && i < iterations * (levels + 1) && s <= 1.0; ++i) {
        vec2 p = g.p0 + g.delta * s;
        float cellSize = float(1 << level);
        ivec2 cell = clamp(ivec2(floor(p / cellSize)), ivec2(0), textureSize(hiz, level) - 1);
        float dmin = texelFetch(hiz, cell, level).r;
        vec2 boundary = (vec2(cell) + step(vec2(0.0), g.delta)) * cellSize;
        vec2 sb = (boundary - g.p0) * invDelta;
        sb = mix(sb, vec2(3.0e38), lessThan(abs(g.delta), vec2(1e-6)));
        float sExit = clamp(min(sb.x, sb.y), s, 1.0);
        float dEnter = ssrSegmentDepth(g, s), dExit = ssrSegmentDepth(g, sExit);
        float rayNear = min(dEnter, dExit), rayFar = max(dEnter, dExit);
        if (rayFar < dmin) {  // in front of everything in the cell
            s = sExit + kCross / len;
            ++advances;
            level = min(level + 1, levels - 1);
            continue;
        }
        if (level == 0) {
            if (ssrDepthHit(rayNear, rayFar, dmin, thickness, cam.far)) {
                float sHit = dEnter < dmin ? clamp((1.0 / dmin - g.k0) / g.dk, s, sExit) : s;
                return SsrHit(true, (g.p0 + g.delta * sHit) / cam.size, ssrSegmentDepth(g, sHit));
            }
            s = sExit + kCross / len;  // passes behind a thick surface (or reached the sky)
            ++advances;
            continue;
        }
        if (dEnter < dmin && abs(g.dk) > 0.0) s = clamp((1.0 / dmin - g.k0) / g.dk, s, sExit);
        level -= 1;
    }
    return ssrMiss();
}
