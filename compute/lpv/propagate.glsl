// One propagation step of a destination cell gathering from its 6
// neighbours (SPEC 3.5, [KD10] with the corrections of [Kir10b]): for a
// neighbour N one cell behind along the flow direction d, each of the 5
// faces f of the destination that do not face back receives
// Phi_f = dOmega_f * max(0, I_N(w_f)) and re-emits it as (Phi_f / pi) *
// cosLobe(n_f). Constants are derived in docs/lpv.md (not the seed's 0.82,
// SPEC 11.4). Shared by the compute path and the raster baseline.
#pragma once
#include "lpv/lpv_common.glsl"

const ivec3 LPV_AXES[6] = ivec3[6](ivec3(1, 0, 0), ivec3(-1, 0, 0), ivec3(0, 1, 0), ivec3(0, -1, 0),
                                   ivec3(0, 0, 1), ivec3(0, 0, -1));

// lpv.sh_order=2 (RTGI_LPV_SH2, compute path only): the same scheme on SH of bands 0-2
// (mat3, lib/sh.glsl); the includer defines lpvSource9, which completes a neighbour's
// band-1 texel with its band-2 coefficients (docs/lpv.md, "Second-order SH").
#ifdef RTGI_LPV_SH2
#define LpvSh mat3
#define lpvLobe shCosineLobe9
mat3 lpvSource9(vec4 lo, int colour, ivec3 cell);
#else
#define LpvSh vec4
#define lpvLobe shCosineLobe
#endif

// lpv.blocking=visibility (compute path; docs/lpv.md, "Face openness"): the traced open fraction
// of the slab between the centres of cells p and p + a (a an axis step, either sign).
#ifdef RTGI_LPV_PROPAGATE_VISIBILITY
layout(binding = RTGI_LPV_TEX_PROPAGATE_VISIBILITY) uniform sampler3D uFaceOpen;
float lpvFaceOpen(ivec3 p, ivec3 a) { return dot(texelFetch(uFaceOpen, p + min(a, ivec3(0)), 0).xyz, abs(vec3(a))); }
#endif

struct LpvRgb {
    LpvSh r, g, b;
};

// Sum of the quadrature over all 30 faces a source feeds (6 destinations x 5 faces).
float lpvQuadratureFlux(LpvSh I) {
    float q = 0.0;
    for (int a = 0; a < 6; ++a) {
        vec3 d = vec3(LPV_AXES[a]);
        q += RTGI_LPV_FRONT_SOLID_ANGLE * max(0.0, shEvaluate(I, d));
        for (int t = 0; t < 6; ++t) {
            if (dot(vec3(LPV_AXES[t]), d) != 0.0) continue;
            vec3 w = RTGI_LPV_SIDE_DIR_T * vec3(LPV_AXES[t]) + RTGI_LPV_SIDE_DIR_D * d;
            q += RTGI_LPV_SIDE_SOLID_ANGLE * max(0.0, shEvaluate(I, w));
        }
    }
    return q;
}

// lpv.energy_conserving: scale so a source emits exactly its flux 2 sqrt(pi) I_00
// (the integral of its intensity) instead of what the quadrature gives.
float lpvConservingScale(LpvSh I) {
    float q = lpvQuadratureFlux(I);
    float target = max(shBand0(I), 0.0) / RTGI_SH_Y00;
    return q > 0.0 ? target / q : 0.0;
}

// Blocking SH, mean albedo and two-sided axis blocking at the face between cell c and its
// neighbour c + o: the mean of the 4 corner-lattice texels spanning that face.
vec4 lpvFaceBlocking(sampler3D gv, sampler3D gvAlbedo, sampler3D gvAxes, ivec3 c, ivec3 o, out vec3 albedo,
                     out vec3 axes) {
    ivec3 base = c + max(o, ivec3(0));
    ivec3 u = o.x != 0 ? ivec3(0, 1, 0) : ivec3(1, 0, 0);
    ivec3 v = o.z != 0 ? ivec3(0, 1, 0) : ivec3(0, 0, 1);
    vec4 sum = vec4(0.0);
    albedo = axes = vec3(0.0);
    for (int i = 0; i < 4; ++i) {
        ivec3 g = base + ((i & 1) != 0 ? u : ivec3(0)) + ((i & 2) != 0 ? v : ivec3(0));
        sum += texelFetch(gv, g, 0);
        albedo += texelFetch(gvAlbedo, g, 0).rgb;
        if (lpv.leak.z != 0) axes += texelFetch(gvAxes, g, 0).xyz;
    }
    albedo *= 0.25;
    axes *= 0.25;
    return 0.25 * sum;
}

