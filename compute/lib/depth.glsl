// Depth conventions: the G-buffer stores linear view depth d > 0 (distance
// along -z of view space), 0 for sky. These pure functions take the
// projection parameters explicitly so tests and other passes can reuse them.
#pragma once

// uv in [0,1]^2 (pixel centres at (i+0.5)/size), d linear depth,
// tanHalfFov = tan(fovY/2), aspect = width/height.
vec3 viewPositionFromDepth(vec2 uv, float d, float tanHalfFov, float aspect) {
    vec2 ndc = uv * 2.0 - 1.0;
    return vec3(ndc.x * tanHalfFov * aspect * d, ndc.y * tanHalfFov * d, -d);
}

// Inverse: view-space point -> uv (and its linear depth in .z).
vec3 uvFromViewPosition(vec3 p, float tanHalfFov, float aspect) {
    float d = -p.z;
    vec2 ndc = vec2(p.x / (tanHalfFov * aspect * d), p.y / (tanHalfFov * d));
    return vec3(ndc * 0.5 + 0.5, d);
}

bool isSky(float linearDepth) { return !(linearDepth > 0.0); }
