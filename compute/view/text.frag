#include "lib/view_shared.h"
layout(location = RTGI_VIEW_LOC_COLOR) uniform vec4 uColor;
layout(location = 0) out vec4 outColor;

void main() { outColor = uColor; }
