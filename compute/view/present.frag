// rtgi-view's image display (docs/viewer.md): one texture mapped to display
// values by mode, exposure and channel; with the live reference, a split
// (technique | reference), the reference alone, side by side, or the heat map
// of |Δ luminance| (the ramp of metrics.cpp's errorHeatmap, black -> yellow).
#include "lib/tonemap.glsl"
#include "lib/view_shared.h"

layout(binding = RTGI_VIEW_TEX_IMAGE) uniform sampler2D uImage;
layout(binding = RTGI_VIEW_TEX_REFERENCE) uniform sampler2D uReference;
layout(location = RTGI_VIEW_LOC_MODE) uniform int uMode;
layout(location = RTGI_VIEW_LOC_SCALE) uniform float uScale;
layout(location = RTGI_VIEW_LOC_FAR) uniform float uFar;
layout(location = RTGI_VIEW_LOC_CHANNEL) uniform int uChannel;
layout(location = RTGI_VIEW_LOC_COMPARE) uniform int uCompare;
layout(location = RTGI_VIEW_LOC_SPLIT) uniform float uSplit;
layout(location = RTGI_VIEW_LOC_REF_MODE) uniform int uRefMode;
layout(location = RTGI_VIEW_LOC_HEAT_MAX) uniform float uHeatMax;

layout(location = RTGI_VIEW_VARY_UV) in vec2 vUv;
layout(location = RTGI_VIEW_OUT_COLOR) out vec4 outColor;

vec4 pickChannel(vec4 t) {
    if (uChannel == 0) return t;
    float v = uChannel == 1 ? t.r : uChannel == 2 ? t.g : uChannel == 3 ? t.b : t.a;
    return vec4(v, v, v, t.a);
}

vec3 display(vec4 t, int mode) {
    t = pickChannel(t);
    if (mode == RTGI_VIEW_MODE_READY) return t.rgb;
    if (mode == RTGI_VIEW_MODE_RADIANCE) return linearToSrgb(max(t.rgb * uScale, vec3(0.0)));
    if (mode == RTGI_VIEW_MODE_SIGNED) return t.rgb * 0.5 + 0.5;
    if (mode == RTGI_VIEW_MODE_GREY) return vec3(t.r * uScale);
    return vec3(uFar > 0.0 ? t.r / uFar : 0.0);
}

float luminanceOf(vec4 t, int mode) {
    if (mode == RTGI_VIEW_MODE_GREY) return t.r;
    return dot(t.rgb, vec3(0.2126, 0.7152, 0.0722));
}

// Black -> purple -> orange -> yellow (an inferno-like ordered ramp).
vec3 heat(float x) {
    x = clamp(x, 0.0, 1.0);
    const vec3 c0 = vec3(0.0, 0.0, 0.015), c1 = vec3(0.34, 0.06, 0.43), c2 = vec3(0.80, 0.25, 0.23),
               c3 = vec3(0.99, 0.64, 0.04), c4 = vec3(0.99, 1.0, 0.64);
    if (x < 0.25) return mix(c0, c1, x * 4.0);
    if (x < 0.5) return mix(c1, c2, (x - 0.25) * 4.0);
    if (x < 0.75) return mix(c2, c3, (x - 0.5) * 4.0);
    return mix(c3, c4, (x - 0.75) * 4.0);
}

void main() {
    vec2 uv = vUv;
    vec3 c;
    if (uCompare == RTGI_VIEW_COMPARE_OFF) {
        c = display(texture(uImage, uv), uMode);
    } else if (uCompare == RTGI_VIEW_COMPARE_SPLIT) {
        c = uv.x < uSplit ? display(texture(uImage, uv), uMode) : display(texture(uReference, uv), uRefMode);
        if (abs(uv.x - uSplit) * float(textureSize(uImage, 0).x) < 0.75) c = vec3(1.0);  // the split line
    } else if (uCompare == RTGI_VIEW_COMPARE_REFERENCE) {
        c = display(texture(uReference, uv), uRefMode);
    } else if (uCompare == RTGI_VIEW_COMPARE_HEATMAP) {
        float d = abs(luminanceOf(texture(uImage, uv), uMode) - luminanceOf(texture(uReference, uv), uRefMode));
        c = heat(uHeatMax > 0.0 ? d / uHeatMax : 0.0);
    } else {  // side by side, each image at half size, centred vertically
        bool left = uv.x < 0.5;
        vec2 q = vec2(fract(uv.x * 2.0), (uv.y - 0.25) * 2.0);
        if (q.y < 0.0 || q.y > 1.0) c = vec3(0.0);
        else c = left ? display(texture(uImage, q), uMode) : display(texture(uReference, q), uRefMode);
    }
    outColor = vec4(clamp(c, 0.0, 1.0), 1.0);
}
