// lpv.apply: outgoing indirect diffuse radiance from the accumulated volume
// (SPEC 3.6, normalization in docs/lpv.md): a cell's coefficients are the
// intensity I(w) of the light flowing through it, radiance L = I / s^2, and
// light arriving from direction w flows along -w, so the irradiance of a
// surface with normal n is E = max(0, <I, cosLobe(-n)>) / s^2.
// Specular (RTGI_LPV_SPECULAR): 3 samples along R (seed listing 8), each the
// radiance arriving from R, averaged, times the split-sum term (F0 A + B)
// when a BRDF LUT exists (RTGI_LPV_BRDF_LUT), else times F0.
// Hooks: RTGI_LPV_BENT_NORMAL looks up along the AO pass's bent normal;
// RTGI_LPV_S3HO integrates against the SH visibility instead of the cosine.
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"
#include "lib/depth.glsl"
#include "lib/brdf.glsl"

layout(local_size_x = RTGI_LPV_LOCAL_2D, local_size_y = RTGI_LPV_LOCAL_2D) in;

layout(binding = RTGI_LPV_TEX_LINEAR_DEPTH) uniform sampler2D uLinearDepth;
layout(binding = RTGI_LPV_TEX_VIEW_NORMAL) uniform sampler2D uViewNormal;
layout(binding = RTGI_LPV_TEX_ALBEDO) uniform sampler2D uAlbedo;
layout(binding = RTGI_LPV_TEX_MATERIAL) uniform sampler2D uMaterial;
layout(binding = RTGI_LPV_TEX_LIGHT_R) uniform sampler3D uLightR;
layout(binding = RTGI_LPV_TEX_LIGHT_G) uniform sampler3D uLightG;
layout(binding = RTGI_LPV_TEX_LIGHT_B) uniform sampler3D uLightB;
layout(binding = RTGI_LPV_TEX_BRDF_LUT) uniform sampler2D uBrdfLut;
layout(binding = RTGI_LPV_TEX_DIRECTIONAL) uniform sampler2D uDirectional;  // bent normal (xyz, view) or S3HO SH (view)
layout(rgba16f, binding = RTGI_LPV_IMG_INDIRECT) uniform writeonly image2D uIndirect;
layout(rgba16f, binding = RTGI_LPV_IMG_SPECULAR) uniform writeonly image2D uSpecular;

// Trilinear lookup; outside the grid there is no LPV light.
bool lpvSample(vec3 world, out vec4 r, out vec4 g, out vec4 b) {
    vec3 uvw = lpvCellCoord(world) / vec3(lpv.grid.xyz);
    r = g = b = vec4(0.0);
    if (any(lessThan(uvw, vec3(0.0))) || any(greaterThan(uvw, vec3(1.0)))) return false;
    r = texture(uLightR, uvw);
    g = texture(uLightG, uvw);
    b = texture(uLightB, uvw);
    return true;
}

// The AO pass writes bent normals / S3HO at AO resolution (half by default):
// address them by UV, not by this pass's pixel (nearest texel, no blending
// across depth edges).
vec4 directionalAt(vec2 uv) {
    ivec2 size = textureSize(uDirectional, 0);
    return texelFetch(uDirectional, clamp(ivec2(uv * vec2(size)), ivec2(0), size - 1), 0);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, frameSize()))) return;
    float d = texelFetch(uLinearDepth, p, 0).r;
    vec3 diffuse = vec3(0.0), specular = vec3(0.0);
    if (!isSky(d)) {
        vec2 uv = (vec2(p) + 0.5) / vec2(frameSize());
        vec3 vp = viewPositionFromDepth(uv, d, frame.projParams.z, frame.projParams.w);
        vec3 wp = viewToWorldPoint(vp);
        vec3 vn = texelFetch(uViewNormal, p, 0).xyz;
        vec3 n = dot(vn, vn) > 0.0 ? normalize(viewToWorldDir(vn)) : vec3(0.0, 1.0, 0.0);
        vec3 albedo = texelFetch(uAlbedo, p, 0).rgb;
        vec2 rm = texelFetch(uMaterial, p, 0).rg;
        float invArea = lpv.rsm.y;  // 1 / s^2: intensity -> radiance
        vec3 lookupN = n;
#ifdef RTGI_LPV_BENT_NORMAL
        vec3 bent = directionalAt(uv).xyz;
        if (dot(bent, bent) > 0.0) lookupN = normalize(viewToWorldDir(bent));
#endif
        vec4 r, g, b;
        // Half a cell along the normal: the light in front of the surface, as injected (3.3).
        if (lpvSample(wp + 0.5 * lpvCellSize() * n, r, g, b)) {
#ifdef RTGI_LPV_S3HO
            vec4 w = shRotate(directionalAt(uv), mat3(frame.invView));
            vec3 e = vec3(dot(shMirror(r), w), dot(shMirror(g), w), dot(shMirror(b), w));
#else
            vec3 e = vec3(shCosineIntegral(shMirror(r), lookupN), shCosineIntegral(shMirror(g), lookupN),
                          shCosineIntegral(shMirror(b), lookupN));
#endif
            diffuse = diffuseAlbedo(albedo, rm.y) * INV_PI * max(e, vec3(0.0)) * invArea;
        }
#ifdef RTGI_LPV_SPECULAR
        vec3 v = normalize(frame.cameraPos.xyz - wp);
        vec3 R = reflect(-v, n);
        vec3 sum = vec3(0.0);
        for (int i = 1; i <= 3; ++i) {
            if (lpvSample(wp + R * (float(i) * lpvCellSize()), r, g, b))
                sum += max(vec3(shEvaluate(r, -R), shEvaluate(g, -R), shEvaluate(b, -R)), vec3(0.0));
        }
        vec3 f0 = specularF0(albedo, rm.y);
#ifdef RTGI_LPV_BRDF_LUT
        vec2 ab = texture(uBrdfLut, vec2(clamp(dot(n, v), 0.0, 1.0), rm.x)).rg;
        vec3 brdf = f0 * ab.x + ab.y;
#else
        vec3 brdf = f0;
#endif
        specular = brdf * (sum / 3.0) * invArea * lpv.rsm.z;
#endif
    }
    imageStore(uIndirect, p, vec4(diffuse * lpv.rsm.z, 1.0));
#ifdef RTGI_LPV_SPECULAR
    imageStore(uSpecular, p, vec4(specular, 1.0));
#endif
}
