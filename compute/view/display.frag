// Shows one texture of the frame in rtgi-view's window. Modes map what the
// texture holds to display values (docs/viewer.md):
// 0 display-ready (ldr), 1 linear radiance x scale -> sRGB, 2 signed vector
// x 0.5 + 0.5, 3 one channel x scale (grey), 4 linear depth / far.
#include "lib/tonemap.glsl"
#include "lib/view_shared.h"

layout(binding = RTGI_VIEW_TEX_IMAGE) uniform sampler2D uImage;
layout(location = RTGI_VIEW_LOC_MODE) uniform int uMode;
layout(location = RTGI_VIEW_LOC_SCALE) uniform float uScale;
layout(location = RTGI_VIEW_LOC_FAR) uniform float uFar;

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() {
    vec4 t = texture(uImage, vUv);
    vec3 c;
    if (uMode == 0) c = t.rgb;
    else if (uMode == 1) c = linearToSrgb(max(t.rgb * uScale, vec3(0.0)));
    else if (uMode == 2) c = t.rgb * 0.5 + 0.5;
    else if (uMode == 3) c = vec3(t.r * uScale);
    else c = vec3(uFar > 0.0 ? t.r / uFar : 0.0);
    outColor = vec4(clamp(c, 0.0, 1.0), 1.0);
}
