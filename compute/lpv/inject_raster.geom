// Moves the injected point to its cell: x/y in the viewport, z as the layer.
#include "lpv/lpv_common.glsl"

layout(points) in;
layout(points, max_vertices = 1) out;

layout(location = 0) flat in ivec4 vCell[];
layout(location = 1) flat in vec4 vR[];
layout(location = 2) flat in vec4 vG[];
layout(location = 3) flat in vec4 vB[];
layout(location = 1) flat out vec4 gR;
layout(location = 2) flat out vec4 gG;
layout(location = 3) flat out vec4 gB;

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
