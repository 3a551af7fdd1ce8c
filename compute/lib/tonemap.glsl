// The one tonemapper (real-time frame and reference use the same): exposure,
// ACES filmic fit (Narkowicz 2015), sRGB encoding.
#pragma once

vec3 acesFilmic(vec3 x) {
    const float a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

vec3 linearToSrgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

vec3 tonemap(vec3 radiance, float exposure) {
    vec3 x = radiance * exposure;
    // Non-finite input must not turn into a plausible colour: mark it magenta.
    if (any(isnan(x)) || any(isinf(x))) return vec3(1.0, 0.0, 1.0);
    return linearToSrgb(acesFilmic(max(x, vec3(0.0))));
}
