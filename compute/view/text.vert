// Overlay text and panels of rtgi-view: triangles in window pixels (stb_easy_font
// quads split in two on the CPU), pulled from a buffer by gl_VertexID.
layout(std430, binding = 0) readonly buffer Positions { vec2 positions[]; };
layout(location = 0) uniform vec2 uWindowSize;

void main() {
    vec2 p = positions[gl_VertexID] / uWindowSize;
    gl_Position = vec4(p.x * 2.0 - 1.0, 1.0 - p.y * 2.0, 0.0, 1.0);
}
