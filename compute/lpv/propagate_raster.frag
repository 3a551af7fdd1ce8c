// One propagation iteration per fragment (= cell): the gather of
// lpv/propagate.glsl; outputs 0-2 write volume k, 3-5 add into the
// accumulated volume through additive blending.
#include "lpv/propagate.glsl"
#include "lib/lpv_shared.h"

layout(binding = RTGI_LPV_TEX_SRC_R) uniform sampler3D uSrcR;
layout(binding = RTGI_LPV_TEX_SRC_G) uniform sampler3D uSrcG;
layout(binding = RTGI_LPV_TEX_SRC_B) uniform sampler3D uSrcB;
layout(binding = RTGI_LPV_TEX_GEOMETRY) uniform sampler3D uGeometry;
layout(binding = RTGI_LPV_TEX_GEOMETRY_ALBEDO) uniform sampler3D uGeometryAlbedo;
layout(binding = RTGI_LPV_TEX_GEOMETRY_AXES) uniform sampler3D uGeometryAxes;
layout(location = RTGI_LPV_LOC_ITERATION) uniform int uIteration;

layout(location = RTGI_LPV_OUT_R) out vec4 outR;
layout(location = RTGI_LPV_OUT_G) out vec4 outG;
layout(location = RTGI_LPV_OUT_B) out vec4 outB;
layout(location = RTGI_LPV_OUT_ACCUM_R) out vec4 outAccumR;
layout(location = RTGI_LPV_OUT_ACCUM_G) out vec4 outAccumG;
layout(location = RTGI_LPV_OUT_ACCUM_B) out vec4 outAccumB;

void main() {
    ivec3 c = ivec3(ivec2(gl_FragCoord.xy), gl_Layer);
    LpvRgb v = lpvGather(c, uIteration, uSrcR, uSrcG, uSrcB, uGeometry, uGeometryAlbedo, uGeometryAxes);
    outR = outAccumR = lpvStorable(v.r);
    outG = outAccumG = lpvStorable(v.g);
    outB = outAccumB = lpvStorable(v.b);
}
