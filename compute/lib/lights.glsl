// Point, spot and area lights: the attenuation shared by the real-time
// direct pass (post/direct.comp) and the reference's next-event estimation
// (lib/ref_scene.glsl), and the local-light shadow-map lookup (direct pass).
// Needs common.glsl (GpuLight from shared.h).
#pragma once

// Radiant intensity reaching p from light g per unit intensity, divided by
// the squared distance: the irradiance on a surface facing the light is
// colorIntensity · localLightAttenuation. l: unit direction p -> light,
// dist: distance. KHR_lights_punctual: inverse square with the
// recommended range window clamp(1 − (d/r)⁴, 0, 1), spot cone
// t = clamp((cos θ − cos outer) / max(cos inner − cos outer, 1e-3), 0, 1),
// attenuation t² (the specification's angularAttenuation). Area lights
// (emissive regions, docs/lights.md) carry I0 = Le·A along their normal and
// fall off as max(cos θ, 0) (a Lambertian emitter seen from afar).
float localLightAttenuation(GpuLight g, vec3 p, out vec3 l, out float dist) {
    vec3 toL = g.positionRange.xyz - p;
    float dist2 = max(dot(toL, toL), 1e-8);  // 1/d² stays finite times any fp32 intensity
    dist = sqrt(dist2);
    l = toL / dist;
    float atten = 1.0 / dist2;
    if (g.positionRange.w > 0.0) {
        float r = dist / g.positionRange.w;
        atten *= clamp(1.0 - r * r * r * r, 0.0, 1.0);
    }
    int type = int(g.directionType.w);
    float cd = dot(-l, g.directionType.xyz);
    if (type == RTGI_LIGHT_SPOT) {
        float t = clamp((cd - g.cone.y) / max(g.cone.x - g.cone.y, 1e-3), 0.0, 1.0);
        atten *= t * t;
    } else if (type == RTGI_LIGHT_AREA) {
        atten *= max(cd, 0.0);
    } else if (type != RTGI_LIGHT_POINT) {
        atten = 0.0;  // culled for this frame
    }
    return atten;
}

// Solid angle of the rectangle [x0, x1] × [y0, y1] on the plane at unit
// distance in front of a point: Ω = F(x1,y1) − F(x0,y1) − F(x1,y0) + F(x0,y0)
// with F(x, y) = atan(x·y / √(1 + x² + y²)) (the antiderivative of
// (1 + x² + y²)^(−3/2); docs/lpv.md "RSMs of local lights"). The texels of a
// cube face sum to exactly 4π/6.
float planeRectSolidAngle(vec2 lo, vec2 hi) {
    vec4 x = vec4(hi.x, lo.x, hi.x, lo.x), y = vec4(hi.y, hi.y, lo.y, lo.y);
    vec4 f = atan(x * y / sqrt(1.0 + x * x + y * y));
    return f.x - f.y - f.z + f.w;
}


// ---- area lights: exact diffuse irradiance, representative-point specular ----
// (docs/lights.md "Area shading"). Vertices are relative to the shaded point.

// θ·(n·γ) of one edge a -> b of a spherical polygon (a, b unit vectors): the
// angle between them times the normal component of the edge's unit normal
// γ = a×b/|a×b| (Lambert's formula). atan2 keeps small angles exact in fp32.
float lambertEdge(vec3 a, vec3 b, vec3 n) {
    vec3 c = cross(a, b);
    float s = length(c);
    float th = atan(s, dot(a, b));
    return (s > 1e-7 ? th / s : 1.0) * dot(c, n);
}

// Projected solid angle ∫ max(n·ω, 0) dω of the quadrilateral q[0..3]
// (relative to the shaded point, either winding) clipped to the hemisphere
// above n: 0.5·|Σ θᵢ n·γᵢ| over the clipped polygon's edges. Irradiance
// from a uniform emitter of radiance Le is Le times this.
float quadProjectedSolidAngle(vec3 q[4], vec3 n) {
    vec3 o[5];
    int m = 0;
    for (int i = 0; i < 4; ++i) {
        vec3 a = q[i], b = q[(i + 1) & 3];
        float ha = dot(a, n), hb = dot(b, n);
        if (ha >= 0.0) o[m++] = a;
        if ((ha >= 0.0) != (hb >= 0.0)) o[m++] = a + (b - a) * (ha / (ha - hb));
    }
    if (m < 3) return 0.0;
    float sum = 0.0;
    for (int i = 0; i < m; ++i) {
        vec3 a = o[i], b = o[i + 1 < m ? i + 1 : 0];
        float la = length(a), lb = length(b);
        if (la > 0.0 && lb > 0.0) sum += lambertEdge(a / la, b / lb, n);
    }
    return 0.5 * abs(sum);
}

// The light's rectangle relative to p: centre ± halfU ± halfV.
void areaLightQuad(GpuLightShape sh, vec3 p, out vec3 q[4]) {
    vec3 c = sh.centerRadius.xyz - p;
    q[0] = c - sh.halfU.xyz - sh.halfV.xyz;
    q[1] = c + sh.halfU.xyz - sh.halfV.xyz;
    q[2] = c + sh.halfU.xyz + sh.halfV.xyz;
    q[3] = c - sh.halfU.xyz + sh.halfV.xyz;
}

