// ref.path: path-traced radiance at the G-buffer surface (SPEC 7.1b).
//   RTGI_REF_FULL: everything (emission + direct light with shadow rays +
//     indirect, sky for escaping rays), compared with the composed hdr;
//   otherwise indirect diffuse only: light that reached the G-buffer surface
//     x1 after at least one other surface, reflected by x1's Lambert lobe
//     (diffuseAlbedo/π·E, the convention of res.indirectDiffuse). x1's own
//     emission, its direct sun/punctual light and sky seen directly from x1
//     (the compose pass's ambient term) are excluded.
// Next-event estimation for the sun and punctual lights (shadow rays) and,
// with RTGI_REF_EMITTER_NEE, for emissive triangles (area sampling, MIS with
// the BRDF-sampled rays that hit them, ref_scene.glsl); sky is picked up by
// BRDF-sampled rays. In the indirect kind with RTGI_REF_EMISSION_IS_DIRECT
// (emissive.lights=on), emission seen directly from x1 is x1's direct light
// (the real-time path turns emitters into lights of the direct pass) and is
// left out. uSamples.w caps the number of bounces
// after x1; Russian roulette from the third on.
#include "lib/common.glsl"
#include "lib/bvh_shared.h"
#include "lib/depth.glsl"
#include "lib/brdf.glsl"
#include "lib/random.glsl"
#include "lib/sampling.glsl"
#include "lib/bvh.glsl"
#include "lib/lights.glsl"
#include "lib/ref_scene.glsl"
#include "lib/moments.glsl"

layout(local_size_x = RTGI_REF_LOCAL, local_size_y = RTGI_REF_LOCAL) in;

layout(binding = RTGI_REF_PATH_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
layout(binding = RTGI_REF_PATH_TEX_NORMAL) uniform sampler2D uNormal;
layout(binding = RTGI_REF_TEX_ALBEDO) uniform sampler2D uAlbedo;
layout(binding = RTGI_REF_TEX_MATERIAL) uniform sampler2D uMaterial;
layout(binding = RTGI_REF_TEX_EMISSIVE) uniform sampler2D uEmissive;
layout(rgba32f, binding = RTGI_REF_IMG_ACCUM) uniform image2D uAccum;    // running mean (rgb), sample count (a)
layout(rgba32f, binding = RTGI_REF_IMG_ACCUM_SQ) uniform image2D uAccumSq;  // running M2 (rgb): lib/moments.glsl


layout(location = RTGI_REF_LOC_SAMPLES) uniform uvec4 uSamples;  // first sample index, samples in this dispatch, seed, max bounces

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, frameSize()))) return;
    Moments batch = momentsEmpty();
    float d = texelFetch(uLinearDepth, p, 0).r;
    if (isSky(d)) {
        // A constant: mean = sky (full) or 0 (indirect), no deviation.
#ifdef RTGI_REF_FULL
        batch.mean = frame.sky.rgb;
#endif
        batch.n = float(uSamples.y);
    } else {
        vec2 uv = (vec2(p) + 0.5) / vec2(frameSize());
        Surface s;
        vec3 gp = viewToWorldPoint(viewPositionFromDepth(uv, d, frame.projParams.z, frame.projParams.w));
        vec3 n = viewToWorldDir(texelFetch(uNormal, p, 0).xyz);
        float len = length(n);
        n = len > 0.0 ? n / len : vec3(0.0, 1.0, 0.0);
        if (dot(n, frame.cameraPos.xyz - gp) < 0.0) n = -n;
        // x1: the pixel-centre ray's hit, or the G-buffer point where the
        // raster shows a surface the ray misses (bvh.glsl gbufferFirstVertex);
        // albedo, material and emission are the G-buffer's either way.
        vec3 r = viewToWorldDir(viewPositionFromDepth(uv, 1.0, frame.projParams.z, frame.projParams.w));
        FirstVertex x1 = gbufferFirstVertex(frame.cameraPos.xyz, gp, r, d, n, frame.projParams.x,
                                            2.0 * frame.projParams.z / float(frameSize().y));
        s.position = x1.position;
        vec3 v = normalize(frame.cameraPos.xyz - s.position);
        n = x1.normal;
        s.normal = n;
        s.geometric = x1.geometric;
        s.albedo = texelFetch(uAlbedo, p, 0).rgb;
        vec2 rm = texelFetch(uMaterial, p, 0).rg;
        s.roughness = rm.x;
        s.metallic = rm.y;
        s.emission = texelFetch(uEmissive, p, 0).rgb;
        s.specular = 1.0;
        vec3 origin = x1.origin;
        for (uint k = 0u; k < uSamples.y; ++k) {
            Rng rng = rngInit(uvec2(p), uSamples.x + k, uSamples.z);
#ifdef RTGI_REF_FULL
            vec3 L = s.emission + directLight(s, v, origin) + sampleEmitters(s, v, origin, rng);
            vec3 l, w;
            float pdf;
            bool specularLobe;
            if (sampleBrdf(s, v, rng, l, w, pdf, specularLobe))
                L += refTraceRadiance(origin, l, pdf, w, uSamples.w, refDiffuseAfter(s, specularLobe, false), rng);
#else
            vec3 l = cosineHemisphere(rngNext2(rng), n);
            vec3 L = refTraceRadiance(origin, l, dot(n, l) * INV_PI, diffuseAlbedo(s.albedo, s.metallic), uSamples.w,
                                      true, rng);
#endif
            // A non-finite sample (degenerate geometry) is dropped, never accumulated.
            if (any(isnan(L)) || any(isinf(L))) L = vec3(0.0);
            momentsAdd(batch, L);
        }
    }
    // One invocation owns its pixel: plain load/store, no atomics.
    Moments m = momentsMerge(momentsLoad(imageLoad(uAccum, p), imageLoad(uAccumSq, p)), batch);
    imageStore(uAccum, p, vec4(m.mean, m.n));
    imageStore(uAccumSq, p, vec4(m.m2, 0.0));
    bvhCommitRayCount(uSamples.x);
}
