// Light Propagation Volumes: constants, bindings and the uniform block
// shared by C++ (src/render/lpv) and GLSL (compute/lpv). C++ includes it
// through src/render/lpv/lpv_math.h, which static_asserts the sizes.
// Derivations of every constant: docs/lpv.md.
#ifndef RTGI_LPV_SHARED_H
#define RTGI_LPV_SHARED_H

// SH constants: lib/sh_shared.h (lib/sh.glsl in GLSL, lpv_math.h in C++).

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
#define RTGI_SSBO_LPV_STATS 3       // uint[2] dropped RSM texels: [0] this frame's injections, [1] the injection cache's
#define RTGI_SSBO_LPV_RSM_FACES 4   // LpvRsmFace[]: the local-light RSM faces of a batched injection (lpv/inject.comp)
#define RTGI_LPV_MAX_CASCADES 6      // lpv.cascades range 1..6
// Geometry accumulation channels: 4 SH of blocking, sum(A * albedo.rgb), sum(A), and with
// lpv.blocking=two-sided (RTGI_LPV_TWO_SIDED) sum(A / s^2 |n|) (xyz: axis blocking, docs/lpv.md "Leaks").
#define RTGI_LPV_GV_CHANNELS_ORIENTED 8
#define RTGI_LPV_GV_CHANNELS_TWO_SIDED 11
#ifdef RTGI_LPV_TWO_SIDED
#define RTGI_LPV_GV_CHANNELS RTGI_LPV_GV_CHANNELS_TWO_SIDED
#else
#define RTGI_LPV_GV_CHANNELS RTGI_LPV_GV_CHANNELS_ORIENTED
#endif
// Cascades (near.comp, apply.comp with RTGI_LPV_CASCADED): texture units, image units, uniform locations.
#define RTGI_LPV_TEX_SOURCE_R 0
#define RTGI_LPV_TEX_SOURCE_G 1
#define RTGI_LPV_TEX_SOURCE_B 2
#define RTGI_LPV_IMG_NEAR_R 0
#define RTGI_LPV_IMG_NEAR_G 1
#define RTGI_LPV_IMG_NEAR_B 2
#define RTGI_LPV_LOC_NEAR_FRACTION 0
#define RTGI_LPV_TEX_APPLY_NEAR_R 9     // apply: the cascade's near part (after the units 0-8 of the single volume)
#define RTGI_LPV_TEX_APPLY_NEAR_G 10
#define RTGI_LPV_TEX_APPLY_NEAR_B 11
#define RTGI_LPV_TEX_APPLY_RSM_FLUX 12   // apply: the RSM (self-illumination correction)
#define RTGI_LPV_TEX_APPLY_RSM_DEPTH 13
#define RTGI_LPV_IMG_APPLY_SUM_E 2      // apply: running sum over cascades of irradiance (rgb)
#define RTGI_LPV_IMG_APPLY_SUM_S 3      // apply: and of specular radiance (rgb)
#define RTGI_LPV_LOC_APPLY_LAST 0       // apply: 1 in the last (coarsest) cascade's dispatch
// Workgroup sizes (read back after linking; listed here so C++ and GLSL agree on tiling).
#define RTGI_LPV_LOCAL_2D 8
#define RTGI_LPV_LOCAL_3D 4
#define RTGI_LPV_LOCAL_REDUCE 16
#define RTGI_LPV_FACE_CELLS 32  // cells per workgroup of the per-face propagation kernel (x 6 faces x 3 colours)  // 2D tiles of the injection passes (shared-memory pre-reduction)

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
    ivec4 cascade;        // x: this volume's cascade index i, y: cascade count C, z: count dropped RSM texels,
                          // w: lpv.reemit=flow (side faces re-emit along their flow direction)
    vec4 cascadeParams;   // x: blend width of a cascade border in cells (apply); y, z: self-irradiance of a
                          // lit plane per unit exitance, all steps / near steps; w: lpv.self_correction
    vec4 cascadeOrigin[RTGI_LPV_MAX_CASCADES];  // every cascade: xyz min corner, w cell size (apply weights)
    ivec4 leak;           // leak remedies (docs/lpv.md, "Leaks"): x lpv.inject_side=front, y lpv.first_step=blocked,
                          // z lpv.blocking=two-sided, w lpv.reflect=source
};

