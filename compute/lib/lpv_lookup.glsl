// Leak remedies of the LPV lookup (issue 22; derivations in docs/lpv.md, "Leaks"), pure
// functions of cell coordinates (cell i spans [i, i + 1), its centre is i + 1/2):
// - geometry-aware trilinear weights: each of the 8 cells of the trilinear stencil keeps its
//   trilinear weight only if its centre lies in front of the shaded surface's tangent plane,
//   times the transmission 1 - beta of the geometry volume between the lookup point and the
//   cell centre ([Kir18]: geometry in the trilinear interpolation), renormalized;
// - derivative damping ([KD10], seed 000 §7): irradiance that is larger one cell behind the
//   surface than in front of it came through the surface, scaled by front / back.
#pragma once
#include "lib/sh.glsl"
#include "lib/lpv_shared.h"

// Stencil of the trilinear lookup at q: cell k (k = 0..7, bit 0 x, bit 1 y, bit 2 z) is
// lpvStencilBase(q) + lpvStencilOffset(k).
ivec3 lpvStencilBase(vec3 q) { return ivec3(floor(q - 0.5)); }
ivec3 lpvStencilOffset(int k) { return ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1); }
vec3 lpvStencilCentre(vec3 q, int k) { return vec3(lpvStencilBase(q) + lpvStencilOffset(k)) + 0.5; }

// The weighted sum of volume t over the 8 stencil cells from `base` (weights w, cells clamped to the
// border cells [0, grid - 1] as the sampler's CLAMP_TO_EDGE does; cells of weight 0 are not fetched).
// lpv/apply.comp's weighted lookups and the sky bounce's injection (lpv/inject.comp) read with it.
vec4 lpvStencilFetch(sampler3D t, ivec3 base, float w[8], ivec3 grid) {
    vec4 sum = vec4(0.0);
    ivec3 top = grid - 1;
    for (int k = 0; k < 8; ++k)
        if (w[k] > 0.0) sum += w[k] * texelFetch(t, clamp(base + lpvStencilOffset(k), ivec3(0), top), 0);
    return sum;
}
float lpvTrilinearWeight(vec3 q, int k) {
    vec3 f = (q - 0.5) - floor(q - 0.5);
    vec3 w = mix(1.0 - f, f, vec3(lpvStencilOffset(k)));
    return w.x * w.y * w.z;
}

// Blocking of the light that reaches the lookup point q from the cell centre c: B is the
// geometry volume's blocking SH at their midpoint; as in the propagation (SPEC 3.5, blocked =
// B(-d) with d the flow direction c -> q), surfaces facing the incoming light block it.
float lpvSegmentBlocking(vec4 B, vec3 q, vec3 c) {
    vec3 d = c - q;
    float l = length(d);
    return l > 0.0 ? clamp(shEvaluate(B, d / l), 0.0, 1.0) : 0.0;
}

// Two-sided (lpv.blocking=two-sided): axes = sum of A / s^2 |n| over the blockers (the area
// projected on the three axis planes); the area projected across the segment's direction w
// is sum A |n.w| / s^2 <= axes . |w| (|n.w| <= sum_i |n_i| |w_i|; equal for axis-aligned walls).
float lpvSegmentBlockingTwoSided(vec3 axes, vec3 q, vec3 c) {
    vec3 d = c - q;
    float l = length(d);
    return l > 0.0 ? clamp(dot(axes, abs(d / l)), 0.0, 1.0) : 0.0;
}

// blocked[k] of the 8 stencil cells around q from the geometry volume (corner lattice: texel
// g at cell coordinate g, (X+1, Y+1, Z+1) texels, linear filtering): the blocking SH gv, or
// with twoSided the axis blocking gvAxes, interpolated at the midpoint of q and the cell centre.
void lpvGeometryBlocking(sampler3D gv, sampler3D gvAxes, bool twoSided, vec3 q, out float blocked[8]) {
    vec3 scale = 1.0 / vec3(textureSize(gv, 0));
    for (int k = 0; k < 8; ++k) {
        vec3 c = lpvStencilCentre(q, k);
        vec3 uvw = (0.5 * (q + c) + 0.5) * scale;
        blocked[k] = twoSided ? lpvSegmentBlockingTwoSided(texture(gvAxes, uvw).xyz, q, c)
                              : lpvSegmentBlocking(texture(gv, uvw), q, c);
    }
}

