// Test kernel of the GPU tier: closest-hit and any-hit traversal of given
// rays (origin.xyz, tMax in w; direction.xyz), written back for comparison
// with a brute-force loop over all triangles on the CPU.
#include "lib/common.glsl"
#include "lib/bvh_shared.h"
#include "lib/bvh.glsl"

layout(local_size_x = 64) in;

struct TestRay {
    vec4 origin;     // xyz, w = tMax
    vec4 direction;  // xyz; out: x = closest t (-1 miss), y = triangle id bits, z = any-hit (0/1)
};
layout(std430, binding = RTGI_SSBO_REF_RAYS) buffer RayBlock { TestRay rays[]; };
layout(location = RTGI_REF_LOC_COUNT) uniform uint uCount;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uCount) return;
    vec3 o = rays[i].origin.xyz, d = rays[i].direction.xyz;
    float tMax = rays[i].origin.w;
    Hit h;
    bool hit = traceClosest(o, d, 0.0, tMax, h);
    bool any = traceAny(o, d, 0.0, tMax);
    rays[i].direction = vec4(hit ? h.t : -1.0, uintBitsToFloat(hit ? h.triangle : 0u), any ? 1.0 : 0.0, 0.0);
}
