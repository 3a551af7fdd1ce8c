// ao.nearfield: near-field indirect light (seed 000 4.2.1, eq. 16) from the
// previous frame's radiance reprojected with the velocity buffer; written to
// its own R11F_G11F_B10F image and added into the indirect diffuse term
// (or written alone when no producer filled it this frame).
#include "lib/common.glsl"
#include "lib/depth.glsl"
#include "lib/brdf.glsl"
#include "lib/ao_shared.h"
#include "lib/ao.glsl"
#include "lib/noise.glsl"
#include "lib/filter.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std140, binding = RTGI_UBO_AO) uniform AoBlock { AoParams ao; };
layout(binding = RTGI_AO_TEX_DEPTH) uniform sampler2D uDepth;
layout(binding = RTGI_AO_TEX_NORMAL) uniform sampler2D uNormal;
layout(binding = RTGI_AO_NEARFIELD_TEX_ALBEDO) uniform sampler2D uAlbedo;
layout(binding = RTGI_AO_TEX_MATERIAL) uniform sampler2D uMaterial;
layout(binding = RTGI_AO_TEX_HISTORY) uniform sampler2D uHistory;   // previous frame HDR (post.history)
layout(binding = RTGI_AO_TEX_VELOCITY) uniform sampler2D uVelocity;
layout(binding = RTGI_AO_NEARFIELD_TEX_NOISE) uniform sampler2DArray uNoise;
layout(r11f_g11f_b10f, binding = RTGI_AO_IMG_NEAR_FIELD) uniform writeonly image2D uNearField;
layout(rgba16f, binding = RTGI_AO_IMG_INDIRECT) uniform image2D uIndirect;
layout(location = RTGI_AO_LOC_ACCUMULATE) uniform int uAccumulate;  // 1: add into uIndirect, 0: overwrite it
layout(location = RTGI_AO_LOC_HISTORY_VALID) uniform int uHistoryValid;

// The previous frame's radiance leaving the surface visible at uvS (linear depth zScene; q its
// texel, of depth zTexel): the history reprojected by the velocity, nothing where it is
// disoccluded or off-screen. Shared by both estimators.
bool senderRadiance(vec2 uvS, float zScene, ivec2 q, float zTexel, out vec3 radiance) {
    ivec2 size = frameSize();
    float tanHalf = frame.projParams.z, aspect = frame.projParams.w;
    radiance = vec3(0.0);
    vec3 sender = viewPositionFromDepth(uvS, zScene, tanHalf, aspect);
    vec2 velocity = texelFetch(uVelocity, q, 0).xy;
    vec2 uvPrev = uvS + velocity;
    if (any(lessThan(uvPrev, vec2(0.0))) || any(greaterThanEqual(uvPrev, vec2(1.0)))) return false;
    vec4 history = texture(uHistory, uvPrev);  // a: the previous frame's linear depth (post.history)
    // A sender whose history is another surface (disoccluded) sends nothing this frame.
    float expected = -(frame.prevView * vec4(viewToWorldPoint(sender), 1.0)).z;
    if (historyDisoccluded(history.a, expected, zScene, depthSlopePerPixel(uDepth, q, size, zTexel),
                           velocity * vec2(size), exp2(-10.0)))
        return false;
    radiance = history.rgb;
    return true;
}

