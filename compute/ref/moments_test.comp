// Test kernel of the GPU tier (tests/gpu/test_reference_convergence.cpp):
// feeds lib/moments.glsl, as ref/path.comp does, a fixed sample stream that
// is stiff for fp32: x_k(p) = 1000 + ((7919·k + 31·p.x + 17·p.y) mod 101)/128
// (exact in fp32: a variance of ~0.05 under a mean of ~1000).
#include "lib/bvh_shared.h"
#include "lib/moments.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = RTGI_REF_IMG_ACCUM) uniform image2D uAccum;    // mean (rgb), n (a)
layout(rgba32f, binding = RTGI_REF_IMG_ACCUM_SQ) uniform image2D uAccumSq;  // M2 (rgb)
layout(location = RTGI_REF_LOC_SAMPLES) uniform uvec3 uBatch;  // first sample index, samples, image edge

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(p, uvec2(uBatch.z)))) return;
    Moments batch = momentsEmpty();
    for (uint k = uBatch.x; k < uBatch.x + uBatch.y; ++k)
        momentsAdd(batch, vec3(1000.0 + float((7919u * k + 31u * p.x + 17u * p.y) % 101u) * (1.0 / 128.0)));
    Moments m = momentsMerge(momentsLoad(imageLoad(uAccum, ivec2(p)), imageLoad(uAccumSq, ivec2(p))), batch);
    imageStore(uAccum, ivec2(p), vec4(m.mean, m.n));
    imageStore(uAccumSq, ivec2(p), vec4(m.m2, 0.0));
}