// Adds what flows from source intensity I (flow direction d) through the 5
// exit faces of the destination, scaled by `transmit`, to `dst`; returns the
// flux reaching the faces before transmission.
float lpvPropagateFaces(LpvSh I, vec3 d, float transmit, inout LpvSh dst) {
    float front = RTGI_LPV_FRONT_SOLID_ANGLE * max(0.0, shEvaluate(I, d));
    float total = front;
    dst += (front * transmit * INV_PI) * lpvLobe(d);
    for (int t = 0; t < 6; ++t) {
        vec3 nf = vec3(LPV_AXES[t]);
        if (dot(nf, d) != 0.0) continue;
        vec3 w = RTGI_LPV_SIDE_DIR_T * nf + RTGI_LPV_SIDE_DIR_D * d;
        float side = RTGI_LPV_SIDE_SOLID_ANGLE * max(0.0, shEvaluate(I, w));
        total += side;
        // lpv.reemit=flow: around the mean direction w of the flux crossing the face (its flux
        // is unchanged); KD10 (face): around the face normal, 57 degrees off (docs/lpv.md).
        dst += (side * transmit * INV_PI) * lpvLobe(lpv.cascade.w != 0 ? w : nf);
    }
    return total;
}

// Flux that source intensity I (flow direction d) sends through the 5 exit faces of the
// destination one cell ahead (the quadrature of lpvPropagateFaces, nothing re-emitted).
float lpvFacesFlux(LpvSh I, vec3 d) {
    float total = RTGI_LPV_FRONT_SOLID_ANGLE * max(0.0, shEvaluate(I, d));
    for (int t = 0; t < 6; ++t) {
        vec3 nf = vec3(LPV_AXES[t]);
        if (dot(nf, d) != 0.0) continue;
        total += RTGI_LPV_SIDE_SOLID_ANGLE * max(0.0, shEvaluate(I, RTGI_LPV_SIDE_DIR_T * nf + RTGI_LPV_SIDE_DIR_D * d));
    }
    return total;
}

// lpv.fuse > 1 (RTGI_LPV_FUSED, lpv/propagate_fused.comp): the sources are the previous step
// held in shared memory by the includer, which defines lpvSharedSource.
#ifdef RTGI_LPV_FUSED
void lpvSharedSource(ivec3 p, out LpvSh sh[3]);
#endif

// lpv.propagate_cascades=joint (RTGI_LPV_JOINT, lpv/propagate.comp): the sources are the
// cascade's slab of a stacked volume, cell p at p + lpvSlab (set once by main).
#ifdef RTGI_LPV_JOINT
ivec3 lpvSlab;
#define LPV_SOURCE_AT(p) ((p) + lpvSlab)
#else
#define LPV_SOURCE_AT(p) (p)
#endif

// The r, g, b SH of source cell p (band 2: the 9 coefficients, lpvSource9).
void lpvFetchSource(ivec3 p, sampler3D srcR, sampler3D srcG, sampler3D srcB, out LpvSh sh[3]) {
#if defined(RTGI_LPV_FUSED)
    lpvSharedSource(p, sh);
#elif defined(RTGI_LPV_SH2)
    sh = LpvSh[3](lpvSource9(texelFetch(srcR, p, 0), 0, p), lpvSource9(texelFetch(srcG, p, 0), 1, p),
                  lpvSource9(texelFetch(srcB, p, 0), 2, p));
#else
    sh = LpvSh[3](texelFetch(srcR, LPV_SOURCE_AT(p), 0), texelFetch(srcG, LPV_SOURCE_AT(p), 0),
                  texelFetch(srcB, LPV_SOURCE_AT(p), 0));
#endif
}

// Whether iteration `iteration` (1-based) meets the geometry: occlusion (and the bounce, which
// needs the blocked part) from iteration 2 on (seed 3.5.1), since the first step would let geometry
// occlude its own light; lpv.first_step=blocked (docs/lpv.md, "Leaks"): the first step is occluded
// too (the injected lobe of a surface points away from it, so the surface's own blocker only meets
// the flux crossing it from behind: the leak).
bool lpvGeometryActive(int iteration) {
    return (iteration >= 2 || lpv.leak.y != 0) && (lpv.flags.x != 0 || lpv.flags.y != 0);
}

// What the geometry does at the face between destination c and its neighbour c + LPV_AXES[a]:
// the transmitted fraction of the flow into c, the albedo reflecting it back towards the
// neighbour (lpv.reflect=destination) and the albedo reflecting c's own flux back into c
// (lpv.reflect=source). Colourless but for the albedos.
struct LpvFaceTerms {
    float transmit;
    vec3 reflected, reflectedOwn;
};

