// Pure AO estimator functions (XeGTAO style: every input is a parameter, no
// bindings), shared by compute/ao/*.comp and the GPU tests. View space:
// camera at the origin looking down -z; "depth" = positive distance along -z.
#pragma once
#include "lib/depth.glsl"
#include "lib/math.glsl"

// Seed 003 eq. 5.3: a view-space radius R at depth z covers
// 0.5 * R * focal / z in texture space, focal = (cot(fovY/2)/aspect, cot(fovY/2)).
vec2 aoTextureRadius(float R, float depth, vec2 focal) { return 0.5 * R * focal / depth; }

// Seed 003 eqs. 3.1-3.3 (Kajalin): visibility of a sample point at depth
// zSample against the scene depth zScene seen through it, invalidated
// relative to the scene depth (camera-distance dependent by design, SPEC 11.7).
float ssaoDiskSampleValue(float zCenter, float zSample, float zScene) {
    float visibility = zScene > zSample ? 1.0 : 0.0;
    float validity = 1.0 - clamp((zCenter - zScene) / zScene, 0.0, 1.0);
    return mix(0.5, visibility, validity);
}

// Seed 003 5.1.3: full-sphere estimators see half of the samples occluded on
// a plane; clip above 0.5 and scale by 2 (plane -> 1). Used by ssao-disk
// (edge-highlight removal) and as the normalization of ssao-sphere and VO.
float halfSpaceNormalize(float visibleFraction) { return min(visibleFraction, 0.5) * 2.0; }

// Seed 003 eq. 3.6: unoccluded length of a line sample of half-length zs
// (unit sphere) when the scene lies dr sphere radii behind the centre, clamped
// to the line (0 .. 2 zs).
float voLineFree(float zs, float dr) { return clamp(min(zs, dr) + zs, 0.0, 2.0 * zs); }

// HBAO tangent vector of the slice through the view point P along the view-
// space direction (dir, 0): the tangent plane (normal n) cut with the plane
// through the eye spanned by P and dir, oriented towards dir. Falls back to
// the view-aligned tangent when the two planes coincide.
vec3 hbaoSliceTangent(vec3 P, vec3 n, vec2 dir) {
    vec3 sliceNormal = cross(P, vec3(dir, 0.0));
    vec3 T = cross(sliceNormal, n);
    if (dot(T, T) < 1e-12) return vec3(dir, -dot(n.xy, dir) / max(n.z, 0.05));
    // T = a P + b (dir, 0); marching towards +dir on screen means b > 0.
    return dot(cross(P, T), sliceNormal) < 0.0 ? -T : T;
}

// HBAO attenuation W(r) = 1 - r^2/R^2 (Bavoil & Sainz 2008).
float hbaoFalloff(float r2, float R2) { return clamp(1.0 - r2 / R2, 0.0, 1.0); }

// [FM08] range check: blockers farther than R from the receiver fade out.
float rangeAttenuation(float R, float distance) { return smoothstep(0.0, 1.0, R / max(distance, 1e-6)); }

// GTAO (Jimenez et al. 2016, eq. 10): cosine-weighted visible arc of one
// slice between horizon angles h0 <= n <= h1 (n: angle of the projected
// normal), times the projected normal length.
float gtaoSliceVisibility(float h0, float h1, float n, float projNormalLength) {
    float cosN = cos(n), sinN = sin(n);
    float a0 = 0.25 * (cosN + 2.0 * h0 * sinN - cos(2.0 * h0 - n));
    float a1 = 0.25 * (cosN + 2.0 * h1 * sinN - cos(2.0 * h1 - n));
    return projNormalLength * (a0 + a1);
}

// GTAO multi-bounce fit (Jimenez et al. 2016, eq. 14) for an albedo.
float gtaoMultiBounce(float visibility, float albedo) {
    float a = 2.0404 * albedo - 0.3324, b = -4.7951 * albedo + 0.6417, c = 2.7552 * albedo + 0.6903;
    float x = visibility;
    return max(x, ((x * a + b) * x + c) * x);
}

// Orthonormal basis around n, rotated by `tangentHint` (noise) about n.
// Returns a matrix with columns (t, b, n); n must be unit length.
mat3 aoBasis(vec3 n, vec3 tangentHint) {
    vec3 t = tangentHint - n * dot(tangentHint, n);
    if (dot(t, t) < 1e-8) t = abs(n.x) < 0.9 ? vec3(1, 0, 0) - n * n.x : vec3(0, 1, 0) - n * n.y;
    t = normalize(t);
    return mat3(t, cross(n, t), n);
}