// Representative point of the rectangle for a GGX lobe around the mirror
// direction r: where r meets the light's plane, clamped into the rectangle
// (when r runs away from the plane, the point of the plane at the centre's
// distance along r, clamped). Returns the unit direction p -> that point.
vec3 areaLightRepresentativeDir(GpuLightShape sh, vec3 p, vec3 r) {
    vec3 u = sh.halfU.xyz, v = sh.halfV.xyz;
    vec3 nl = cross(u, v);
    vec3 c = sh.centerRadius.xyz - p;
    float rn = dot(r, nl), t = dot(c, nl) / (rn != 0.0 ? rn : 1e-30);
    vec3 x = (rn < 0.0 && t > 0.0) ? r * t : r * length(c);
    vec3 d = x - c;
    float uu = max(dot(u, u), 1e-30), vv = max(dot(v, v), 1e-30);
    vec3 y = c + u * clamp(dot(d, u) / uu, -1.0, 1.0) + v * clamp(dot(d, v) / vv, -1.0, 1.0);
    float ly = length(y);
    return ly > 0.0 ? y / ly : -normalize(nl);
}

#ifdef RTGI_LOCAL_SHADOWS
layout(std430, binding = RTGI_SSBO_LOCAL_SHADOW_MATRICES) readonly buffer LocalShadowBlock { mat4 localShadowMatrices[]; };

// Shadow-map layer of a light at world position p: spot lights own one
// perspective map, point and area lights a cube of 6 (faces +x, −x, +y, −y,
// +z, −z, picked by the major axis of p − light).
int localShadowLayer(GpuLight g, vec3 p) {
    int first = int(g.cone.z);
    if (first < 0 || int(g.directionType.w) == RTGI_LIGHT_SPOT) return first;
    vec3 d = p - g.positionRange.xyz, a = abs(d);
    int face = a.x >= a.y && a.x >= a.z ? (d.x >= 0.0 ? 0 : 1) : a.y >= a.z ? (d.y >= 0.0 ? 2 : 3) : (d.z >= 0.0 ? 4 : 5);
    return first + face;
}

// Visibility of light g at p with normal n (3x3 PCF like the sun's); the
// normal offset is 1.5 texels at p's distance (g.cone.w: texel size per
// unit distance).
float localShadow(sampler2DArrayShadow maps, GpuLight g, vec3 p, vec3 n, float dist) {
    if (g.cone.z < 0.0) return 1.0;
    vec3 q = p + n * (g.cone.w * dist);
    int layer = localShadowLayer(g, q);
    vec4 c = localShadowMatrices[layer] * vec4(q, 1.0);
    if (!(c.w > 0.0)) return 1.0;
    vec3 s = c.xyz / c.w * 0.5 + 0.5;
    if (any(lessThan(s, vec3(0.0))) || any(greaterThan(s, vec3(1.0)))) return 1.0;
    vec2 texel = 1.0 / vec2(textureSize(maps, 0).xy);
    float v = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) v += texture(maps, vec4(s.xy + vec2(x, y) * texel, float(layer), s.z));
    return v / 9.0;
}
// ---- soft shadows (PCSS over the light's extent, docs/lights.md "Penumbrae") ----

// Distance along the layer's view axis of a D32F value of a local shadow
// layer (GL perspective projection, near = far / 1000 as in render/lights.cpp).
float localShadowViewDepth(float z, float far) {
    float near = far * 1e-3;
    return 2.0 * far * near / ((far + near) - (2.0 * z - 1.0) * (far - near));
}

// Shadow-map position (xy, layer in z, depth in w) of world point x; false
// outside every layer of the light.
bool localShadowCoord(GpuLight g, vec3 x, out vec4 coord) {
    int layer = localShadowLayer(g, x);
    vec4 c = localShadowMatrices[layer] * vec4(x, 1.0);
    coord = vec4(0.0);
    if (!(c.w > 0.0)) return false;
    vec3 s = c.xyz / c.w * 0.5 + 0.5;
    coord = vec4(s.xy, float(layer), s.z);
    return all(greaterThanEqual(s.xy, vec2(0.0))) && all(lessThanEqual(s.xy, vec2(1.0)));
}

// Point k of m² on the emitting shape centre ± u ± v: an m x m stratified
// grid, each point moved inside its cell by xi ∈ [0,1)².
vec3 lightShapePoint(vec3 centre, vec3 u, vec3 v, int k, int m, vec2 xi) {
    vec2 t = (vec2(float(k % m), float(k / m)) + xi) * (2.0 / float(m)) - 1.0;
    return centre + u * t.x + v * t.y;
}

