layout(location = 1) uniform vec4 uColor;
layout(location = 0) out vec4 outColor;

void main() { outColor = uColor; }
