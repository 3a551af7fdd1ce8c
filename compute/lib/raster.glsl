// The compute rasterizer's one library (docs/visibility.md): scene fetch,
// near-plane and guard-band clipping, fixed-point triangle setup with the
// top-left fill rule, edge functions, depth, the visibility buffer and the
// perspective-correct barycentrics of the resolves.
//
// Design after Laine & Karras 2011 ("High-Performance Software Rasterization
// on GPUs": setup/cull pass, bins of screen tiles rasterized per workgroup)
// and Burns & Hunt 2013 ("The Visibility Buffer": depth + triangle id, the
// attributes fetched again in a resolve). Must be the first include of a
// shader: it carries the #extension lines.
#extension GL_ARB_gpu_shader_int64 : require
#ifdef RTGI_VISIBILITY_ATOMIC64
#extension GL_NV_shader_atomic_int64 : require
#endif
#pragma once
#include "lib/visibility_shared.h"
#include "lib/shared.h"

layout(location = RTGI_VISIBILITY_LOC_VIEW_PROJ) uniform mat4 uViewProj;
layout(location = RTGI_VISIBILITY_LOC_SIZE) uniform ivec2 uSize;
layout(location = RTGI_VISIBILITY_LOC_TRIANGLES) uniform int uTriangles;
layout(location = RTGI_VISIBILITY_LOC_PHASE) uniform int uPhase;
layout(location = RTGI_VISIBILITY_LOC_FLAGS) uniform int uFlags;
layout(location = RTGI_VISIBILITY_LOC_CAPACITY) uniform ivec2 uCapacity;