#ifdef RTGI_AO_NEARFIELD_BITMASK
// Bitmask near-field light (docs/ao.md, "Bitmask near-field light"; Therrien et al. 2023 §5):
// vbao's march over the full-resolution depth; every sample adds its radiance times the
// cosine-weighted measure of the sectors it is the first to occlude.
#define AO_VBAO_GATHER 1
vec3 gP, gGather;
float gOpen;
// The texel's surface extended as a plane to the exact ray through uv (as ao.comp).
float aoSceneDepth(vec2 uv) {
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return 0.0;
    ivec2 q = ivec2(uv * vec2(frameSize()));
    float z = texelFetch(uDepth, q, 0).r;
    if (isSky(z)) return z;
    float tanHalf = frame.projParams.z, aspect = frame.projParams.w;
    vec3 Q = viewPositionFromDepth((vec2(q) + 0.5) / vec2(frameSize()), z, tanHalf, aspect);
    vec3 nQ = aoSafeNormal(texelFetch(uNormal, q, 0).xyz, Q);
    return aoPlaneDepthAlongRay(Q, nQ, uv, tanHalf, aspect, z);
}
float aoSceneDepth2(vec2 uv) { return 0.0; }
float aoPointOcclusion(vec3 P, vec3 S, float R) { return 0.0; }
vec3 aoKernel(int i) { return vec3(0.0); }
vec4 aoVoSample(int i) { return vec4(0.0); }
void aoVbaoGather(vec2 uvS, vec3 S, float zS, float w) {
    if (!(w > 0.0)) return;
    ivec2 q = ivec2(uvS * vec2(frameSize()));
    vec3 nS = aoSafeNormal(texelFetch(uNormal, q, 0).xyz, S);
    if (dot(nS, gP - S) <= 0.0) return;  // the sender's back: it sends nothing towards P
    vec3 radiance;
    if (senderRadiance(uvS, zS, q, texelFetch(uDepth, q, 0).r, radiance)) gGather += w * radiance;
}
void aoVbaoGatherOpen(float open) { gOpen += open; }
#include "lib/ao_estimators.glsl"
#endif

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = frameSize();
    if (any(greaterThanEqual(p, size))) return;
    vec3 L = vec3(0.0);
    float d = texelFetch(uDepth, p, 0).r;
    if (!isSky(d) && uHistoryValid != 0) {
        vec2 uv = (vec2(p) + 0.5) / vec2(size);
        float tanHalf = frame.projParams.z, aspect = frame.projParams.w;
        vec3 P = viewPositionFromDepth(uv, d, tanHalf, aspect);
        vec3 n = aoSafeNormal(texelFetch(uNormal, p, 0).xyz, P);
        vec4 bn = blueNoise(uNoise, p, frameIndex());
        float a = TWO_PI * bn.x;
        mat3 basis = aoBasis(n, vec3(cos(a), sin(a), 0.0));
        vec3 rho = diffuseAlbedo(texelFetch(uAlbedo, p, 0).rgb, texelFetch(uMaterial, p, 0).g);
        float R = ao.radius.x;
#ifdef RTGI_AO_NEARFIELD_BITMASK
        gP = P;
        gGather = vec3(0.0);
        gOpen = 0.0;
        AoCamera cam = AoCamera(ao.focal.xy, tanHalf, aspect, vec2(size));
        aoVbao(cam, uv, P, n, d, R, bn.xyz, ao.counts.y, ao.counts.z, ao.bitmask.x, ao.bitmask.y != 0.0, false);
        // (1/pi) E = sum of L w / open (the slices' quadrature of the cosine lobe, as vbao's visibility):
        // the outgoing radiance rho / pi E.
        if (gOpen > 1e-6) L = rho * gGather / gOpen;
#else
        int N = ao.counts.x;
        float senderArea = PI * R * R / float(N);  // A_s = pi r_max^2 / N
        for (int i = 0; i < N; ++i) {
            vec3 o = ao.kernel[i].xyz;
            o.z = abs(o.z);
            vec3 S = P + R * (basis * o);
            vec3 uvS = uvFromViewPosition(S, tanHalf, aspect);
            if (any(lessThan(uvS.xy, vec2(0.0))) || any(greaterThanEqual(uvS.xy, vec2(1.0)))) continue;
            ivec2 q = ivec2(uvS.xy * vec2(size));
            float zTexel = texelFetch(uDepth, q, 0).r;
            if (isSky(zTexel)) continue;
            // The texel's surface extended as a plane to the sample's exact ray
            // (as in ao.comp): the sender lies on the surface, not half a texel off.
            vec3 Q = viewPositionFromDepth((vec2(q) + 0.5) / vec2(size), zTexel, tanHalf, aspect);
            vec3 nS = aoSafeNormal(texelFetch(uNormal, q, 0).xyz, Q);
            float zScene = aoPlaneDepthAlongRay(Q, nS, uvS.xy, tanHalf, aspect, zTexel);
            // V(w_i) = 0 (occluded): the blocker visible there is the sender.
            if (zScene >= uvS.z - 0.02 * R) continue;
            vec3 sender = viewPositionFromDepth(uvS.xy, zScene, tanHalf, aspect);
            vec3 radiance;
            if (!senderRadiance(uvS.xy, zScene, q, zTexel, radiance)) continue;
            L += nearFieldSample(rho, radiance, sender - P, nS, n, senderArea, R);
        }
#endif
        L *= ao.misc.y;  // strength (seed used 3)
    }
    imageStore(uNearField, p, vec4(L, 0.0));
    vec4 base = uAccumulate != 0 ? imageLoad(uIndirect, p) : vec4(0.0, 0.0, 0.0, 1.0);
    imageStore(uIndirect, p, vec4(base.rgb + L, base.a));
}
