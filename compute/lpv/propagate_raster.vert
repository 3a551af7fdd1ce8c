// Seed-method propagation (lpv.path=raster, seed 5.2.4): one full-screen
// triangle per volume slice (instance = slice).
#include "lib/lpv_shared.h"
layout(location = RTGI_LPV_VARY_LAYER) flat out int vLayer;

void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
    vLayer = gl_InstanceID;
}