layout(std430, binding = RTGI_VISIBILITY_SSBO_VERTICES) readonly buffer VisVertices { float visVertexData[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_INDICES) readonly buffer VisIndices { uint visIndex[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_VISBUF) buffer VisBuffer {
#ifdef RTGI_VISIBILITY_ATOMIC64
    uint64_t vis[];  // (depth bits << 32) | triangle id; min = nearest, ties to the lowest id
#else
    uint vis[];      // [0, N): depth bits; [N, 2N): triangle id
#endif
};
#ifdef RTGI_VISIBILITY_COUNT_HITS
layout(std430, binding = RTGI_VISIBILITY_SSBO_HITS) buffer VisHits { uint visHits[]; };  // tests: writes per pixel
#endif

// ---- scene ----------------------------------------------------------------------
// GpuVertex: position[3], normal[3], uv[2], material (36 bytes).
vec3 visPosition(uint v) { return vec3(visVertexData[9 * v], visVertexData[9 * v + 1], visVertexData[9 * v + 2]); }
vec3 visNormal(uint v) { return vec3(visVertexData[9 * v + 3], visVertexData[9 * v + 4], visVertexData[9 * v + 5]); }
vec2 visUv(uint v) { return vec2(visVertexData[9 * v + 6], visVertexData[9 * v + 7]); }
uint visMaterial(uint v) { return floatBitsToUint(visVertexData[9 * v + 8]); }
uvec3 visTriangle(uint id) { return uvec3(visIndex[3 * id], visIndex[3 * id + 1], visIndex[3 * id + 2]); }

// ---- visibility buffer --------------------------------------------------------------
uint visPixelCount() { return uint(uSize.x) * uint(uSize.y); }

// The nearest fragment wins; on equal depth the lowest triangle id, which is
// the hardware's GL_LESS with the scene drawn in index order (first drawn wins).
void visWrite(uint pixel, float depth, uint id) {
    uint d = floatBitsToUint(depth);
#ifdef RTGI_VISIBILITY_COUNT_HITS
    if (uPhase == 0) atomicAdd(visHits[pixel], 1u);
#endif
#ifdef RTGI_VISIBILITY_ATOMIC64
    uint64_t depthId = (uint64_t(d) << 32) | uint64_t(id);
    if (depthId < vis[pixel]) atomicMin(vis[pixel], depthId);  // plain read first: most fragments lose
#else
    // Two-pass 32-bit path: phase 0 keeps the nearest depth, phase 1 the
    // lowest id among the fragments at exactly that depth.
    if (uPhase == 0) {
        if (d < vis[pixel]) atomicMin(vis[pixel], d);
    } else if (vis[pixel] == d) {
        atomicMin(vis[visPixelCount() + pixel], id);
    }
#endif
}

// False for an empty pixel.
bool visRead(uint pixel, out float depth, out uint id) {
#ifdef RTGI_VISIBILITY_ATOMIC64
    uint64_t v = vis[pixel];
    id = uint(v & 0xffffffffUL);
    depth = uintBitsToFloat(uint(v >> 32));
#else
    id = vis[visPixelCount() + pixel];
    depth = uintBitsToFloat(vis[pixel]);
#endif
    return id != RTGI_VISIBILITY_EMPTY;
}

void visClear(uint pixel) {
#ifdef RTGI_VISIBILITY_ATOMIC64
    vis[pixel] = ~0UL;
#else
    vis[pixel] = RTGI_VISIBILITY_EMPTY;
    vis[visPixelCount() + pixel] = RTGI_VISIBILITY_EMPTY;
#endif
#ifdef RTGI_VISIBILITY_COUNT_HITS
    visHits[pixel] = 0u;
#endif
}

// ---- second depth layer (RTGI_VISIBILITY_LAYER2; docs/ao.md "Second depth layer") ----
// The same setup and tile kernels over the first layer's bins, keeping per
// pixel the nearest fragment farther than the first layer's linear depth
// plus a minimum separation (deep G-buffers, Mara et al. 2016). Only a depth
// is kept, so one 32-bit atomicMin on the positive float bits serves every
// driver (no id, no second phase).
#ifdef RTGI_VISIBILITY_LAYER2
layout(binding = RTGI_VISIBILITY_IMG_LAYER1, r32f) uniform readonly image2D visLayer1;
layout(binding = RTGI_VISIBILITY_IMG_LAYER2, r32ui) uniform uimage2D visLayer2;
layout(location = RTGI_VISIBILITY_LOC_LAYER2) uniform vec4 uLayer2;

// View-space distance along -z of window depth zw under a perspective
// projection P: z_ndc = -P22 + P32 / L, so L = P32 / (z_ndc + P22).
double visLinearDepth(double zw) { return double(uLayer2.w) / (2.0LF * zw - 1.0LF + double(uLayer2.z)); }

void visWriteLayer2(ivec2 pixel, double zw) {
    float z1 = imageLoad(visLayer1, pixel).r;
    if (!(z1 > 0.0)) return;  // sky in the first layer
    float separation = uLayer2.y != 0.0 ? uLayer2.x * z1 : uLayer2.x;
    float z = float(visLinearDepth(zw));
    if (!(z > z1 + separation)) return;
    uint bits = floatBitsToUint(z);  // positive floats order as their bits
    if (bits < imageLoad(visLayer2, pixel).r) imageAtomicMin(visLayer2, pixel, bits);
}
#endif

// ---- clipping ---------------------------------------------------------------------------
// Signed distance of a clip-space vertex to plane k (>= 0 inside): the near
// plane z >= -w as the hardware clips it, then a guard band of
// RTGI_VISIBILITY_GUARD_BAND pixels on each side (keeps fixed point in range; edges
// only move outside the viewport there). The far plane is tested per pixel.
float visPlane(vec4 c, int k, vec2 guard) {
    if (k == 0) return c.z + c.w;
    if (k == 1) return guard.x * c.w - c.x;
    if (k == 2) return guard.x * c.w + c.x;
    if (k == 3) return guard.y * c.w - c.y;
    return guard.y * c.w + c.y;
}

vec2 visGuardNdc() { return 1.0 + 2.0 * RTGI_VISIBILITY_GUARD_BAND / vec2(uSize); }

// Sutherland-Hodgman against the five planes; returns the vertex count of the
// convex polygon (0: nothing left; at most 3 + 5 = 8).
int visClip(vec4 c0, vec4 c1, vec4 c2, out vec4 poly[8]) {
    vec2 guard = visGuardNdc();
    poly[0] = c0;
    poly[1] = c1;
    poly[2] = c2;
    int n = 3;
    vec4 tmp[8];
    for (int k = 0; k < 5; ++k) {
        bool allIn = true;
        for (int i = 0; i < n; ++i) allIn = allIn && visPlane(poly[i], k, guard) >= 0.0;
        if (allIn) continue;
        int m = 0;
        for (int i = 0; i < n; ++i) {
            vec4 a = poly[i], b = poly[(i + 1) % n];
            float da = visPlane(a, k, guard), db = visPlane(b, k, guard);
            if (da >= 0.0) tmp[m++] = a;
            if ((da >= 0.0) != (db >= 0.0) && m < 8) tmp[m++] = mix(a, b, da / (da - db));
        }
        n = m;
        for (int i = 0; i < n; ++i) poly[i] = tmp[i];
        if (n < 3) return 0;
    }
    return n;
}

// ---- triangle setup ----------------------------------------------------------------------
// Window position in pixels (before snapping) and window depth (glDepthRange
// 0..1: z_ndc * 0.5 + 0.5, the D32F convention of the G-buffer).
vec2 visWindow(vec4 c) { return (c.xy / c.w * 0.5 + 0.5) * vec2(uSize); }
float visWindowDepth(vec4 c) { return c.z / c.w * 0.5 + 0.5; }
// Fixed point with RTGI_VISIBILITY_SUBPIXEL_BITS, rounding half up.
ivec2 visSnap(vec2 w) { return ivec2(floor(w * float(1 << RTGI_VISIBILITY_SUBPIXEL_BITS) + 0.5)); }

struct VisRasterTri {
    i64vec3 A, B, C;    // E_k(p) = A_k p.x + B_k p.y + C_k over the edge opposite vertex k, > 0 inside
    i64vec3 rule;       // 0 on top-left edges, -1 elsewhere: inside iff E_k + rule_k >= 0
    dvec2 q0, q1, q2;   // unsnapped window positions: the depth plane (coverage uses the snapped ones)
    double invArea;     // 1 / twice the unsnapped signed area (0: use the snapped barycentrics)
    double invAreaFixed;
    vec3 z;             // window depth at the vertices
    float bias;         // polygon offset (shadow maps)
    ivec4 box;          // pixel box (inclusive) clamped to the target
    uint id;
};

// Edge a -> b of a counter-clockwise triangle (y up, GL window space). The
// top-left rule of D3D/Vulkan, stated in y-down memory order as hardware
// applies it: a pixel centre exactly on an edge belongs to the triangle when
// the edge is a left edge (interior to its right: the edge runs downwards in
// y-up space) or, in y-down order, a top edge, which in GL's y-up window
// space is the bottom edge (horizontal, interior above: runs left to right).
// This is what Mesa llvmpipe does in framebuffer objects (test "fill-rule
// ties match the hardware rasterizer").
void visEdge(ivec2 a, ivec2 b, out int64_t A, out int64_t B, out int64_t C, out int64_t rule) {
    A = -int64_t(b.y - a.y);
    B = int64_t(b.x - a.x);
    C = -(A * int64_t(a.x) + B * int64_t(a.y));
    bool topLeft = (b.y - a.y) < 0 || ((b.y - a.y) == 0 && (b.x - a.x) > 0);
    rule = topLeft ? 0L : -1L;
}

// Set-up of a triangle from its window positions; false when culled (zero
// area after snapping, back face when culling, no pixel centre inside the
// box or the box off the target). Coverage uses the snapped positions
// (exact integer edge functions); depth is the plane through the unsnapped
// positions, as hardware interpolates, so that coplanar triangles agree.
bool visSetup(vec2 w0, vec2 w1, vec2 w2, vec3 z, uint id, out VisRasterTri t) {
    ivec2 p0 = visSnap(w0), p1 = visSnap(w1), p2 = visSnap(w2);
    int64_t area = int64_t(p1.x - p0.x) * int64_t(p2.y - p0.y) - int64_t(p1.y - p0.y) * int64_t(p2.x - p0.x);
    if (area == 0L) return false;
    if (area < 0L) {
        // Clockwise in window space = back face (glFrontFace GL_CCW).
        if ((uFlags & RTGI_VISIBILITY_FLAG_CULL_BACK) != 0) return false;
        ivec2 tp = p1;
        p1 = p2;
        p2 = tp;
        vec2 tw = w1;
        w1 = w2;
        w2 = tw;
        z = z.xzy;
        area = -area;
    }
    visEdge(p1, p2, t.A.x, t.B.x, t.C.x, t.rule.x);
    visEdge(p2, p0, t.A.y, t.B.y, t.C.y, t.rule.y);
    visEdge(p0, p1, t.A.z, t.B.z, t.C.z, t.rule.z);
    t.q0 = dvec2(w0);
    t.q1 = dvec2(w1);
    t.q2 = dvec2(w2);
    dvec2 e01 = t.q1 - t.q0, e02 = t.q2 - t.q0;
    double a = e01.x * e02.y - e01.y * e02.x;
    t.invArea = a != 0.0LF ? 1.0LF / a : 0.0LF;
    t.invAreaFixed = 1.0LF / double(area);
    t.z = z;
    t.id = id;
    // Pixels whose centre (x + 0.5) * 2^bits lies in the box.
    const int half_ = 1 << (RTGI_VISIBILITY_SUBPIXEL_BITS - 1);
    ivec2 lo = min(p0, min(p1, p2)) - half_, hi = max(p0, max(p1, p2)) - half_;
    // ceil / floor division by 2^bits (arithmetic shift floors, also for negatives)
    ivec2 first = (lo + ((1 << RTGI_VISIBILITY_SUBPIXEL_BITS) - 1)) >> RTGI_VISIBILITY_SUBPIXEL_BITS;
    ivec2 last = hi >> RTGI_VISIBILITY_SUBPIXEL_BITS;
    first = max(first, ivec2(0));
    last = min(last, uSize - 1);
    t.box = ivec4(first, last);
    if (any(greaterThan(first, last))) return false;
    t.bias = 0.0;
    if ((uFlags & RTGI_VISIBILITY_FLAG_DEPTH_BIAS) != 0) {
        // glPolygonOffset(1.5, 2.0): 1.5 * max |dz/dx|, |dz/dy| per pixel + 2 r,
        // r = 2^(exponent(max z) - 23) for a float depth buffer (GL 4.5 §14.6.5).
        float s = float(1 << RTGI_VISIBILITY_SUBPIXEL_BITS) * float(t.invAreaFixed);
        float dzdx = s * (float(t.A.y) * (z.y - z.x) + float(t.A.z) * (z.z - z.x));
        float dzdy = s * (float(t.B.y) * (z.y - z.x) + float(t.B.z) * (z.z - z.x));
        float zmax = max(z.x, max(z.y, z.z));
        int e;
        frexp(max(zmax, 1e-30), e);
        t.bias = 1.5 * max(abs(dzdx), abs(dzdy)) + 2.0 * exp2(float(e - 1 - 23));
    }
    return true;
}

// Fixed-point sample position of a pixel centre.
i64vec2 visSample(int x, int y) {
    const int half_ = 1 << (RTGI_VISIBILITY_SUBPIXEL_BITS - 1);
    return i64vec2((x << RTGI_VISIBILITY_SUBPIXEL_BITS) + half_, (y << RTGI_VISIBILITY_SUBPIXEL_BITS) + half_);
}

// Tests one pixel and writes it to the visibility buffer when covered.
void visRasterPixel(VisRasterTri t, int x, int y) {
    i64vec2 p = visSample(x, y);
    i64vec3 e = t.A * p.x + t.B * p.y + t.C;
    if (any(lessThan(e + t.rule, i64vec3(0L)))) return;
    // Depth: the plane through the unsnapped vertices at the pixel centre,
    // in double (one rounding to float).
    double b1, b2;
    if (t.invArea != 0.0LF) {
        dvec2 c = dvec2(x, y) + 0.5LF;
        dvec2 d20 = t.q0 - t.q2, d01 = t.q1 - t.q0, c2 = c - t.q2, c0 = c - t.q0;
        b1 = (d20.x * c2.y - d20.y * c2.x) * t.invArea;
        b2 = (d01.x * c0.y - d01.y * c0.x) * t.invArea;
    } else {
        b1 = double(e.y) * t.invAreaFixed;
        b2 = double(e.z) * t.invAreaFixed;
    }
    double zd = double(t.z.x) + b1 * double(t.z.y - t.z.x) + b2 * double(t.z.z - t.z.x);
    float z = float(zd);
    if (z < 0.0 || z > 1.0) return;  // far plane (and near after rounding), as clipping does
#ifdef RTGI_VISIBILITY_LAYER2
    visWriteLayer2(ivec2(x, y), zd);
#else
    if (t.bias != 0.0) z = clamp(z + t.bias, 0.0, 1.0);
    visWrite(uint(y) * uint(uSize.x) + uint(x), z, t.id);
#endif
}

// ---- large-triangle records (setup -> bin -> tile) ---------------------------------------
// The set-up triangle itself (visSetup's result, exactly: integers and doubles stored as they
// are), so that bin and tile read it instead of repeating the set-up (two double divisions
// and the int64 edges) in every thread of every tile the triangle covers. 208 bytes (std430);
// the edges' rule in the .w of A, B, C.
struct VisTriangle {
    i64vec4 A, B, C;  // A.x..z the edges' A, .w the rule (likewise B, C)
    dvec4 q01;        // q0, q1
    dvec4 q2Area;     // q2, invArea, invAreaFixed
    vec4 zBias;       // z, bias
    ivec4 box;
    uvec4 id;         // .x
};

VisTriangle visPack(VisRasterTri t) {
    VisTriangle r;
    r.A = i64vec4(t.A, t.rule.x);
    r.B = i64vec4(t.B, t.rule.y);
    r.C = i64vec4(t.C, t.rule.z);
    r.q01 = dvec4(t.q0, t.q1);
    r.q2Area = dvec4(t.q2, t.invArea, t.invAreaFixed);
    r.zBias = vec4(t.z, t.bias);
    r.box = t.box;
    r.id = uvec4(t.id, 0u, 0u, 0u);
    return r;
}
bool visUnpack(VisTriangle r, out VisRasterTri t) {
    t.A = r.A.xyz;
    t.B = r.B.xyz;
    t.C = r.C.xyz;
    t.rule = i64vec3(r.A.w, r.B.w, r.C.w);
    t.q0 = r.q01.xy;
    t.q1 = r.q01.zw;
    t.q2 = r.q2Area.xy;
    t.invArea = r.q2Area.z;
    t.invAreaFixed = r.q2Area.w;
    t.z = r.zBias.xyz;
    t.bias = r.zBias.w;
    t.box = r.box;
    t.id = r.id.x;
    return true;
}

// ---- resolve: perspective-correct barycentrics from the triangle id --------------------
// Homogeneous 2D rasterization (Olano & Greer 1997): with the clip-space
// vertices c_k (x, y, w), lambda_k(p) = cross(c_{k+1}, c_{k+2}) . (p.x, p.y, 1)
// is proportional to the perspective-correct barycentric of vertex k at the
// NDC point p, for any w sign, so no clipped vertices are needed.
struct VisBary {
    vec3 b, bx, by;  // at the pixel centre, one pixel right, one pixel up
    bool front;      // counter-clockwise in window space
};

VisBary visBarycentrics(vec4 c0, vec4 c1, vec4 c2, ivec2 pixel, ivec2 size) {
    vec3 e0 = cross(c1.xyw, c2.xyw), e1 = cross(c2.xyw, c0.xyw), e2 = cross(c0.xyw, c1.xyw);
    vec2 px = 2.0 / vec2(size);
    vec2 p = (vec2(pixel) + 0.5) * px - 1.0;
    VisBary r;
    vec3 l = vec3(dot(e0, vec3(p, 1.0)), dot(e1, vec3(p, 1.0)), dot(e2, vec3(p, 1.0)));
    vec3 lx = l + vec3(e0.x, e1.x, e2.x) * px.x;
    vec3 ly = l + vec3(e0.y, e1.y, e2.y) * px.y;
    r.b = l / (l.x + l.y + l.z);
    r.bx = lx / (lx.x + lx.y + lx.z);
    r.by = ly / (ly.x + ly.y + ly.z);
    r.front = dot(c0.xyw, e0) > 0.0;
    return r;
}

// Attributes of the visible triangle at a pixel (resolves).
struct VisSurface {
    vec3 position;  // world
    vec3 normal;    // interpolated vertex normal (not normalized)
    vec2 uv, dUvDx, dUvDy;
    uint material;
    bool front;
    uvec3 vertices;  // the triangle's vertex indices
    vec3 bary;       // perspective-correct barycentrics at the pixel centre
};

VisSurface visSurface(uint id, ivec2 pixel) {
    uvec3 v = visTriangle(id);
    vec3 p0 = visPosition(v.x), p1 = visPosition(v.y), p2 = visPosition(v.z);
    VisBary b = visBarycentrics(uViewProj * vec4(p0, 1.0), uViewProj * vec4(p1, 1.0), uViewProj * vec4(p2, 1.0),
                                pixel, uSize);
    VisSurface s;
    s.position = b.b.x * p0 + b.b.y * p1 + b.b.z * p2;
    s.normal = b.b.x * visNormal(v.x) + b.b.y * visNormal(v.y) + b.b.z * visNormal(v.z);
    vec2 t0 = visUv(v.x), t1 = visUv(v.y), t2 = visUv(v.z);
    s.uv = b.b.x * t0 + b.b.y * t1 + b.b.z * t2;
    // Texture LOD from the UV change to the neighbouring pixel centres (the
    // analytic counterpart of the hardware's 2x2-quad differences).
    s.dUvDx = b.bx.x * t0 + b.bx.y * t1 + b.bx.z * t2 - s.uv;
    s.dUvDy = b.by.x * t0 + b.by.y * t1 + b.by.z * t2 - s.uv;
    s.material = visMaterial(v.x);
    s.front = b.front;
    s.vertices = v;
    s.bary = b.b;
    return s;
}
