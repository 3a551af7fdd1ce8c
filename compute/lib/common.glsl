// Frame constants and the conventions every pass shares.
#pragma once
#include "lib/shared.h"
#include "lib/math.glsl"

layout(std140, binding = RTGI_UBO_FRAME) uniform FrameBlock { FrameUniforms frame; };


ivec2 frameSize() { return frame.size.xy; }
bool cameraCut() { return frame.size.w != 0; }
uint frameIndex() { return uint(frame.size.z); }

// Linear algebra on the frame's matrices.
vec3 viewToWorldPoint(vec3 p) { return (frame.invView * vec4(p, 1.0)).xyz; }
vec3 viewToWorldDir(vec3 d) { return mat3(frame.invView) * d; }
vec3 worldToViewDir(vec3 d) { return mat3(frame.view) * d; }

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// Largest finite half float. Values stored into 16-bit float images are
// clamped to it (overflow would become Inf); --check counts |x| >= this as
// "fp16 saturated" so the clamp is visible in results (docs/STABILITY.md).
const float HALF_MAX = 65504.0;
vec4 clampHalf(vec4 x) { return clamp(x, vec4(-HALF_MAX), vec4(HALF_MAX)); }
vec3 clampHalf(vec3 x) { return clamp(x, vec3(-HALF_MAX), vec3(HALF_MAX)); }
