// Overlay text and panels of rtgi-view: triangles in window pixels (stb_easy_font
// quads split in two on the CPU), pulled from a buffer by gl_VertexID.
#include "lib/view_shared.h"
layout(std430, binding = RTGI_VIEW_SSBO_POSITIONS) readonly buffer Positions { vec2 positions[]; };
layout(location = RTGI_VIEW_LOC_WINDOW_SIZE) uniform vec2 uWindowSize;

void main() {
    vec2 p = positions[gl_VertexID] / uWindowSize;
    gl_Position = vec4(p.x * 2.0 - 1.0, 1.0 - p.y * 2.0, 0.0, 1.0);
}
