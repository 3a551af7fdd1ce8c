// lpv.apply: outgoing indirect diffuse radiance from the accumulated volume
// (SPEC 3.6, normalization in docs/lpv.md): a cell's coefficients are the
// intensity I(w) of the light flowing through it, radiance L = I / s^2, and
// light arriving from direction w flows along -w, so the irradiance of a
// surface with normal n is E = max(0, <I, cosLobe(-n)>) / s^2.
// Specular (RTGI_LPV_SPECULAR): 3 samples along R (seed listing 8), each the
// radiance arriving from R, averaged, times the split-sum term (F0 A + B)
// when a BRDF LUT exists (RTGI_LPV_BRDF_LUT), else times F0.
// Leaks (docs/lpv.md, "Leaks"): RTGI_LPV_LOOKUP_GEOMETRY weights the 8 cells of the diffuse
// lookup by side and geometry-volume blocking (lib/lpv_lookup.glsl); RTGI_LPV_DAMPING damps
// it by the irradiance one cell behind the surface; RTGI_LPV_LOOKUP_VISIBILITY weights them by
// side and the cells' distance moments (lpv.visibility, Chebyshev as DDGI).
// Hooks: RTGI_LPV_BENT_NORMAL looks up along the AO pass's bent normal;
// RTGI_LPV_S3HO integrates against the SH visibility instead of the cosine.
// lpv.apply_resolution=half (RTGI_LPV_APPLY_HALF): one invocation per half-resolution texel, the
// nearest non-sky pixel of its 2x2 block moved along its tangent plane to the texel centre (as
// ao.downsample); the outputs are half-resolution and hold the albedo-free terms (irradiance / pi,
// specular radiance), its depth and view normal go to uLowGeometry; lpv/upsample.comp brings
// them to full resolution and multiplies by the full-resolution albedo and BRDF.
// Specular in a dispatch of its own (RTGI_LPV_APPLY_SPECULAR_ONLY, docs/lpv.md "Apply cost"): the
// same shader without the diffuse lookups, after the diffuse dispatch (compiled without
// RTGI_LPV_SPECULAR); each is lighter than the two in one (measured on the H200).
// lpv.sh_order=2 (RTGI_LPV_SH2): the volumes hold bands 0-2 (mat3, lib/sh.glsl);
// the irradiance uses the band-2 clamped cosine (A_2 = pi / 4), the specular
// lookup evaluates bands 0-2 (docs/lpv.md, "Second-order SH").
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"
#include "lib/depth.glsl"
#include "lib/brdf.glsl"
#include "lib/lpv_lookup.glsl"
#ifdef RTGI_LPV_APPLY_HALF
#include "lib/ao.glsl"
layout(rgba32f, binding = RTGI_LPV_IMG_APPLY_LOW_GEOMETRY) uniform writeonly image2D uLowGeometry;
#endif

layout(local_size_x = RTGI_LPV_LOCAL_2D, local_size_y = RTGI_LPV_LOCAL_2D) in;

