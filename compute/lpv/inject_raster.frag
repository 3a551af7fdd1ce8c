// Writes the point's coefficients to the injected volume (0-2) and the
// accumulated volume (3-5); both blend additively.
#include "lpv/lpv_common.glsl"

layout(location = 1) flat in vec4 gR;
layout(location = 2) flat in vec4 gG;
layout(location = 3) flat in vec4 gB;
layout(location = 0) out vec4 outR;
layout(location = 1) out vec4 outG;
layout(location = 2) out vec4 outB;
layout(location = 3) out vec4 outAccumR;
layout(location = 4) out vec4 outAccumG;
layout(location = 5) out vec4 outAccumB;

void main() {
    outR = outAccumR = gR;
    outG = outAccumG = gG;
    outB = outAccumB = gB;
}
