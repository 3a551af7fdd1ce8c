// visibility.raster, step 2 (one thread per scene triangle): transform, clip
// against the near plane and the guard band, snap to fixed point, cull
// (frustum, back face when asked, zero area, no pixel centre covered), then
// rasterize small triangles (pixel box <= RTGI_VISIBILITY_SMALL^2) here and append
// the others to the large-triangle list for binning (Laine & Karras 2011 §4).
// 32-bit path, phase 1: only the small triangles again (the large list and
// its bins are reused).
#include "lib/raster.glsl"

layout(local_size_x = RTGI_VISIBILITY_SETUP_GROUP) in;

layout(std430, binding = RTGI_VISIBILITY_SSBO_LARGE) writeonly buffer Large { VisTriangle large[]; };
layout(std430, binding = RTGI_VISIBILITY_SSBO_COUNTERS) buffer Counters { VisCounters counters; };

shared uint sSmall, sCulled;

void emit(vec4 c0, vec4 c1, vec4 c2, uint id, inout bool any_, inout bool small) {
    vec2 w0 = visWindow(c0), w1 = visWindow(c1), w2 = visWindow(c2);
    vec3 z = vec3(visWindowDepth(c0), visWindowDepth(c1), visWindowDepth(c2));
    VisRasterTri t;
    if (!visSetup(w0, w1, w2, z, id, t)) return;
    any_ = true;
    ivec2 extent = t.box.zw - t.box.xy + 1;
    if (extent.x <= RTGI_VISIBILITY_SMALL && extent.y <= RTGI_VISIBILITY_SMALL) {
        for (int y = t.box.y; y <= t.box.w; ++y)
            for (int x = t.box.x; x <= t.box.z; ++x) visRasterPixel(t, x, y);
        return;
    }
    small = false;
    if (uPhase != 0) return;
    uint slot = atomicAdd(counters.largeCount, 1u);
    if (slot >= uint(uCapacity.x)) return;  // overflow: reported by the pass after the frame
    large[slot] = visPack(t);
}

void main() {
    if (gl_LocalInvocationIndex == 0u) {
        sSmall = 0u;
        sCulled = 0u;
    }
    barrier();
    uint id = gl_GlobalInvocationID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (id < uint(uTriangles)) {
        uvec3 v = visTriangle(id);
        vec4 c0 = uViewProj * vec4(visPosition(v.x), 1.0);
        vec4 c1 = uViewProj * vec4(visPosition(v.y), 1.0);
        vec4 c2 = uViewProj * vec4(visPosition(v.z), 1.0);
        bool any_ = false, small = true;
        // Trivial frustum reject: all three vertices outside one clip plane.
        bool outside = (c0.x > c0.w && c1.x > c1.w && c2.x > c2.w) || (c0.x < -c0.w && c1.x < -c1.w && c2.x < -c2.w) ||
                       (c0.y > c0.w && c1.y > c1.w && c2.y > c2.w) || (c0.y < -c0.w && c1.y < -c1.w && c2.y < -c2.w) ||
                       (c0.z > c0.w && c1.z > c1.w && c2.z > c2.w) || (c0.z < -c0.w && c1.z < -c1.w && c2.z < -c2.w);
        if (!outside) {
            vec2 guard = visGuardNdc();
            bool inside = true;
            for (int k = 0; k < 5; ++k)
                inside = inside && visPlane(c0, k, guard) >= 0.0 && visPlane(c1, k, guard) >= 0.0 &&
                         visPlane(c2, k, guard) >= 0.0;
            if (inside) {
                emit(c0, c1, c2, id, any_, small);
            } else {
                // Clipped polygon as a fan; every piece keeps the triangle id
                // (the resolve needs only the original vertices).
                vec4 poly[8];
                int n = visClip(c0, c1, c2, poly);
                for (int k = 1; k + 1 < n; ++k) emit(poly[0], poly[k], poly[k + 1], id, any_, small);
            }
        }
        if (uPhase == 0) {
            if (!any_) atomicAdd(sCulled, 1u);
            else if (small) atomicAdd(sSmall, 1u);
        }
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u && uPhase == 0) {
        if (sSmall != 0u) atomicAdd(counters.smallCount, sSmall);
        if (sCulled != 0u) atomicAdd(counters.culledCount, sCulled);
    }
}