// One local-light RSM face of a batched injection (lpv/inject.comp with RTGI_LPV_INJECT_FACES; std430):
// workgroup z of the dispatch reads entry RTGI_LPV_INJECT_LOC_FIRST_FACE + z (docs/lpv.md "Injection").
RTGI_LPV_STRUCT(LpvRsmFace) {
    mat4 invViewProj;  // RSM clip -> world of the view the face was drawn with
    ivec4 layer;       // x: the face's layer in its RSM array
};

#ifndef RTGI_GLSL
}  // namespace rtgi::gpu
#endif

// ---- slots of compute/lpv/ (docs/architecture.md, "Binding slots") ----
// RTGI_<FAMILY>[_<PASS>]_<TEX|IMG|LOC|SSBO>_<ROLE>; the pass appears only where the
// family's passes give the same role different slots.
// texture units (sampler bindings)
#define RTGI_LPV_TEX_LINEAR_DEPTH    0  // lpv/apply.comp lpv/inject_geometry.comp
#define RTGI_LPV_TEX_VIEW_NORMAL     1  // lpv/apply.comp lpv/inject_geometry.comp
#define RTGI_LPV_TEX_ALBEDO          2  // lpv/apply.comp lpv/inject_geometry.comp
#define RTGI_LPV_TEX_MATERIAL        3  // lpv/apply.comp lpv/inject_geometry.comp
#define RTGI_LPV_TEX_LIGHT_R         4  // lpv/apply.comp
#define RTGI_LPV_TEX_LIGHT_G         5  // lpv/apply.comp
#define RTGI_LPV_TEX_LIGHT_B         6  // lpv/apply.comp
#define RTGI_LPV_TEX_BRDF_LUT        7  // lpv/apply.comp
#define RTGI_LPV_TEX_DIRECTIONAL     8  // lpv/apply.comp
#define RTGI_LPV_TEX_FLUX            0  // lpv/inject.comp lpv/inject_raster.vert
#define RTGI_LPV_TEX_NORMAL          1  // lpv/inject.comp lpv/inject_raster.vert
#define RTGI_LPV_TEX_DEPTH           2  // lpv/inject.comp lpv/inject_raster.vert
#define RTGI_LPV_TEX_SRC_R           0  // lpv/propagate.comp lpv/propagate_raster.frag
#define RTGI_LPV_TEX_SRC_G           1  // lpv/propagate.comp lpv/propagate_raster.frag
#define RTGI_LPV_TEX_SRC_B           2  // lpv/propagate.comp lpv/propagate_raster.frag
#define RTGI_LPV_TEX_GEOMETRY        3  // lpv/propagate.comp lpv/propagate_raster.frag
#define RTGI_LPV_TEX_GEOMETRY_ALBEDO 4  // lpv/propagate.comp lpv/propagate_raster.frag
#define RTGI_LPV_SLICE_TEX_A         0  // lpv/slice.comp
#define RTGI_LPV_SLICE_TEX_B         1  // lpv/slice.comp
#define RTGI_LPV_SLICE_TEX_C         2  // lpv/slice.comp
#define RTGI_LPV_TEX_CUR_R           0  // lpv/temporal.comp
#define RTGI_LPV_TEX_CUR_G           1  // lpv/temporal.comp
#define RTGI_LPV_TEX_CUR_B           2  // lpv/temporal.comp
#define RTGI_LPV_TEX_PREV_R          3  // lpv/temporal.comp
#define RTGI_LPV_TEX_PREV_G          4  // lpv/temporal.comp
#define RTGI_LPV_TEX_PREV_B          5  // lpv/temporal.comp
// image units
#define RTGI_LPV_IMG_INDIRECT                       0  // lpv/apply.comp
#define RTGI_LPV_IMG_SPECULAR                       1  // lpv/apply.comp
#define RTGI_LPV_INJECT_IMG_INJECT_R                0  // lpv/inject.comp
#define RTGI_LPV_INJECT_IMG_INJECT_G                1  // lpv/inject.comp
#define RTGI_LPV_INJECT_IMG_INJECT_B                2  // lpv/inject.comp
#define RTGI_LPV_INJECT_LOC_FIRST_FACE   0  // lpv/inject.comp (RTGI_LPV_INJECT_FACES): first LpvRsmFace entry
#define RTGI_LPV_INJECT_LOC_STATS_SLOT   1  // lpv/inject.comp (RTGI_LPV_INJECT_FACES): dropped-texel counter 0 or 1
#define RTGI_LPV_INJECT_RASTER_LOC_LAYER 0  // lpv/inject_raster.vert (RTGI_LPV_RSM_ARRAY): layer of the face
#define RTGI_LPV_INJECT_RASTER_LOC_INV_VIEW_PROJ 1  // and its RSM clip -> world (mat4: locations 1-4)
#define RTGI_LPV_INJECT_GEOMETRY_IMG_GEOMETRY_ACCUM 0  // lpv/inject_geometry.comp
// The sun RSM's textures in lpv/inject_geometry.comp: beside the G-buffer's (RTGI_LPV_TEX_LINEAR_DEPTH ..
// RTGI_LPV_TEX_MATERIAL), since one dispatch reads both sources.
#define RTGI_LPV_INJECT_GEOMETRY_TEX_RSM_FLUX   4
#define RTGI_LPV_INJECT_GEOMETRY_TEX_RSM_NORMAL 5
#define RTGI_LPV_INJECT_GEOMETRY_TEX_RSM_DEPTH  6
// Samples per invocation of lpv/inject_geometry.comp, in x and y (summed in registers while in one cell).
#define RTGI_LPV_GV_BLOCK 2
#define RTGI_LPV_IMG_GEOMETRY                       0  // lpv/pack.comp
#define RTGI_LPV_IMG_VOL_R                          0  // lpv/pack.comp
#define RTGI_LPV_IMG_GEOMETRY_ALBEDO                1  // lpv/pack.comp
#define RTGI_LPV_IMG_VOL_G                          1  // lpv/pack.comp
#define RTGI_LPV_IMG_VOL_B                          2  // lpv/pack.comp
#define RTGI_LPV_PACK_IMG_GEOMETRY_ACCUM            2  // lpv/pack.comp
#define RTGI_LPV_PACK_IMG_INJECT_R                  3  // lpv/pack.comp
#define RTGI_LPV_PACK_IMG_INJECT_G                  4  // lpv/pack.comp
#define RTGI_LPV_PACK_IMG_INJECT_B                  5  // lpv/pack.comp
#define RTGI_LPV_IMG_DST_R                          0  // lpv/propagate.comp
#define RTGI_LPV_IMG_DST_G                          1  // lpv/propagate.comp
#define RTGI_LPV_IMG_DST_B                          2  // lpv/propagate.comp
#define RTGI_LPV_IMG_ACCUM_R                        3  // lpv/propagate.comp
#define RTGI_LPV_IMG_ACCUM_G                        4  // lpv/propagate.comp
#define RTGI_LPV_IMG_ACCUM_B                        5  // lpv/propagate.comp
#define RTGI_LPV_IMG_SLICE                          0  // lpv/slice.comp
#define RTGI_LPV_IMG_OUT_R                          0  // lpv/temporal.comp
#define RTGI_LPV_IMG_OUT_G                          1  // lpv/temporal.comp
#define RTGI_LPV_IMG_OUT_B                          2  // lpv/temporal.comp
// uniform locations
#define RTGI_LPV_LOC_ITERATION 0  // lpv/propagate.comp lpv/propagate_raster.frag lpv/propagate_fused.comp
#define RTGI_LPV_LOC_FUSED_COUNT 1  // lpv/propagate_fused.comp: iterations in the dispatch
#define RTGI_LPV_LOC_Z         0  // lpv/slice.comp
// lpv.sh_order=2 (RTGI_LPV_SH2; docs/lpv.md "Second-order SH"): coefficients 4-7 of each colour
// in an RGBA volume ("hi" r, g, b) and coefficient 8 of r, g, b in a fourth ("last", .rgb);
// each pass binds them after its band-1 slots. Injection accumulation: injectHi r32f (4X, Y, Z)
// per colour (coefficient 4 + k at 4x + k), injectLast r32f (3X, Y, Z) (colour c at 3x + c).
#define RTGI_LPV_INJECT_IMG_INJECT_HI_R   3  // lpv/inject.comp
#define RTGI_LPV_INJECT_IMG_INJECT_HI_G   4
#define RTGI_LPV_INJECT_IMG_INJECT_HI_B   5
#define RTGI_LPV_INJECT_IMG_INJECT_LAST   6
#define RTGI_LPV_PACK_IMG_INJECT_HI_R     0  // lpv/pack.comp with RTGI_LPV_PACK_HI
#define RTGI_LPV_PACK_IMG_INJECT_HI_G     1
#define RTGI_LPV_PACK_IMG_INJECT_HI_B     2
#define RTGI_LPV_PACK_IMG_INJECT_LAST     3
#define RTGI_LPV_PACK_IMG_VOL_HI_R        4
#define RTGI_LPV_PACK_IMG_VOL_HI_G        5
#define RTGI_LPV_PACK_IMG_VOL_HI_B        6
#define RTGI_LPV_PACK_IMG_VOL_LAST        7
#define RTGI_LPV_TEX_SRC_HI_R             5  // lpv/propagate.comp (after geometry 3, 4)
#define RTGI_LPV_TEX_SRC_HI_G             6
#define RTGI_LPV_TEX_SRC_HI_B             7
#define RTGI_LPV_TEX_SRC_LAST             8
#define RTGI_LPV_IMG_DST_HI_R             3  // lpv/propagate.comp (band 2 writes no accum: lpv/accumulate.comp)
#define RTGI_LPV_IMG_DST_HI_G             4
#define RTGI_LPV_IMG_DST_HI_B             5
#define RTGI_LPV_IMG_DST_LAST             6
#define RTGI_LPV_ACC_TEX_STEP_R           0  // lpv/accumulate.comp: accum += step k
#define RTGI_LPV_ACC_TEX_STEP_G           1
#define RTGI_LPV_ACC_TEX_STEP_B           2
#define RTGI_LPV_ACC_TEX_STEP_HI_R        3
#define RTGI_LPV_ACC_TEX_STEP_HI_G        4
#define RTGI_LPV_ACC_TEX_STEP_HI_B        5
#define RTGI_LPV_ACC_TEX_STEP_LAST        6
#define RTGI_LPV_ACC_IMG_ACCUM_R          0
#define RTGI_LPV_ACC_IMG_ACCUM_G          1
#define RTGI_LPV_ACC_IMG_ACCUM_B          2
#define RTGI_LPV_ACC_IMG_ACCUM_HI_R       3
#define RTGI_LPV_ACC_IMG_ACCUM_HI_G       4
#define RTGI_LPV_ACC_IMG_ACCUM_HI_B       5
#define RTGI_LPV_ACC_IMG_ACCUM_LAST       6
#define RTGI_LPV_TEX_SOURCE_HI_R          3  // lpv/near.comp
#define RTGI_LPV_TEX_SOURCE_HI_G          4
#define RTGI_LPV_TEX_SOURCE_HI_B          5
#define RTGI_LPV_TEX_SOURCE_LAST          6
#define RTGI_LPV_IMG_NEAR_HI_R            3
#define RTGI_LPV_IMG_NEAR_HI_G            4
#define RTGI_LPV_IMG_NEAR_HI_B            5
#define RTGI_LPV_IMG_NEAR_LAST            6
#define RTGI_LPV_TEX_LIGHT_HI_R          14  // lpv/apply.comp (after the RSM at 13)
#define RTGI_LPV_TEX_LIGHT_HI_G          15
#define RTGI_LPV_TEX_LIGHT_HI_B          16
#define RTGI_LPV_TEX_LIGHT_LAST          17
#define RTGI_LPV_TEX_APPLY_NEAR_HI_R     18
#define RTGI_LPV_TEX_APPLY_NEAR_HI_G     19
#define RTGI_LPV_TEX_APPLY_NEAR_HI_B     20
#define RTGI_LPV_TEX_APPLY_NEAR_LAST     21
#define RTGI_LPV_TEX_APPLY_GEOMETRY      22  // lpv/apply.comp with RTGI_LPV_LOOKUP_GEOMETRY: the cascade's geometry volume
#define RTGI_LPV_TEX_APPLY_GEOMETRY_AXES 23  // and its two-sided axis blocking
#define RTGI_LPV_TEX_GEOMETRY_AXES        9  // lpv/propagate.comp lpv/propagate_raster.frag (after band 2's 5-8)
#define RTGI_LPV_IMG_GEOMETRY_AXES        3  // lpv/pack.comp (RTGI_LPV_PACK_GEOMETRY)
#define RTGI_LPV_TEX_CUR_HI_R             6  // lpv/temporal.comp (after prev 3-5)
#define RTGI_LPV_TEX_CUR_HI_G             7
#define RTGI_LPV_TEX_CUR_HI_B             8
#define RTGI_LPV_TEX_CUR_LAST             9
#define RTGI_LPV_TEX_PREV_HI_R           10
#define RTGI_LPV_TEX_PREV_HI_G           11
#define RTGI_LPV_TEX_PREV_HI_B           12
#define RTGI_LPV_TEX_PREV_LAST           13
#define RTGI_LPV_IMG_OUT_HI_R             3
#define RTGI_LPV_IMG_OUT_HI_G             4
#define RTGI_LPV_IMG_OUT_HI_B             5
#define RTGI_LPV_IMG_OUT_LAST             6
#define RTGI_LPV_PROBE_IMG_ACCUM_HI_R     3  // lpv/probe.comp
#define RTGI_LPV_PROBE_IMG_ACCUM_HI_G     4
#define RTGI_LPV_PROBE_IMG_ACCUM_HI_B     5
#define RTGI_LPV_PROBE_IMG_ACCUM_LAST     6
// lpv/probe.comp (lpv.source=probe, docs/lpv.md "Stage attribution"); BVH and scene
// buffers at their bvh_shared.h / shared.h bindings.
#define RTGI_LPV_PROBE_IMG_ACCUM_R 0
#define RTGI_LPV_PROBE_IMG_ACCUM_G 1
#define RTGI_LPV_PROBE_IMG_ACCUM_B 2
#define RTGI_LPV_PROBE_LOC_PARAMS  0  // uvec4: directions per cell, bounces, seed, first z slice
// After scene.vert's mat4 at RTGI_RASTER_LOC_LIGHT_VIEW_PROJ (locations 0-3) of the same program.
#define RTGI_LPV_RSM_LOC_LIGHT 4  // lpv/rsm.frag (RTGI_RSM_LOCAL): vec4[4] GpuLight, locations 4-7
#define RTGI_LPV_RSM_LOC_FACE  8  // lpv/rsm.frag (RTGI_RSM_LOCAL): vec2 tan(half fov), RSM side
// stage interfaces of the seed's raster baseline (varyings and colour outputs)
#define RTGI_LPV_VARY_CELL 0    // inject_raster.vert -> .geom
#define RTGI_LPV_VARY_R 1
#define RTGI_LPV_VARY_G 2
#define RTGI_LPV_VARY_B 3
#define RTGI_LPV_VARY_LAYER 0   // propagate_raster.vert -> .geom
#define RTGI_LPV_OUT_R 0        // colour attachments of inject/propagate_raster.frag
#define RTGI_LPV_OUT_G 1
#define RTGI_LPV_OUT_B 2
#define RTGI_LPV_OUT_ACCUM_R 3
#define RTGI_LPV_OUT_ACCUM_G 4
#define RTGI_LPV_OUT_ACCUM_B 5

