// Moves the injected point to its cell: x/y in the viewport, z as the layer.
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"

layout(points) in;
layout(points, max_vertices = 1) out;

layout(location = RTGI_LPV_VARY_CELL) flat in ivec4 vCell[];
layout(location = RTGI_LPV_VARY_R) flat in vec4 vR[];
layout(location = RTGI_LPV_VARY_G) flat in vec4 vG[];
layout(location = RTGI_LPV_VARY_B) flat in vec4 vB[];
layout(location = RTGI_LPV_VARY_R) flat out vec4 gR;
layout(location = RTGI_LPV_VARY_G) flat out vec4 gG;
layout(location = RTGI_LPV_VARY_B) flat out vec4 gB;

void main() {
    if (vCell[0].w == 0) return;
    vec2 xy = (vec2(vCell[0].xy) + 0.5) / vec2(lpv.grid.xy) * 2.0 - 1.0;
    gl_Position = vec4(xy, 0.0, 1.0);
    gl_PointSize = 1.0;
    gl_Layer = vCell[0].z;
    gR = vR[0];
    gG = vG[0];
    gB = vB[0];
    EmitVertex();
    EndPrimitive();
}