// Seed 000 eq. 16 for one sender sample: rho/pi * L * (1 - V) * A_s cos(s) cos(r) / d^2,
// with the distance clamped to 0.25 R (the sender disc area A_s = pi R^2 / N
// makes the point-to-disc form factor invalid closer than that).
vec3 nearFieldSample(vec3 rho, vec3 senderRadiance, vec3 toSender, vec3 senderNormal, vec3 receiverNormal,
                     float senderArea, float R) {
    float d2 = max(dot(toSender, toSender), 0.0625 * R * R);
    vec3 l = toSender * inversesqrt(max(dot(toSender, toSender), 1e-12));
    float cosS = max(0.0, dot(senderNormal, -l)), cosR = max(0.0, dot(receiverNormal, l));
    return rho * INV_PI * senderRadiance * senderArea * cosS * cosR / d2;
}

// Depth along the ray through uv of the plane through the view-space point Q
// with normal nQ: the first-order (tangent-plane) reconstruction of the
// surface a depth texel holds, evaluated off the texel centre. Returns
// `fallback` (the texel's own depth) when the ray grazes the plane or the
// extension moves the depth by more than half of it (a silhouette, not a plane).
float aoPlaneDepthAlongRay(vec3 Q, vec3 nQ, vec2 uv, float tanHalfFov, float aspect, float fallback) {
    vec3 ray = viewPositionFromDepth(uv, 1.0, tanHalfFov, aspect);  // z = -1: t is the linear depth
    float denom = dot(nQ, ray);
    if (abs(denom) < 1e-4) return fallback;
    float t = dot(nQ, Q) / denom;
    return (t > 0.0 && abs(t - fallback) < 0.5 * fallback) ? t : fallback;
}

// Surface normal from the G-buffer, made safe: zero/NaN normals (holes,
// broken meshes) fall back to facing the viewer.
vec3 aoSafeNormal(vec3 n, vec3 viewPos) {
    float l2 = dot(n, n);
    if (!(l2 > 1e-6) || !(l2 < 1e6)) return normalize(-viewPos);
    return n * inversesqrt(l2);
}

// The surface half-resolution texel o stands for (ao.downsample; the half-resolution LPV apply): of
// its 2x2 full-resolution pixels the nearest non-sky one, nearer meaning nearer by more than `rel`
// of the depth (rel > 0: near-equal depths keep the first pixel in block order instead of flipping
// with the rounding of positions), its depth moved along its own tangent plane to the half texel's
// centre uvHalf, so that every estimator reconstructs a point on that plane. Returns the depth (0:
// sky); `at` is the chosen pixel, `n` its stored normal, `range` the least and largest depth of its
// non-sky pixels.
float aoHalfTexelSurface(sampler2D depth, sampler2D normal, ivec2 o, vec2 uvHalf, float rel, float tanHalfFov,
                         float aspect, out ivec2 at, out vec4 n, out vec2 range) {
    ivec2 full = textureSize(depth, 0);
    float d = 0.0;
    at = min(2 * o, full - 1);
    range = vec2(3.4e38, 0.0);
    for (int i = 0; i < 4; ++i) {
        ivec2 q = min(2 * o + ivec2(i & 1, i >> 1), full - 1);
        float dq = texelFetch(depth, q, 0).r;
        if (!isSky(dq)) range = vec2(min(range.x, dq), max(range.y, dq));
        if (!isSky(dq) && (isSky(d) || dq < d * (1.0 - rel))) d = dq, at = q;
    }
    n = texelFetch(normal, at, 0);
    if (isSky(d)) return d;
    vec3 Q = viewPositionFromDepth((vec2(at) + 0.5) / vec2(full), d, tanHalfFov, aspect);
    return aoPlaneDepthAlongRay(Q, aoSafeNormal(n.xyz, Q), uvHalf, tanHalfFov, aspect, d);
}

// How far depth d (aoHalfTexelSurface's moved depth) lies outside its block's depth `range` widened by
// `rel`, relative to d (0 inside). On a plane it is 0 (1/z is linear across the block); at a crease the
// plane continued to the texel centre can pass behind the other face (outside the room) or into the
// air in front of it.
float aoHalfTexelOutside(float d, vec2 range, float rel) {
    return max(max(range.x * (1.0 - rel) - d, d - range.y * (1.0 + rel)), 0.0) / d;
}

// The view-space point a half texel of lpv.apply shades (docs/lpv.md "Half-resolution apply"): the
// texel centre's point on its chosen pixel's plane (aoHalfTexelSurface), moved towards the pixel's own
// point as that plane leaves the block's depths (aoHalfTexelOutside, 10^-3 margin): all the way once it
// is 1 % outside, linearly before, so that rounding near the edge of the range changes the point by
// little. `dStore` is the matching depth (0: sky) for the upsample's weights.
vec3 aoHalfTexelPoint(sampler2D depth, sampler2D normal, ivec2 o, vec2 uvHalf, float tanHalfFov, float aspect,
                      out ivec2 at, out vec4 n, out float dStore) {
    vec2 range;
    float d = aoHalfTexelSurface(depth, normal, o, uvHalf, 1e-3, tanHalfFov, aspect, at, n, range);
    dStore = d;
    if (isSky(d)) return vec3(0.0);
    vec3 P = viewPositionFromDepth(uvHalf, d, tanHalfFov, aspect);
    float t = clamp(aoHalfTexelOutside(d, range, 1e-3) / 1e-2, 0.0, 1.0);
    if (t > 0.0) {
        float dOwn = texelFetch(depth, at, 0).r;
        P = mix(P, viewPositionFromDepth((vec2(at) + 0.5) / vec2(textureSize(depth, 0)), dOwn, tanHalfFov, aspect), t);
        dStore = mix(d, dOwn, t);
    }
    return P;
}

