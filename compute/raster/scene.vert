// Vertex stage of every scene rasterization (G-buffer, shadow map, RSM).
// RTGI_VP_UNIFORM selects a light's view-projection instead of the camera's.
#include "lib/common.glsl"
#include "lib/raster_shared.h"

layout(location = RTGI_ATTR_POSITION) in vec3 inPosition;
layout(location = RTGI_ATTR_NORMAL) in vec3 inNormal;
layout(location = RTGI_ATTR_UV) in vec2 inUv;
layout(location = RTGI_ATTR_MATERIAL) in uint inMaterial;
layout(location = RTGI_ATTR_PREV_POSITION) in vec3 inPrevPosition;  // = inPosition unless the object moved

layout(location = RTGI_RASTER_LOC_LIGHT_VIEW_PROJ) uniform mat4 uLightViewProj;  // used by shadow/RSM variants

layout(location = RTGI_RASTER_VARY_WORLD_POS) out vec3 vWorldPos;
layout(location = RTGI_RASTER_VARY_NORMAL) out vec3 vNormal;
layout(location = RTGI_RASTER_VARY_UV) out vec2 vUv;
layout(location = RTGI_RASTER_VARY_MATERIAL) flat out uint vMaterial;
layout(location = RTGI_RASTER_VARY_CUR_CLIP) out vec4 vCurClip;
layout(location = RTGI_RASTER_VARY_PREV_CLIP) out vec4 vPrevClip;

void main() {
    vWorldPos = inPosition;  // the scene is flattened to world space
    vNormal = inNormal;
    vUv = inUv;
    vMaterial = inMaterial;
#ifdef RTGI_LIGHT_VIEW
    gl_Position = uLightViewProj * vec4(inPosition, 1.0);
    vCurClip = gl_Position;
    vPrevClip = gl_Position;
#else
    gl_Position = frame.viewProj * vec4(inPosition, 1.0);
    vCurClip = gl_Position;
    vPrevClip = frame.prevViewProj * vec4(inPrevPosition, 1.0);  // camera and object motion
#endif
}
