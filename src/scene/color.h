#pragma once
// Rec. 709 relative luminance of linear RGB: the CPU twin of compute/lib/common.glsl's luminance().

namespace rtgi {

inline double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

}  // namespace rtgi