// ---- visibility bitmask (vbao; Therrien et al. 2023, docs/ao.md "Visibility bitmask") ----
// The slice of GTAO in view-angle coordinates (theta = 0 along V, positive
// towards the marching direction), n the projected normal's angle. The
// hemisphere of the slice [n - pi/2, n + pi/2] is cut into VBAO_SECTORS equal
// angular sectors, one bit each.
const int VBAO_SECTORS = 32;

// Signed cosine-weighted measure of the slice from 0 to h: the integral of
// |sin t| cos(t - n) dt (GTAO's integrand, Jimenez et al. 2016 eq. 10), so
// vbaoArc(b, n) - vbaoArc(a, n) is the weight of the arc [a, b] and
// gtaoSliceVisibility(h0, h1, n, 1) = vbaoArc(h1, n) - vbaoArc(h0, n).
float vbaoArc(float h, float n) { return sign(h) * 0.25 * (cos(n) - cos(2.0 * h - n) + 2.0 * h * sin(n)); }

// Bits of the sectors whose jittered point (k + jitter)/N of the hemisphere
// lies in the arc [a, b] (view angles): point-sampling each sector with one
// stratified offset makes the quantization unbiased over the jitter.
uint vbaoSectorMask(float a, float b, float n, float jitter) {
    const float N = float(VBAO_SECTORS);
    float xa = (a - (n - HALF_PI)) / PI, xb = (b - (n - HALF_PI)) / PI;
    int k0 = max(int(ceil(xa * N - jitter)), 0);
    int k1 = min(int(floor(xb * N - jitter)), VBAO_SECTORS - 1);
    if (k1 < k0) return 0u;
    int count = k1 - k0 + 1;
    uint run = count >= 32 ? 0xFFFFFFFFu : ((1u << uint(count)) - 1u);
    return run << uint(k0);
}

// Cosine-weighted measure of the sectors set in `occluded` (runs of set bits
// integrated in closed form, one vbaoArc pair per run).
float vbaoOccludedArc(uint occluded, float n) {
    const float w = PI / float(VBAO_SECTORS);
    float lo = n - HALF_PI, sum = 0.0;
    uint m = occluded;
    while (m != 0u) {
        int a = findLSB(m);
        uint gaps = ~m & (0xFFFFFFFFu << uint(a));
        int b = gaps == 0u ? 32 : findLSB(gaps);
        sum += vbaoArc(lo + float(b) * w, n) - vbaoArc(lo + float(a) * w, n);
        m = b >= 32 ? 0u : (m & (0xFFFFFFFFu << uint(b)));
    }
    return sum;
}

// Parameter interval [t0, t1] of the column X(t) = S + t s (s unit, t in
// [0, tMax]) inside the sphere |X - P| < R; false when it misses.
bool vbaoColumnInSphere(vec3 D, vec3 s, float tMax, float R, out vec2 t) {
    float b = dot(D, s), c = dot(D, D) - R * R;
    float disc = b * b - c;
    t = vec2(0.0);
    if (disc <= 0.0) return false;
    float q = sqrt(disc);
    t = vec2(max(-b - q, 0.0), min(-b + q, tMax));
    return t.x < t.y;
}

// Sectors of side sgn (+1 towards the marching direction) that the column
// behind the surface point S (linear depth zS) occludes: S pushed away from
// the camera along its view ray to depth zS + T, clipped to the ball
// |X - P| < R (docs/ao.md "Visibility bitmask", "Thickness").
uint vbaoColumnMask(vec3 P, vec3 V, vec3 S, float zS, float T, float R, float sgn, float nAngle, float jitter) {
    float lenS = length(S);
    vec3 sHat = S / lenS, D = S - P;
    vec2 t;
    if (!vbaoColumnInSphere(D, sHat, T * lenS / zS, R, t)) return 0u;
    vec3 D0 = D + t.x * sHat, D1 = D + t.y * sHat;
    float l0 = length(D0), l1 = length(D1);
    if (l0 < 1e-6 || l1 < 1e-6) return 0u;
    float a = sgn * acos(clamp(dot(D0 / l0, V), -1.0, 1.0));
    float b = sgn * acos(clamp(dot(D1 / l1, V), -1.0, 1.0));
    return vbaoSectorMask(min(a, b), max(a, b), nAngle, jitter);
}
