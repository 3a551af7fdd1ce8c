// Visibility-buffer depth -> a D32F depth texture (G-buffer depth, shadow
// map, RSM depth): depth formats cannot be image-stored and consumers sample
// them as depth (shadow compare), so one full-screen triangle writes
// gl_FragDepth (depth test ALWAYS). Empty pixels get the clear value 1.
#include "lib/raster.glsl"

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float depth;
    uint id;
    gl_FragDepth = visRead(uint(pixel.y) * uint(uSize.x) + uint(pixel.x), depth, id) ? depth : 1.0;
}
