// Light Propagation Volumes: constants, bindings and the uniform block
// shared by C++ (src/render/lpv) and GLSL (compute/lpv). C++ includes it
// through src/render/lpv/lpv_math.h, which static_asserts the sizes.
// Derivations of every constant: docs/lpv.md.
#ifndef RTGI_LPV_SHARED_H
#define RTGI_LPV_SHARED_H

// ---- real SH bands 0-1, order (Y00, Y1-1, Y10, Y11), SPEC 3 / seed eq. 10 ----
#define RTGI_SH_Y00 0.28209479177387814    // 1 / (2 sqrt(pi))
#define RTGI_SH_Y1 0.48860251190291992     // sqrt(3) / (2 sqrt(pi))
#define RTGI_SH_COS_C0 0.88622692545275801  // sqrt(pi) / 2: clamped cosine, band 0 [KD10]
#define RTGI_SH_COS_C1 1.0233267079464885   // sqrt(pi / 3): clamped cosine, band 1

// ---- propagation faces (unit cells; a neighbour one cell behind the destination) ----
// Front face (square at distance 1.5): 4 asin(1/10). Side faces: (2 pi / 3 - front) / 4
// = pi/6 - asin(1/10), so 6 neighbours x 5 faces cover exactly 4 pi.
#define RTGI_LPV_FRONT_SOLID_ANGLE 0.40066968464623920
#define RTGI_LPV_SIDE_SOLID_ANGLE 0.42343135443673900
// Mean direction over a side face's solid angle, as tangent (towards the
// face) and propagation-axis components (numerical integral, docs/lpv.md).
#define RTGI_LPV_SIDE_DIR_T 0.5440142
#define RTGI_LPV_SIDE_DIR_D 0.8390760

// ---- bindings ----
#define RTGI_UBO_LPV 1              // LpvUniforms
#define RTGI_SSBO_LPV_STATS 3       // uint dropped RSM texels
#define RTGI_RSM_LOC_LIGHT 1        // lpv/rsm.frag (RTGI_RSM_LOCAL): vec4[4] GpuLight, locations 1-4
#define RTGI_RSM_LOC_FACE 5         // lpv/rsm.frag (RTGI_RSM_LOCAL): vec2 tan(half fov), RSM side
#define RTGI_LPV_GV_CHANNELS 8      // geometry accumulation: 4 SH of blocking, sum(A * albedo.rgb), sum(A)
// Workgroup sizes (read back after linking; listed here so C++ and GLSL agree on tiling).
#define RTGI_LPV_LOCAL_2D 8
#define RTGI_LPV_LOCAL_3D 4
#define RTGI_LPV_LOCAL_REDUCE 16  // 2D tiles of the injection passes (shared-memory pre-reduction)

#ifdef RTGI_GLSL
#define RTGI_LPV_STRUCT(name) struct name
#else
#define RTGI_LPV_STRUCT(name) struct alignas(16) name
namespace rtgi::gpu {
#endif

// std140, bound at RTGI_UBO_LPV by every LPV pass; made by makeLpvUniforms().
RTGI_LPV_STRUCT(LpvUniforms) {
    mat4 rsmViewProj;     // world -> RSM clip (orthographic, fitted to the grid box)
    mat4 rsmInvViewProj;  // RSM clip -> world
    vec4 origin;          // xyz: world position of the grid's min corner; w: cell size s
    ivec4 grid;           // xyz: cells; w: RSM side R
    vec4 rsm;             // x: A_texel (world area per RSM texel); y: 1/s^2; z: lpv.strength; w: min cos for areas
    ivec4 flags;          // x: occlusion, y: bounce, z: energy conserving, w: specular
    ivec4 temporalShift;  // xyz: cell index shift to the previous frame's grid; w: history valid
    vec4 temporal;        // x: blend weight of the previous volume
};

#ifndef RTGI_GLSL
}  // namespace rtgi::gpu
#endif
#endif