LpvFaceTerms lpvFaceTerms(ivec3 c, int a, bool geometry, sampler3D gv, sampler3D gvAlbedo, sampler3D gvAxes) {
    LpvFaceTerms f = LpvFaceTerms(1.0, vec3(0.0), vec3(0.0));
    if (!geometry) return f;
    vec3 d = -vec3(LPV_AXES[a]);  // flow from the neighbour into c
    // lpv.reflect=source (docs/lpv.md, "Leaks"): the bounce of c's own flux off the blocker at
    // each of its faces returns into c, the side the light came from (not into the cell
    // behind the blocker, which for a thin wall is the other room).
    bool reflectToSource = lpv.leak.w != 0;
    vec3 albedo, axes;
    // The blocking potential stays band 1 for either order (docs/lpv.md).
    vec4 B = lpvFaceBlocking(gv, gvAlbedo, gvAxes, c, LPV_AXES[a], albedo, axes);
    // Surfaces facing the incoming light block it (SPEC 3.5: 1 - B(-d)); lpv.blocking=two-sided
    // (docs/lpv.md, "Leaks"): the area projected on the face, whichever side faces the light.
    float blocked = clamp(lpv.leak.z != 0 ? dot(axes, abs(d)) : shEvaluate(B, -d), 0.0, 1.0);
    f.transmit = 1.0 - blocked;
    float open = 1.0;
#ifdef RTGI_LPV_PROPAGATE_VISIBILITY
    // What the surfaces between the two centres stop does not pass (reflected below).
    open = lpvFaceOpen(c, LPV_AXES[a]);
    f.transmit *= open;
#endif
    if (lpv.flags.y != 0 && !reflectToSource) f.reflected = blocked * albedo;  // seed 3.5.2: B(-w) reflects, weighted by albedo
    if (lpv.flags.y != 0 && reflectToSource) {
        // c's own flux towards n (flow -d) meets the blocker of the same face from c's side;
        // what the open fraction stops on top is reflected too (1 without visibility).
        float blockedOut = clamp(lpv.leak.z != 0 ? dot(axes, abs(d)) : shEvaluate(B, d), 0.0, 1.0);
        f.reflectedOwn = (1.0 - (1.0 - blockedOut) * open) * albedo;
    }
    return f;
}

// c's own intensity of one colour as the reflection into the source sends it (energy conserving:
// scaled like every source).
LpvSh lpvOwnSource(LpvSh own) {
    return lpv.leak.w != 0 && lpv.flags.z != 0 ? own * lpvConservingScale(own) : own;
}

// What one colour (index ch) of neighbour intensity I adds to destination c through the face with
// terms f (flow direction d into c); own: c's intensity of that colour as lpvOwnSource gives it.
LpvSh lpvFaceColour(LpvSh I, LpvSh own, vec3 d, LpvFaceTerms f, int ch) {
    LpvSh acc = LpvSh(0.0);
    float scale = lpv.flags.z != 0 ? lpvConservingScale(I) : 1.0;
    float total = lpvPropagateFaces(I * scale, d, f.transmit, acc);
    // The reflected part leaves the blocking surface back towards the source.
    acc += (f.reflected[ch] * total * INV_PI) * lpvLobe(-d);
    if (f.reflectedOwn[ch] > 0.0) acc += (f.reflectedOwn[ch] * lpvFacesFlux(own, -d) * INV_PI) * lpvLobe(d);
    return acc;
}

// Iteration `iteration` (1-based) for destination cell c; src is volume k-1. The per-face kernel
// (lpv/propagate_faces.comp) computes the same lpvFaceColour terms, one invocation each.
LpvRgb lpvGather(ivec3 c, int iteration, sampler3D srcR, sampler3D srcG, sampler3D srcB, sampler3D gv,
                 sampler3D gvAlbedo, sampler3D gvAxes) {
    LpvRgb o = LpvRgb(LpvSh(0.0), LpvSh(0.0), LpvSh(0.0));
    ivec3 dims = lpv.grid.xyz;
    LpvSh own[3];
    lpvFetchSource(c, srcR, srcG, srcB, own);
    for (int ch = 0; ch < 3; ++ch) own[ch] = lpvOwnSource(own[ch]);
    bool geometry = lpvGeometryActive(iteration);
    for (int a = 0; a < 6; ++a) {
        ivec3 n = c + LPV_AXES[a];
        if (!lpvInside(n, dims)) continue;
        LpvSh I[3];
        lpvFetchSource(n, srcR, srcG, srcB, I);
        LpvFaceTerms f = lpvFaceTerms(c, a, geometry, gv, gvAlbedo, gvAxes);
        vec3 d = -vec3(LPV_AXES[a]);
        o.r += lpvFaceColour(I[0], own[0], d, f, 0);
        o.g += lpvFaceColour(I[1], own[1], d, f, 1);
        o.b += lpvFaceColour(I[2], own[2], d, f, 2);
    }
    return o;
}