// Weights of the 8 stencil cells at lookup point q for a surface point x with normal n
// (all in cell coordinates), blocked[k] from lpvSegmentBlocking. w_k = t_k [n.(c_k - x) > 0]
// (1 - blocked_k), divided by their sum. Fallbacks when the sum vanishes (every front cell
// fully blocked): the front-side weights t_k [n.(c_k - x) > 0] alone, and if those vanish too
// (impossible when q = x + n/2: the stencil cell farthest along n lies in front) the plain
// trilinear weights. Returns 2, 1 or 0: which of the three was used.
int lpvGeometryWeights(vec3 q, vec3 x, vec3 n, float blocked[8], out float w[8]) {
    float sum = 0.0, sumFront = 0.0;
    float front[8];
    for (int k = 0; k < 8; ++k) {
        float t = lpvTrilinearWeight(q, k);
        front[k] = dot(lpvStencilCentre(q, k) - x, n) > 0.0 ? t : 0.0;
        w[k] = front[k] * (1.0 - clamp(blocked[k], 0.0, 1.0));
        sum += w[k];
        sumFront += front[k];
    }
    int mode = 2;
    if (!(sum > 1e-6)) {
        mode = sumFront > 0.0 ? 1 : 0;
        sum = 0.0;
        for (int k = 0; k < 8; ++k) {
            w[k] = mode == 1 ? front[k] : lpvTrilinearWeight(q, k);
            sum += w[k];
        }
    }
    for (int k = 0; k < 8; ++k) w[k] /= sum;
    return mode;
}

// Derivative damping of one channel's irradiance: `front` at the lookup point (half a cell in
// front of the surface), `back` one cell further back (half a cell behind it). Light arriving
// at the front face cannot have been brighter behind the surface unless it passed through it:
// the lookup is scaled by front / back where back > front (1 for a field without a gradient
// along n, or one falling off behind the surface).
float lpvDamping(float front, float back) { return back > front && back > 0.0 ? max(front, 0.0) / back : 1.0; }
vec3 lpvDamping(vec3 front, vec3 back) {
    return vec3(lpvDamping(front.x, back.x), lpvDamping(front.y, back.y), lpvDamping(front.z, back.z));
}

// Per-cell visibility moments (lpv.lookup=visibility; docs/lpv.md, "Visibility moments"), as
// DDGI's irradiance probes: every cell stores, per direction w of an N x N octahedral map, the
// mean and mean square of the distance d (cell units, clamped to RTGI_LPV_VIS_MAX_DISTANCE) from
// its centre to the first surface along w. Cell c's map is the tile [c.x N, c.x N + N) x
// [c.y N, c.y N + N) of slice c.z of a (X N, Y N, Z) RG texture.

// Octahedral map of the unit sphere onto [0, 1]^2 and back (upper hemisphere inside the
// diamond |u| + |v| <= 1, the lower folded onto the corners).
vec2 lpvOctEncode(vec3 w) {
    vec3 a = w / (abs(w.x) + abs(w.y) + abs(w.z));
    vec2 e = a.xy;
    if (a.z < 0.0) e = (1.0 - abs(a.yx)) * vec2(a.x >= 0.0 ? 1.0 : -1.0, a.y >= 0.0 ? 1.0 : -1.0);
    return e * 0.5 + 0.5;
}
vec3 lpvOctDecode(vec2 uv) {
    vec2 e = uv * 2.0 - 1.0;
    vec3 w = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (w.z < 0.0) w.xy = (1.0 - abs(w.yx)) * vec2(w.x >= 0.0 ? 1.0 : -1.0, w.y >= 0.0 ? 1.0 : -1.0);
    return normalize(w);
}

