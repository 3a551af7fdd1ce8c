// The one set of circle constants for every shader (lib/common.glsl includes
// it; libraries without frame data, e.g. brdf.glsl, include it directly).
#pragma once

const float PI = 3.14159265358979323846;
const float INV_PI = 0.31830988618379067154;
const float TWO_PI = 2.0 * PI;   // exact in float: a power-of-two multiple of PI
const float HALF_PI = 0.5 * PI;
