// Grid addressing and the LPV uniform block, shared by every LPV shader
// (compute and the raster baseline).
#pragma once
#include "lib/common.glsl"
#include "lib/sh.glsl"
#include "lib/lpv_shared.h"

layout(std140, binding = RTGI_UBO_LPV) uniform LpvBlock { LpvUniforms lpv; };

// Volume image format: set by lpv::formatDefines(); rgba16f when compiled alone.
#ifndef RTGI_LPV_FORMAT
#define RTGI_LPV_FORMAT rgba16f
#define RTGI_LPV_HALF 1
#endif

float lpvCellSize() { return lpv.origin.w; }
ivec3 lpvGrid() { return lpv.grid.xyz; }

// Continuous cell coordinates: cell i spans [i, i + 1), its centre is i + 0.5.
vec3 lpvCellCoord(vec3 world) { return (world - lpv.origin.xyz) / lpv.origin.w; }

bool lpvInside(ivec3 c, ivec3 dims) { return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, dims)); }

// Linear index of cell c of a grid of `dims` cells (<= 513^3 < 2^32) and back.
uint lpvKeyOfCell(ivec3 c, ivec3 dims) { return uint(c.x) + uint(dims.x) * (uint(c.y) + uint(dims.y) * uint(c.z)); }
ivec3 lpvCellOfKey(uint key, ivec3 dims) {
    uint xy = uint(dims.x) * uint(dims.y);
    return ivec3(int(key % uint(dims.x)), int((key % xy) / uint(dims.x)), int(key / xy));
}

// World position of texel `texel` of an RSM of side `side` drawn with the inverse view-projection
// `invViewProj`, from its window-space depth (orthographic or perspective).
vec3 rsmWorldPosition(mat4 invViewProj, int side, ivec2 texel, float depth) {
    vec2 uv = (vec2(texel) + 0.5) / float(side);
    vec4 w = invViewProj * vec4(uv * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
    return w.xyz / w.w;
}
// The same for the RSM of the uniform block (the sun's, orthographic; side lpv.grid.w).
vec3 rsmWorldPosition(ivec2 texel, float depth) { return rsmWorldPosition(lpv.rsmInvViewProj, lpv.grid.w, texel, depth); }

// Cell receiving a surface point's light: moved half a cell along its normal
// so a surface lights the cell in front of it, not itself (seed 3.3, SPEC 3.3).
// lpv.inject_side=front (docs/lpv.md, "Leaks"): the half-cell offset puts the cell centre on
// the texel's lit side for axis-aligned normals only (centre - p = n/2 + e, |e_i| <= 1/2, so
// n.(centre - p) >= 1/2 - |n|_1 / 2 < 0 is possible for oblique n); a centre behind the
// surface's plane is moved one cell along the normal's dominant axis, which makes n.(centre - p)
// grow by |n|_max >= 1/sqrt(3) >= the deficit (|n|_1 - 1)/2 <= (sqrt(3) - 1)/2.
bool lpvInjectionCell(vec3 p, vec3 n, out ivec3 cell) {
    vec3 q = lpvCellCoord(p + 0.5 * lpvCellSize() * n);
    if (lpv.leak.x != 0 && dot(floor(q) + 0.5 - lpvCellCoord(p), n) <= 0.0) {
        vec3 a = abs(n);
        vec3 axis = a.x >= a.y && a.x >= a.z ? vec3(1.0, 0.0, 0.0) : a.y >= a.z ? vec3(0.0, 1.0, 0.0) : vec3(0.0, 0.0, 1.0);
        q += axis * sign(dot(axis, n));
    }
    cell = ivec3(floor(q));
    // floor() of huge/NaN coordinates is undefined as int: test in float first.
    return all(greaterThanEqual(q, vec3(0.0))) && all(lessThan(q, vec3(lpv.grid.xyz))) && lpvInside(cell, lpv.grid.xyz);
}

// rgba16f volumes saturate at the largest finite half instead of becoming Inf (docs/lpv.md).
vec4 lpvStorable(vec4 v) {
#ifdef RTGI_LPV_HALF
    return clamp(v, vec4(-65504.0), vec4(65504.0));
#else
    return v;
#endif
}
mat3 lpvStorable(mat3 v) {
#ifdef RTGI_LPV_HALF
    return mat3(clamp(v[0], vec3(-65504.0), vec3(65504.0)), clamp(v[1], vec3(-65504.0), vec3(65504.0)),
                clamp(v[2], vec3(-65504.0), vec3(65504.0)));
#else
    return v;
#endif
}
