// A G-buffer sample as a surfel for the LPV's camera-side injections (lpv/inject_geometry.comp
// with RTGI_LPV_GV_GBUFFER, lpv/inject.comp with RTGI_LPV_INJECT_SKY): the surface at pixel
// `full`, standing for the stride x stride pixels it samples (lpv.geometry_stride).
#pragma once
#include "lib/common.glsl"
#include "lib/depth.glsl"

// World position, world normal and the surface area of the stride^2 pixels. A pinhole pixel at
// angle theta off the view axis subtends the solid angle (2 tan(fovY/2) / H)^2 cos^3 theta; at the
// distance r = d / cos theta (d the linear depth) on a surface whose normal makes the angle V
// with the view ray it covers that solid angle * r^2 / cos V = (2 d tan / H)^2 cos theta / cos V
// (docs/lpv.md, "Sky bounce"). cos V is clamped below by `minCos` (grazing views). False for sky
// pixels, pixels outside the frame and pixels without a normal.
bool lpvGBufferSurfel(sampler2D linearDepth, sampler2D viewNormal, ivec2 full, int stride, float minCos,
                      out vec3 wp, out vec3 n, out float area) {
    wp = n = vec3(0.0);
    area = 0.0;
    if (any(greaterThanEqual(full, frameSize()))) return false;
    float d = texelFetch(linearDepth, full, 0).r;
    if (isSky(d)) return false;
    vec2 uv = (vec2(full) + 0.5) / vec2(frameSize());
    vec3 vp = viewPositionFromDepth(uv, d, frame.projParams.z, frame.projParams.w);
    vec3 vn = texelFetch(viewNormal, full, 0).xyz;
    if (!(dot(vn, vn) > 0.0)) return false;
    vn = normalize(vn);
    float pixel = 2.0 * d * frame.projParams.z / float(frameSize().y);
    vec3 toEye = normalize(-vp);
    float cosTheta = toEye.z;  // the view ray against the view axis (the eye looks along -z)
    float cosView = max(dot(vn, toEye), minCos);
    area = float(stride * stride) * pixel * pixel * cosTheta / cosView;
    wp = viewToWorldPoint(vp);
    n = viewToWorldDir(vn);
    return true;
}
