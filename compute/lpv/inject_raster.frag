// Writes the point's coefficients to the injected volume (0-2) and the
// accumulated volume (3-5); both blend additively.
#include "lpv/lpv_common.glsl"
#include "lib/lpv_shared.h"

layout(location = RTGI_LPV_VARY_R) flat in vec4 gR;
layout(location = RTGI_LPV_VARY_G) flat in vec4 gG;
layout(location = RTGI_LPV_VARY_B) flat in vec4 gB;
layout(location = RTGI_LPV_OUT_R) out vec4 outR;
layout(location = RTGI_LPV_OUT_G) out vec4 outG;
layout(location = RTGI_LPV_OUT_B) out vec4 outB;
layout(location = RTGI_LPV_OUT_ACCUM_R) out vec4 outAccumR;
layout(location = RTGI_LPV_OUT_ACCUM_G) out vec4 outAccumG;
layout(location = RTGI_LPV_OUT_ACCUM_B) out vec4 outAccumB;

void main() {
    outR = outAccumR = gR;
    outG = outAccumG = gG;
    outB = outAccumB = gB;
}