layout(binding = RTGI_LPV_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
layout(binding = RTGI_LPV_TEX_VIEW_NORMAL) uniform sampler2D uViewNormal;
layout(binding = RTGI_LPV_TEX_ALBEDO) uniform sampler2D uAlbedo;
layout(binding = RTGI_LPV_TEX_MATERIAL) uniform sampler2D uMaterial;
layout(binding = RTGI_LPV_TEX_LIGHT_R) uniform sampler3D uLightR;
layout(binding = RTGI_LPV_TEX_LIGHT_G) uniform sampler3D uLightG;
layout(binding = RTGI_LPV_TEX_LIGHT_B) uniform sampler3D uLightB;
layout(binding = RTGI_LPV_TEX_BRDF_LUT) uniform sampler2D uBrdfLut;
layout(binding = RTGI_LPV_TEX_DIRECTIONAL) uniform sampler2D uDirectional;  // bent normal (xyz, view) or S3HO SH (view)
#ifdef RTGI_LPV_SH2
layout(binding = RTGI_LPV_TEX_LIGHT_HI_R) uniform sampler3D uLightHiR;
layout(binding = RTGI_LPV_TEX_LIGHT_HI_G) uniform sampler3D uLightHiG;
layout(binding = RTGI_LPV_TEX_LIGHT_HI_B) uniform sampler3D uLightHiB;
layout(binding = RTGI_LPV_TEX_LIGHT_LAST) uniform sampler3D uLightLast;
#define LpvSh mat3
#else
#define LpvSh vec4
#endif
layout(rgba16f, binding = RTGI_LPV_IMG_INDIRECT) uniform writeonly image2D uIndirect;
layout(rgba16f, binding = RTGI_LPV_IMG_SPECULAR) uniform writeonly image2D uSpecular;

#ifdef RTGI_LPV_SELF
// Self-illumination correction (docs/lpv.md, "Self-illumination"): the RSM gives the
// exitance of a sunlit receiver; the scheme lights a uniformly lit plane with
// kappa * exitance of its own light (lpv::planeSelfIrradiance), which is subtracted.
layout(binding = RTGI_LPV_TEX_APPLY_RSM_FLUX) uniform sampler2D uRsmFlux;
layout(binding = RTGI_LPV_TEX_APPLY_RSM_DEPTH) uniform sampler2D uRsmDepth;

// Exitance (rgb) from the sun of the plane through `plane` (normal n) at its point x: the
// RSM texel over x when the surface the RSM sees there lies in that plane (within a
// quarter cell), flux / (A_texel / cos); 0 where the plane is not lit or not there.
vec3 lpvPlaneExitanceAt(vec3 x, vec3 plane, vec3 n, float cosl) {
    vec4 c = lpv.rsmViewProj * vec4(x, 1.0);
    vec2 ndc = c.xy / c.w;
    if (any(greaterThan(abs(ndc), vec2(1.0)))) return vec3(0.0);
    int side = lpv.grid.w;
    ivec2 t = clamp(ivec2((ndc * 0.5 + 0.5) * float(side)), ivec2(0), ivec2(side - 1));
    vec3 q = rsmWorldPosition(t, texelFetch(uRsmDepth, t, 0).r);
    if (abs(dot(q - plane, n)) > 0.25 * lpvCellSize()) return vec3(0.0);
    return texelFetch(uRsmFlux, t, 0).rgb * cosl / lpv.rsm.x;
}

// The plane's exitance weighted by the scheme's lateral self-illumination kernel: ring
// weights (cells 0..4 away) of the 3D double model of a point on a plane, 8 steps, flow,
// energy conserving (docs/lpv.md): 93 % of the self-light comes from within 4 cells, the
// own cell's is negative. A uniformly lit plane gives its exitance back (weights sum to 1).
vec3 lpvOwnExitance(vec3 wp, vec3 n) {
    vec3 l = frame.sunDirection.xyz;  // towards the sun
    float cosl = dot(n, l);
    if (cosl <= 0.0) return vec3(0.0);
    const float ring[5] = float[5](-0.179, 0.406, 0.326, 0.213, 0.234);
    vec3 t1 = normalize(abs(n.y) < 0.9 ? cross(n, vec3(0.0, 1.0, 0.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
    vec3 t2 = cross(n, t1);
    vec3 m = ring[0] * lpvPlaneExitanceAt(wp, wp, n, cosl);
    for (int r = 1; r <= 4; ++r) {
        float a = (r & 1) != 0 ? 0.0 : 0.7853982;  // alternate rings turned by 45 degrees
        vec3 ringSum = vec3(0.0);
        for (int k = 0; k < 4; ++k) {
            float phi = a + float(k) * 1.5707963;
            vec3 x = wp + float(r) * lpvCellSize() * (cos(phi) * t1 + sin(phi) * t2);
            ringSum += lpvPlaneExitanceAt(x, wp, n, cosl);
        }
        m += ring[r] * 0.25 * ringSum;
    }
    return max(m, vec3(0.0));
}
#endif

#ifdef RTGI_LPV_CASCADED
// Cascades (docs/lpv.md, "Cascades"): one dispatch per cascade, finest first;
// each adds its weighted irradiance and specular radiance to running sums,
// the last one writes the outputs.
layout(binding = RTGI_LPV_TEX_APPLY_NEAR_R) uniform sampler3D uNearR;
layout(binding = RTGI_LPV_TEX_APPLY_NEAR_G) uniform sampler3D uNearG;
layout(binding = RTGI_LPV_TEX_APPLY_NEAR_B) uniform sampler3D uNearB;
layout(rgba32f, binding = RTGI_LPV_IMG_APPLY_SUM_E) uniform image2D uSumE;
layout(rgba32f, binding = RTGI_LPV_IMG_APPLY_SUM_S) uniform image2D uSumS;
layout(location = RTGI_LPV_LOC_APPLY_LAST) uniform int uLast;
#ifdef RTGI_LPV_SH2
layout(binding = RTGI_LPV_TEX_APPLY_NEAR_HI_R) uniform sampler3D uNearHiR;
layout(binding = RTGI_LPV_TEX_APPLY_NEAR_HI_G) uniform sampler3D uNearHiG;
layout(binding = RTGI_LPV_TEX_APPLY_NEAR_HI_B) uniform sampler3D uNearHiB;
layout(binding = RTGI_LPV_TEX_APPLY_NEAR_LAST) uniform sampler3D uNearLast;
#endif

// How far inside cascade j the point lies: 1 from kCascadeBlendCells + 1/2
// cells inside its border on, falling linearly to 0 half a cell inside it
// (where the trilinear lookup still reads only the cascade's own cells). The
// coarsest cascade: 1 wherever inside.
float lpvCascadeInside(int j, vec3 world) {
    vec4 o = lpv.cascadeOrigin[j];
    vec3 q = (world - o.xyz) / o.w;
    vec3 g = vec3(lpv.grid.xyz);
    float d = min(min(min(q.x, q.y), q.z), min(min(g.x - q.x, g.y - q.y), g.z - q.z));
    if (j == lpv.cascade.y - 1) return d >= 0.0 ? 1.0 : 0.0;
    return clamp((d - 0.5) / lpv.cascadeParams.x, 0.0, 1.0);
}

// Weights of this cascade i at a point (docs/lpv.md): u_i = w_i prod_{j<i}(1 - w_j)
// (cascade i is the finest one used there) for the near part, U_i = 1 -
// prod_{j<=i}(1 - w_j) (cascade i or a finer one is) for the far part.
vec2 lpvCascadeWeights(vec3 world) {
    float outside = 1.0;  // prod_{j<i} (1 - w_j)
    int i = lpv.cascade.x;
    for (int j = 0; j < i; ++j) outside *= 1.0 - lpvCascadeInside(j, world);
    float w = lpvCascadeInside(i, world);
    return vec2(w * outside, 1.0 - outside * (1.0 - w));
}
#endif

#ifdef RTGI_LPV_LOOKUP_GEOMETRY
layout(binding = RTGI_LPV_TEX_APPLY_GEOMETRY) uniform sampler3D uGeometry;  // corner lattice, (X+1, Y+1, Z+1)
layout(binding = RTGI_LPV_TEX_APPLY_GEOMETRY_AXES) uniform sampler3D uGeometryAxes;
#endif
#ifdef RTGI_LPV_SKY
layout(binding = RTGI_LPV_TEX_APPLY_SKY) uniform sampler3D uSky;  // band-1 SH of the cells' sky visibility
#endif
#ifdef RTGI_LPV_LOOKUP_VISIBILITY
layout(binding = RTGI_LPV_TEX_APPLY_VISIBILITY) uniform sampler3D uVisibility;  // (X N, Y N, Z) distance moments
#endif

// Where a lookup reads: the trilinear texture coordinate, or (weighted) the 8 stencil cells
// from `base` with weights w (lib/lpv_lookup.glsl).
struct LpvLookup {
    vec3 uvw;
    bool weighted;
    ivec3 base;
    float w[8];
};

LpvLookup lpvPlainLookup(vec3 world) {
    LpvLookup l;
    l.uvw = lpvCellCoord(world) / vec3(lpv.grid.xyz);
    l.weighted = false;
    return l;
}

// The diffuse lookup at `world` for the surface point wp with normal n.
LpvLookup lpvSurfaceLookup(vec3 world, vec3 wp, vec3 n) {
    LpvLookup l = lpvPlainLookup(world);
#ifdef RTGI_LPV_LOOKUP_GEOMETRY
    vec3 q = lpvCellCoord(world);
    float blocked[8];
    lpvGeometryBlocking(uGeometry, uGeometryAxes, lpv.leak.z != 0, q, blocked);
    lpvGeometryWeights(q, lpvCellCoord(wp), n, blocked, l.w);
    l.base = lpvStencilBase(q);
    l.weighted = true;
#elif defined(RTGI_LPV_LOOKUP_VISIBILITY)
    // The same side test, the cells' own visibility (Chebyshev bound of their distance moments)
    // instead of the geometry volume's blocking, with the view bias (a ceiling pixel at the restaurant's
    // back wall read the sunlit outside without it).
    vec3 q = lpvCellCoord(world);
    float blocked[8];
    lpvVisibilityBlockingFromView(uVisibility, q, normalize(frame.cameraPos.xyz - wp), lpv.grid.xyz, blocked);
    lpvGeometryWeights(q, lpvCellCoord(wp), n, blocked, l.w);
    l.base = lpvStencilBase(q);
    l.weighted = true;
#endif
    return l;
}

vec4 lpvFetch(sampler3D t, LpvLookup l) {
    if (!l.weighted) return texture(t, l.uvw);
    return lpvStencilFetch(t, l.base, l.w, lpv.grid.xyz);
}

// lpvFetch of the r, g, b volumes of one lookup in one pass over the stencil: each cell's weight
// test and clamped coordinate once for the three (the same sums, in the same order).
void lpvFetchRgb(sampler3D tr, sampler3D tg, sampler3D tb, LpvLookup l, out vec4 r, out vec4 g, out vec4 b) {
    if (!l.weighted) {
        r = texture(tr, l.uvw);
        g = texture(tg, l.uvw);
        b = texture(tb, l.uvw);
        return;
    }
    r = g = b = vec4(0.0);
    ivec3 top = lpv.grid.xyz - 1;
    for (int k = 0; k < 8; ++k) {
        if (!(l.w[k] > 0.0)) continue;
        ivec3 t = clamp(l.base + lpvStencilOffset(k), ivec3(0), top);
        r += l.w[k] * texelFetch(tr, t, 0);
        g += l.w[k] * texelFetch(tg, t, 0);
        b += l.w[k] * texelFetch(tb, t, 0);
    }
}

// Whether the lookup point lies in the grid (uvw in [0, 1]^3); outside it there is no LPV light.
bool lpvInGrid(LpvLookup lk) { return all(greaterThanEqual(lk.uvw, vec3(0.0))) && all(lessThanEqual(lk.uvw, vec3(1.0))); }

// Trilinear (or weighted) lookup; outside the grid there is no LPV light. Cascade i > 0:
// u_i near + U_i (total - near), for i = 0 w_0 total (docs/lpv.md); w = (u_i, U_i) at `world`
// (lpvCascadeWeights, computed once by the caller; unused for a single volume).
// Exact shortcuts (docs/lpv.md, "Apply cost"): where U_i = 0 (so u_i = 0) the cascade adds
// nothing and nothing is fetched; where u_i = U_i (no finer cascade there) the near part's
// weight u_i - U_i is 0 and only the total is fetched (U_i T_i, the same up to float rounding).
bool lpvSample(vec3 world, LpvLookup lk, vec2 w, out LpvSh r, out LpvSh g, out LpvSh b) {
    r = g = b = LpvSh(0.0);
    if (!lpvInGrid(lk)) return false;
#ifdef RTGI_LPV_CASCADED
    if (w.y == 0.0) return true;
#endif
#ifdef RTGI_LPV_SH2
    vec4 last = lpvFetch(uLightLast, lk);
    r = shFromParts(lpvFetch(uLightR, lk), lpvFetch(uLightHiR, lk), last.r);
    g = shFromParts(lpvFetch(uLightG, lk), lpvFetch(uLightHiG, lk), last.g);
    b = shFromParts(lpvFetch(uLightB, lk), lpvFetch(uLightHiB, lk), last.b);
#else
    lpvFetchRgb(uLightR, uLightG, uLightB, lk, r, g, b);
#endif
#ifdef RTGI_LPV_CASCADED
    if (lpv.cascade.x == 0) {
        r *= w.x;
        g *= w.x;
        b *= w.x;
    } else if (w.x == w.y) {
        r *= w.y;
        g *= w.y;
        b *= w.y;
    } else {
#ifdef RTGI_LPV_SH2
        vec4 nl = lpvFetch(uNearLast, lk);
        mat3 nr = shFromParts(lpvFetch(uNearR, lk), lpvFetch(uNearHiR, lk), nl.r);
        mat3 ng = shFromParts(lpvFetch(uNearG, lk), lpvFetch(uNearHiG, lk), nl.g);
        mat3 nb = shFromParts(lpvFetch(uNearB, lk), lpvFetch(uNearHiB, lk), nl.b);
#else
        vec4 nr, ng, nb;
        lpvFetchRgb(uNearR, uNearG, uNearB, lk, nr, ng, nb);
#endif
        r = w.x * nr + w.y * (r - nr);
        g = w.x * ng + w.y * (g - ng);
        b = w.x * nb + w.y * (b - nb);
    }
#endif
    return true;
}

// The AO pass writes bent normals / S3HO at AO resolution (half by default):
// address them by UV, not by this pass's pixel (nearest texel, no blending
// across depth edges).
vec4 directionalAt(vec2 uv) {
    ivec2 size = textureSize(uDirectional, 0);
    return texelFetch(uDirectional, clamp(ivec2(uv * vec2(size)), ivec2(0), size - 1), 0);
}

// albedo (1 - metallic) / pi, or 1 / pi at half resolution (lpv/upsample.comp multiplies the albedo).
vec3 lpvDiffuseFactor(vec3 albedo, float metallic) {
#ifdef RTGI_LPV_APPLY_HALF
    return vec3(INV_PI);
#else
    return diffuseAlbedo(albedo, metallic) * INV_PI;
#endif
}

void main() {
    ivec2 o = ivec2(gl_GlobalInvocationID.xy);  // output texel
#ifdef RTGI_LPV_APPLY_HALF
    ivec2 outSize = imageSize(uIndirect);
#else
    ivec2 outSize = frameSize();
#endif
    if (any(greaterThanEqual(o, outSize))) return;
#ifdef RTGI_LPV_APPLY_HALF
    // The surface of the texel as ao.downsample chooses it (lib/ao.glsl), except that a pixel must be
    // nearer by more than 1e-3 of the depth to replace the block's first: near-equal depths (a wall
    // facing the camera, a crease) then keep one pixel instead of flipping with the rounding of
    // positions (the choice decides the normal the texel shades with; the scale-invariance test
    // caught the flip).
    vec2 uv = (vec2(o) + 0.5) / vec2(outSize);
    ivec2 p;
    vec4 lowN;
    float d;
    vec3 halfPoint = aoHalfTexelPoint(uLinearDepth, uViewNormal, o, uv, frame.projParams.z, frame.projParams.w, p, lowN, d);
    // (The point leaves the texel centre's plane only where that plane leaves the block's depths — a
    // crease: continued behind the other face, where the volume holds the outside's light; a ceiling
    // texel at the restaurant's back wall read 0.22 against 0.03 inside.)
#if !defined(RTGI_LPV_APPLY_SPECULAR_ONLY)
#ifdef RTGI_LPV_CASCADED
    if (uLast != 0)
#endif
        imageStore(uLowGeometry, o, vec4(d, lowN.xyz));
#endif
#else
    ivec2 p = o;
    vec2 uv = (vec2(p) + 0.5) / vec2(outSize);
    float d = texelFetch(uLinearDepth, p, 0).r;
#endif
    vec3 diffuse = vec3(0.0), specular = vec3(0.0), irradiance = vec3(0.0);
    // lpv.sky=visibility: this cascade's cosine-weighted sky visibility at the lookup point and
    // its cascade weight u_i (1 for a single volume); alpha of the indirect output (compose's sky term).
    float skyVisible = 0.0, skyWeight = 0.0, skyAlpha = 1.0;
    if (!isSky(d)) {
#ifdef RTGI_LPV_APPLY_HALF
        vec3 vp = halfPoint;
#else
        vec3 vp = viewPositionFromDepth(uv, d, frame.projParams.z, frame.projParams.w);
#endif
        vec3 wp = viewToWorldPoint(vp);
        vec3 vn = texelFetch(uViewNormal, p, 0).xyz;
        vec3 n = dot(vn, vn) > 0.0 ? normalize(viewToWorldDir(vn)) : vec3(0.0, 1.0, 0.0);
        vec3 albedo = texelFetch(uAlbedo, p, 0).rgb;
        vec2 rm = texelFetch(uMaterial, p, 0).rg;
        float invArea = lpv.rsm.y;  // 1 / s^2: intensity -> radiance
        vec3 lookupN = n;
#ifdef RTGI_LPV_BENT_NORMAL
        vec3 bent = directionalAt(uv).xyz;
        if (dot(bent, bent) > 0.0) lookupN = normalize(viewToWorldDir(bent));
#endif
        LpvSh r, g, b;
#ifndef RTGI_LPV_APPLY_SPECULAR_ONLY
        // Half a cell along the normal: the light in front of the surface, as injected (3.3).
        vec3 lookupAt = wp + 0.5 * lpvCellSize() * n;
        // This cascade's weights (u_i, U_i) at the lookup point, once for the light, the sky
        // visibility, the self-illumination term and the sky alpha below.
#ifdef RTGI_LPV_CASCADED
        vec2 cw = lpvCascadeWeights(lookupAt);
#else
        vec2 cw = vec2(1.0);
#endif
        // Where the cascade has no weight (U_i = 0) its light, sky and self terms are 0: the
        // lookup weights (the moments' fetches) are not computed either (docs/lpv.md, "Apply cost").
        LpvLookup lk;
        if (cw.y != 0.0) lk = lpvSurfaceLookup(lookupAt, wp, n);
        else lk = lpvPlainLookup(lookupAt);
        if (lpvSample(lookupAt, lk, cw, r, g, b)) {
#ifdef RTGI_LPV_SKY
            // Not mirrored: V(w) is a function of the direction looked along, I(w) of the flow.
            // Weighted by u_i: nothing to fetch where it is 0.
            skyWeight = cw.x;
            if (skyWeight != 0.0) skyVisible = clamp(shCosineIntegral(lpvFetch(uSky, lk), n) * INV_PI, 0.0, 1.0);
#endif
#ifdef RTGI_LPV_S3HO
            // S3HO is band 1: the band-2 part of the light has no visibility to meet.
            vec4 w = shRotate(directionalAt(uv), mat3(frame.invView));
#ifdef RTGI_LPV_SH2
            vec3 e = vec3(dot(shLo(shMirror(r)), w), dot(shLo(shMirror(g)), w), dot(shLo(shMirror(b)), w));
#else
            vec3 e = vec3(dot(shMirror(r), w), dot(shMirror(g), w), dot(shMirror(b), w));
#endif
#else
            vec3 e = vec3(shCosineIntegral(shMirror(r), lookupN), shCosineIntegral(shMirror(g), lookupN),
                          shCosineIntegral(shMirror(b), lookupN));
#endif
#ifdef RTGI_LPV_DAMPING
            // The same irradiance one cell further back (half a cell behind the surface), plain trilinear.
            {
                LpvSh rb, gb, bb;
                vec3 behind = wp - 0.5 * lpvCellSize() * n;
#ifdef RTGI_LPV_CASCADED
                vec2 cwb = lpvCascadeWeights(behind);
#else
                vec2 cwb = vec2(1.0);
#endif
                if (lpvSample(behind, lpvPlainLookup(behind), cwb, rb, gb, bb)) {
                    vec3 eb = vec3(shCosineIntegral(shMirror(rb), lookupN), shCosineIntegral(shMirror(gb), lookupN),
                                   shCosineIntegral(shMirror(bb), lookupN));
                    e *= lpvDamping(e, eb);
                }
            }
#endif
            vec3 eSelf = vec3(0.0);
#if defined(RTGI_LPV_SELF) || defined(RTGI_LPV_SKY_SELF)
            // Weighted like the volume it stands for: all steps, or near + far of a cascade.
            float kappa = lpv.cascadeParams.y;
#ifdef RTGI_LPV_CASCADED
            kappa = lpv.cascade.x == 0 ? cw.x * lpv.cascadeParams.y
                                       : cw.x * lpv.cascadeParams.z + cw.y * (lpv.cascadeParams.y - lpv.cascadeParams.z);
#endif
#endif
#ifdef RTGI_LPV_SELF
            // 0 where the cascade has no weight: the 17 RSM taps are skipped (M is finite).
            if (kappa != 0.0) eSelf = kappa * lpvOwnExitance(wp, n);
#endif
#ifdef RTGI_LPV_SKY_SELF
            // The sky bounce's own exitance M = rho pi sky f (docs/lpv.md, "Sky bounce"): the receiver's
            // own (sky light varies slowly along a plane; ring taps like the sun's cost ~1 ms at 1080p).
            if (kappa != 0.0) {
                float f = skyWeight != 0.0 ? skyVisible
                                           : clamp(shCosineIntegral(lpvFetch(uSky, lk), n) * INV_PI, 0.0, 1.0);
                eSelf += kappa * PI * f * frame.sky.rgb * diffuseAlbedo(albedo, rm.y);
            }
#endif
#ifdef RTGI_LPV_CASCADED
            irradiance = e * invArea - eSelf;
#else
            diffuse = lpvDiffuseFactor(albedo, rm.y) * max(e * invArea - eSelf, vec3(0.0));
#endif
        }
#ifdef RTGI_LPV_CASCADED
        // .a: the running sum of u_i V_i (lpv.sky=visibility).
        float skySum = skyWeight * skyVisible;
        if (lpv.cascade.x > 0) {
            vec4 prev = imageLoad(uSumE, o);
            irradiance += prev.rgb;
            skySum += prev.a;
        }
        if (uLast == 0) imageStore(uSumE, o, vec4(irradiance, skySum));
        // Sum_i u_i = U of the last cascade: where no cascade covers the point the sky is not occluded.
        skyAlpha = skySum + 1.0 - cw.y;
        diffuse = lpvDiffuseFactor(albedo, rm.y) * max(irradiance, vec3(0.0));
#endif
#endif  // !RTGI_LPV_APPLY_SPECULAR_ONLY
#ifdef RTGI_LPV_SPECULAR
        vec3 v = normalize(frame.cameraPos.xyz - wp);
        vec3 R = reflect(-v, n);
        vec3 sum = vec3(0.0);
        for (int i = 1; i <= 3; ++i) {
            vec3 at = wp + R * (float(i) * lpvCellSize());
#ifdef RTGI_LPV_CASCADED
            vec2 ws = lpvCascadeWeights(at);
#else
            vec2 ws = vec2(1.0);
#endif
            if (lpvSample(at, lpvPlainLookup(at), ws, r, g, b))
                sum += max(vec3(shEvaluate(r, -R), shEvaluate(g, -R), shEvaluate(b, -R)), vec3(0.0));
        }
#if defined(RTGI_LPV_APPLY_HALF)
        vec3 brdf = vec3(1.0);  // lpv/upsample.comp applies it at full resolution
#elif defined(RTGI_LPV_BRDF_LUT)
        vec3 f0 = specularF0(albedo, rm.y);
        vec2 ab = texture(uBrdfLut, vec2(clamp(dot(n, v), 0.0, 1.0), rm.x)).rg;
        vec3 brdf = f0 * ab.x + ab.y;
#else
        vec3 brdf = specularF0(albedo, rm.y);
#endif
        vec3 radiance = sum * invArea;  // each cascade with its own 1/s^2
#ifdef RTGI_LPV_CASCADED
        if (lpv.cascade.x > 0) radiance += imageLoad(uSumS, o).rgb;
        if (uLast == 0) imageStore(uSumS, o, vec4(radiance, 0.0));
#endif
        specular = brdf * (radiance / 3.0) * lpv.rsm.z;
#endif
    }
#ifdef RTGI_LPV_CASCADED
    if (uLast == 0) return;
#endif
    float alpha = 1.0;  // the fraction of compose's sky term that reaches the pixel (docs/lpv.md, "Sky visibility")
#if defined(RTGI_LPV_SKY)
#ifdef RTGI_LPV_CASCADED
    alpha = clamp(skyAlpha, 0.0, 1.0);
#else
    alpha = skyWeight > 0.0 ? skyVisible : 1.0;
#endif
#endif
#ifndef RTGI_LPV_APPLY_SPECULAR_ONLY
    imageStore(uIndirect, o, vec4(diffuse * lpv.rsm.z, alpha));
#endif
#ifdef RTGI_LPV_SPECULAR
    imageStore(uSpecular, o, vec4(specular, 1.0));
#endif
}