// Visibility of an extended light (area rectangle, or a point/spot light of
// source radius R seen as the square of the disc's area facing p) at p with
// normal n: percentage-closer soft shadows in world space. The map is drawn
// from the light's centre o; the ray from p' (p with the normal offset) to
// a point l on the light crosses a blocker at distance r_B from o at
// b = p' + (l − p')·(1 − r_B/|p' − o|), so the shadow map looked up in b's
// direction answers "is that ray blocked" exactly for a blocker at r_B.
// The rays go to an m x m grid on the light, m = sh.halfV.w: 4 for a whole
// light (or 0), 2 for a piece of an emissive.split panel, so the 2 x 2
// pieces together sample the panel's 4x4 grid, each from its own map.
// 1. blocker search: max(m², 4) rays p' -> l at four fractions s of the way
//    (m = 4: a Latin square over the grid), the mean distance r_B of texels
//    closer to o than the receiver's tangent plane in that direction (no
//    self-shadowing of the plane) and than the receiver (cleared texels are
//    no blockers);
//    2. m² compare taps (each bilinear, 2x2) at the receiver's
//    plane along the rays for that r_B: penumbra width 2h·(d − r_B)/r_B
//    (similar triangles). Falls back to the 3x3 PCF for a punctual light.
// The two steps for the m x m grid on the light (called with a literal m,
// so each instance's loops have constant bounds).
float softShadowGrid(sampler2DArrayShadow maps, sampler2DArray depths, GpuLight g, vec3 centre, vec3 u, vec3 v,
                     vec3 q, vec3 n, float far, vec2 xi, int m) {
    vec3 o = g.positionRange.xyz;
    float d = length(q - o);
    float planeDist = dot(q - o, n);  // < 0: the light is in front of the receiver's plane
    float tolerance = 1.0 - 2.0 * g.cone.w;
    int taps = m * m;
    float sum = 0.0, found = 0.0;
    for (int j = 0; j < max(taps, 4); ++j) {
        int k = j % taps;
        // 0.35, 0.55, 0.75, 0.95 of the way
        float s = 0.35 + 0.2 * float(m == 4 ? ((k & 3) + (k >> 2)) & 3 : j & 3);
        vec3 b = q + (lightShapePoint(centre, u, v, k, m, vec2(0.5)) - q) * s;
        vec4 c;
        if (!localShadowCoord(g, b, c)) continue;
        vec3 dir = normalize(b - o);
        float axis = int(g.directionType.w) == RTGI_LIGHT_SPOT ? dot(dir, g.directionType.xyz)
                                                                : max(abs(dir.x), max(abs(dir.y), abs(dir.z)));
        float z = texture(depths, c.xyz).r;
        if (z >= 1.0) continue;  // cleared texel: nothing in that direction
        float rB = localShadowViewDepth(z, far) / max(axis, 1e-4);
        float dn = dot(dir, n);
        float rPlane = dn < -1e-4 ? planeDist / dn : d;
        // A blocker lies between the light and the receiver: closer to o than
        // the receiver's plane in that direction and than the receiver itself.
        if (rB < min(rPlane, d) * tolerance) {
            sum += rB;
            found += 1.0;
        }
    }
    if (found == 0.0) return 1.0;
    float sf = clamp(1.0 - sum / found / d, 0.0, 1.0);
    float vis = 0.0;
    for (int k = 0; k < taps; ++k) {
        vec3 b = q + (lightShapePoint(centre, u, v, k, m, xi) - q) * sf;
        vec3 dir = normalize(b - o);
        float dn = dot(dir, n);
        vec3 x = dn < -1e-4 ? o + dir * (planeDist / dn) : b;
        vec4 c;
        vis += localShadowCoord(g, x, c) ? texture(maps, c) : 1.0;
    }
    return vis / float(taps);
}

float localShadowSoft(sampler2DArrayShadow maps, sampler2DArray depths, GpuLight g, GpuLightShape sh, vec3 p,
                      vec3 n, float dist, vec2 xi) {
    if (g.cone.z < 0.0) return 1.0;
    vec3 o = g.positionRange.xyz;
    vec3 centre, u, v;
    if (int(g.directionType.w) == RTGI_LIGHT_AREA) {
        centre = sh.centerRadius.xyz;
        u = sh.halfU.xyz;
        v = sh.halfV.xyz;
    } else {
        float radius = sh.centerRadius.w;
        if (!(radius > 0.0)) return localShadow(maps, g, p, n, dist);
        vec3 w = normalize(p - o);
        vec3 t = normalize(cross(abs(w.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0), w));
        float h = radius * 0.886226925;  // √π / 2: the square of the disc's area
        centre = o;
        u = t * h;
        v = cross(w, t) * h;
    }
    vec3 q = p + n * (g.cone.w * dist);
    // Two instances only (4 and 2 rays per side; uniform per light, no divergence): a third (1) or one
    // with a run-time m made the whole direct pass 1.5x slower on the H100 (docs/lights.md).
    if (sh.halfV.w == 0.0 || sh.halfV.w >= 4.0) return softShadowGrid(maps, depths, g, centre, u, v, q, n, sh.halfU.w, xi, 4);
    return softShadowGrid(maps, depths, g, centre, u, v, q, n, sh.halfU.w, xi, 2);
}
#endif