// lpv.lookup=visibility (docs/lpv.md, "Visibility moments"): per-cell distance moments.
#define RTGI_LPV_VIS_RES 6                  // N: each cell's octahedral map is N x N directions
#define RTGI_LPV_VIS_SUBSAMPLES 2           // rays per map texel: S x S strata
#define RTGI_LPV_VIS_MAX_DISTANCE 2.0       // cells: longer distances are stored as this (lookups reach sqrt(3))
#define RTGI_LPV_VIS_MIN_VARIANCE 0.00390625  // cells^2: (1/16 cell)^2, floor of the Chebyshev variance
#define RTGI_LPV_TEX_APPLY_VISIBILITY    24  // lpv/apply.comp with RTGI_LPV_LOOKUP_VISIBILITY: the cascade's moments
#define RTGI_LPV_VIS_IMG_MOMENTS          0  // lpv/visibility.comp (BVH and scene buffers at their bvh_shared.h bindings)
#define RTGI_LPV_VIS_IMG_SKY              1  // lpv/visibility.comp with RTGI_LPV_VIS_SKY: sky visibility SH per cell
#define RTGI_LPV_SKY_STRATA               8  // lpv.sky=visibility: M x M rays per cell
#define RTGI_LPV_TEX_PROPAGATE_VISIBILITY 10  // lpv/propagate.comp with RTGI_LPV_PROPAGATE_VISIBILITY (after axes 9): face openness
// lpv.propagate_cascades=joint (lpv/propagate.comp with RTGI_LPV_JOINT): the second cascade's geometry volume
// (the first's at RTGI_LPV_TEX_GEOMETRY, _ALBEDO, _AXES); near.comp's z offset into the stacked sum.
#define RTGI_LPV_TEX_JOINT_GEOMETRY_1        11
#define RTGI_LPV_TEX_JOINT_GEOMETRY_ALBEDO_1 12
#define RTGI_LPV_TEX_JOINT_GEOMETRY_AXES_1   13
#define RTGI_LPV_LOC_NEAR_OFFSET 1  // lpv/near.comp: z of the cascade's slab in the source (0 unless stacked)
// lpv.blocking=visibility (docs/lpv.md, "Face openness"): per cell and axis, the open fraction of the
// slab between its centre and the next cell's centre, from F x F parallel rays.
#define RTGI_LPV_VIS_FACE_RAYS            4  // F
#define RTGI_LPV_VIS_IMG_FACES            2  // lpv/visibility.comp with RTGI_LPV_VIS_FACES: RGBA8, (+x, +y, +z, 0)
#define RTGI_LPV_TEX_APPLY_SKY           25  // lpv/apply.comp with RTGI_LPV_SKY: the cascade's sky visibility SH
// lpv.apply_resolution=half (docs/lpv.md, "Half-resolution apply")
#define RTGI_LPV_IMG_APPLY_LOW_GEOMETRY   4  // lpv/apply.comp with RTGI_LPV_APPLY_HALF: depth (r), view normal (gba)
#define RTGI_LPV_UPSAMPLE_TEX_LOW_INDIRECT 4  // lpv/upsample.comp (G-buffer and BRDF LUT at the apply's units)
#define RTGI_LPV_UPSAMPLE_TEX_LOW_SPECULAR 5  // lpv/upsample.comp
#define RTGI_LPV_UPSAMPLE_TEX_LOW_GEOMETRY 6  // lpv/upsample.comp
// lpv.sky_bounce (docs/lpv.md, "Sky bounce"): lpv/inject.comp with RTGI_LPV_INJECT_SKY reads the G-buffer at
// RTGI_LPV_TEX_LINEAR_DEPTH .. _MATERIAL and the cascade's sky visibility and moments here.
#define RTGI_LPV_TEX_INJECT_SKY            4
#define RTGI_LPV_TEX_INJECT_MOMENTS        5

#endif