// One-sided Chebyshev bound on P(d >= r) from the moments m = (E[d], E[d^2]): 1 for r <= E[d],
// else var / (var + (r - E[d])^2) with var = max(E[d^2] - E[d]^2, RTGI_LPV_VIS_MIN_VARIANCE).
float lpvChebyshev(vec2 m, float r) {
    if (r <= m.x) return 1.0;
    float var = max(m.y - m.x * m.x, RTGI_LPV_VIS_MIN_VARIANCE);
    float d = r - m.x;
    return var / (var + d * d);
}

// Texture coordinate of cell c's moments in direction w: the octahedral coordinate, clamped
// half a texel inside the cell's tile so the bilinear filter never reads a neighbour's tile;
// z at the slice's centre.
vec3 lpvVisibilityCoord(ivec3 c, vec3 w, ivec3 texSize) {
    float n = float(RTGI_LPV_VIS_RES);
    vec2 t = clamp(lpvOctEncode(w) * n, vec2(0.5), vec2(n - 0.5)) + vec2(c.xy) * n;
    return vec3(t, float(c.z) + 0.5) / vec3(texSize);
}

// blocked[k] = 1 - P_k^e of the 8 stencil cells around q, P_k the Chebyshev bound on P(d_k >= r_k):
// d_k the distance from cell k's centre c_k to geometry in the direction of q, r_k = |q - c_k|
// (cell units); e = RTGI_LPV_VIS_EXPONENT (lpv.visibility_exponent; DDGI's 3 sharpens the bound's
// soft tail behind thin walls, docs/lpv.md). Cells outside the grid (clamped, as the light fetch)
// use the border cell's map.
#ifndef RTGI_LPV_VIS_EXPONENT
#define RTGI_LPV_VIS_EXPONENT 1
#endif
// lpv.visibility_view_bias (cells; lpv/apply.comp): 0 tests against the lookup point itself.
#ifndef RTGI_LPV_VIS_VIEW_BIAS
#define RTGI_LPV_VIS_VIEW_BIAS 0.0
#endif
// blocked[k] of the stencil cells around q for light that reaches the point `target` (cell coordinates):
// the same bound with the direction and r_k taken from c_k to the target (lpv.apply's view bias).
void lpvVisibilityBlockingAt(sampler3D moments, vec3 q, vec3 target, ivec3 grid, out float blocked[8]) {
    ivec3 texSize = textureSize(moments, 0);
    for (int k = 0; k < 8; ++k) {
        vec3 c = lpvStencilCentre(q, k);
        vec3 d = target - c;
        float r = length(d);
        ivec3 cell = clamp(lpvStencilBase(q) + lpvStencilOffset(k), ivec3(0), grid - 1);
        float p = r > 0.0 ? lpvChebyshev(texture(moments, lpvVisibilityCoord(cell, d / r, texSize)).xy, r) : 1.0;
        float v = p;
        for (int i = 1; i < RTGI_LPV_VIS_EXPONENT; ++i) v *= p;
        blocked[k] = 1.0 - v;
    }
}
void lpvVisibilityBlocking(sampler3D moments, vec3 q, ivec3 grid, out float blocked[8]) {
    lpvVisibilityBlockingAt(moments, q, q, grid, blocked);
}
// The receivers' test (lpv.apply, the sky bounce's injection): against RTGI_LPV_VIS_VIEW_BIAS cells from q
// along toCamera, the unit direction from the surface point to the camera (DDGI's view bias; docs/lpv.md,
// "View bias of the visibility test"): the segment from a visible surface to the camera is free space, so
// the point lies on the visible side of every surface near the pixel, also of a second one at a crease,
// which the normal offset to q alone leaves q on.
void lpvVisibilityBlockingFromView(sampler3D moments, vec3 q, vec3 toCamera, ivec3 grid, out float blocked[8]) {
    lpvVisibilityBlockingAt(moments, q, q + float(RTGI_LPV_VIS_VIEW_BIAS) * toCamera, grid, blocked);
}
