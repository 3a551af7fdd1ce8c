// ref.ao: ray-traced ambient occlusion from the G-buffer surface (SPEC 7.1a):
// cosine-weighted hemisphere rays of maximum length uRayLength; visibility 1
// when nothing is hit. Adds this dispatch's samples to the accumulation
// images (one invocation owns its pixel: plain load/store, no atomics).
#include "lib/common.glsl"
#include "lib/bvh_shared.h"
#include "lib/depth.glsl"
#include "lib/random.glsl"
#include "lib/sampling.glsl"
#include "lib/bvh.glsl"
#include "lib/moments.glsl"

layout(local_size_x = RTGI_REF_LOCAL, local_size_y = RTGI_REF_LOCAL) in;

layout(binding = RTGI_REF_AO_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
layout(binding = RTGI_REF_AO_TEX_NORMAL) uniform sampler2D uNormal;
layout(rgba32f, binding = RTGI_REF_IMG_ACCUM) uniform image2D uAccum;    // running mean (rgb), sample count (a)
layout(rgba32f, binding = RTGI_REF_IMG_ACCUM_SQ) uniform image2D uAccumSq;  // running M2 (rgb): lib/moments.glsl


layout(location = RTGI_REF_LOC_SAMPLES) uniform uvec4 uSamples;  // first sample index, samples in this dispatch, seed
layout(location = RTGI_REF_LOC_RAY) uniform float uRayLength;    // maximum ray length

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, frameSize()))) return;
    float n = float(uSamples.y);
    float visible = n;  // sky pixels: unoccluded
    float d = texelFetch(uLinearDepth, p, 0).r;
    if (!isSky(d)) {
        vec2 uv = (vec2(p) + 0.5) / vec2(frameSize());
        vec3 wp = viewToWorldPoint(viewPositionFromDepth(uv, d, frame.projParams.z, frame.projParams.w));
        vec3 nrm = viewToWorldDir(texelFetch(uNormal, p, 0).xyz);
        float len = length(nrm);
        nrm = len > 0.0 ? nrm / len : vec3(0.0, 1.0, 0.0);
        if (dot(nrm, frame.cameraPos.xyz - wp) < 0.0) nrm = -nrm;
        // x1: the pixel-centre ray's hit, or the G-buffer point where the
        // raster shows a surface the ray misses (bvh.glsl gbufferFirstVertex).
        vec3 r = viewToWorldDir(viewPositionFromDepth(uv, 1.0, frame.projParams.z, frame.projParams.w));
        FirstVertex x1 = gbufferFirstVertex(frame.cameraPos.xyz, wp, r, d, nrm, frame.projParams.x,
                                            2.0 * frame.projParams.z / float(frameSize().y));
        vec3 origin = x1.origin;
        nrm = x1.normal;
        visible = 0.0;
        for (uint s = 0u; s < uSamples.y; ++s) {
            Rng rng = rngInit(uvec2(p), uSamples.x + s, uSamples.z);
            vec3 dir = cosineHemisphere(rngNext2(rng), nrm);
            if (!traceAny(origin, dir, 0.0, uRayLength)) visible += 1.0;
        }
    }
    // Visibility is 0 or 1: a batch of n rays with k visible has mean k/n
    // and M2 = Σ(x − k/n)² = k·(1 − k/n).
    float mean = visible / n;
    Moments batch = Moments(vec3(mean), vec3(visible * (1.0 - mean)), n);
    Moments m = momentsMerge(momentsLoad(imageLoad(uAccum, p), imageLoad(uAccumSq, p)), batch);
    imageStore(uAccum, p, vec4(m.mean, m.n));
    imageStore(uAccumSq, p, vec4(m.m2, 0.0));
    bvhCommitRayCount(uSamples.x);
}
