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
#endif
