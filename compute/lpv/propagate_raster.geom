// Routes the slice's triangle to its layer of the 3D render targets.
#include "lib/lpv_shared.h"
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

layout(location = RTGI_LPV_VARY_LAYER) flat in int vLayer[];

void main() {
    for (int i = 0; i < 3; ++i) {
        gl_Position = gl_in[i].gl_Position;
        gl_Layer = vLayer[0];
        EmitVertex();
    }
    EndPrimitive();
}
