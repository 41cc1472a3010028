// constants.h — binding slots and work-group sizes shared by the C++ host code
// and the shaders, so a slot is named in one place only.
#ifndef FT_CONSTANTS_H
#define FT_CONSTANTS_H
#include "prelude.h"

// Uniform-buffer bindings (std140).
#define FT_UBO_YARN_PARAMS 0
#define FT_UBO_VIEW_PARAMS 1
#define FT_UBO_DISPATCH 2
#define FT_UBO_KNIT_PARAMS 3
#define FT_UBO_SELF_SHADOW 5       // SelfShadowParams + YarnDensityParams (common/self_shadow.h)
#define FT_UBO_AMBIENT_OCCLUSION 6  // AmbientOcclusionParams (common/ambient_occlusion.h)

// Shader-storage bindings (std430).
#define FT_SSBO_CONTROL_POINTS 0
#define FT_SSBO_CURVES 1
#define FT_SSBO_SEGMENTS 2
#define FT_SSBO_FRAMES 3
#define FT_SSBO_FIBER_TABLE 4
#define FT_SSBO_DECISIONS 5
#define FT_SSBO_OFFSETS 6
#define FT_SSBO_VERTICES 7
#define FT_SSBO_INDICES 8
#define FT_SSBO_DRAW_COMMAND 9
#define FT_SSBO_SEGMENT_LIST 10
#define FT_SSBO_LAYOUT_PROBE 11
#define FT_SSBO_SAMPLES 12
#define FT_SSBO_STRIP_OWNERS 13
#define FT_SSBO_SAMPLE_OWNERS 14
#define FT_SSBO_KNIT_STITCHES 15
#define FT_SSBO_KNIT_POINTS 16
#define FT_SSBO_KNIT_ENERGY 17
#define FT_SSBO_KNIT_YARN_LIST 18
#define FT_SSBO_KNIT_VERTICES 19
#define FT_SSBO_FRAME_CARRY 20
#define FT_SSBO_BCSDF_INPUT 22     // BCSDF evaluation requests (harness)
#define FT_SSBO_BCSDF_OUTPUT 23    // their results

// Self-shadow 3D texture (common/self_shadow.h, gpu/self_shadow_gpu.h): SSBO 24–27.
#define FT_SSBO_SELF_SHADOW_TEXTURE 24   // float[N_s][N_v][N_u]: D, the baked texture
#define FT_SSBO_SELF_SHADOW_DENSITY 25   // float[N_s][N_v][N_u]: ρ at the texel centres (grid variant)
#define FT_SSBO_SELF_SHADOW_REQUESTS 26  // lookup requests (harness)
#define FT_SSBO_SELF_SHADOW_RESULTS 27   // their results

// Ambient occlusion (common/ambient_occlusion.h, gpu/ambient_occlusion_gpu.h):
// slots 28–31 and UBO 6 are this group's.
#define FT_SSBO_AO_POINTS 28       // vec4 requests: (x, y, ψ) per point; two per lookup request (gpu/ambient_occlusion_gpu.h)
#define FT_SSBO_AO_OUTPUT 29       // float results (texels or one per request)
#define FT_SSBO_AO_DENSITY 30      // float[m·m]: the density grid of the paper-faithful bake
#define FT_SSBO_AO_TEXTURE 31      // float[n·n]: an AO texture to look up

// Core-fiber texture bake (common/core_texture.h, gpu/core_texture_gpu.h;
// 000 §3.2): SSBO 32–35 and UBO 7 are this group's (others use 24–31, UBO 5–6).
#define FT_UBO_CORE_TEXTURE 7      // CoreTextureParams
#define FT_SSBO_CORE_FIBERS 32     // vec4[coreFibers]: ftCoreFiberRow
#define FT_SSBO_CORE_TEX0 33       // vec4[columns·height]: (h, n_u, n_v, 0), row-major
#define FT_SSBO_CORE_TEX1 34       // vec4[columns·height]: (t_u, t_v, t_w, 0)

// Yarn shadow map (common/shadow_map.h, 000 §4.1; FiberRenderer's depth pass
// and the frame's lookup): UBO 8 and SSBO 36–39 are this group's.
#define FT_UBO_SHADOW_MAP 8        // ShadowMapParams
#define FT_SSBO_SHADOW_MAP 36      // float[lights][N][N]: the stored depth in [0, 1], rows bottom-up

// Occlusion culling of the shaded frame (common/occlusion_cull.h,
// FiberRenderer::draw): the occluder pass's depth, its max-depth pyramid.
#define FT_UBO_OCCLUSION 9         // OcclusionPyramid
#define FT_SSBO_OCCLUSION 37       // float[ftOcclusionTexelCount]: max window depth per texel, all levels
#define FT_TEX_OCCLUDER_DEPTH 0    // sampler2DMS: the occluder pass's depth (pyramid level 0 reads it)
#define FT_WG_OCCLUSION 8          // 8 × 8 texels per work group
// Harness read-back of a multisampled depth texture, sample by sample, in a
// program of its own (like the layout probe, whose slot it shares).
#define FT_SSBO_SAMPLE_DEPTHS FT_SSBO_LAYOUT_PROBE
// Two-pass culling (common/occlusion_cull.h ftLineKey): one bit per line key,
// the lines that won a sample of the last frame (read by the visibility
// pass's geometry stage) or of this one (set by the compaction). Bound only
// around those two, which read nothing else there, so it shares the probe's
// slot too (no slot below llvmpipe's 80 is free).
#define FT_SSBO_VISIBLE_LINES FT_SSBO_LAYOUT_PROBE
// ... and on the compute path the index buffer of one of its two draws
// (two_pass_lines.comp.glsl), written by a program of its own that reads no
// strip owners (generation's pass 5), whose slot it shares.
#define FT_SSBO_TWO_PASS_INDICES FT_SSBO_STRIP_OWNERS
#define FT_WG_TWO_PASS 64

// Deferred shading of the frame (FiberRenderer::drawDeferred, docs/shaded-frame.md):
// the visibility pass's hit records (FT_VISIBILITY_TARGETS 4× multisampled
// RGBA32F textures, read at texture units 1–5) and the list of distinct hits
// to shade (SSBO 73, the last free slot below llvmpipe's 80).
#define FT_VISIBILITY_TARGETS 5    // vec4s per hit record (fiber_strip.frag.glsl ftPackHit)
#define FT_DEFERRED_SAMPLES 4      // the shaded target's samples per pixel
#define FT_TEX_HIT_RECORD0 1       // sampler2DMS: record k at unit FT_TEX_HIT_RECORD0 + k
#define FT_TEX_HIT_LINE (FT_TEX_HIT_RECORD0 + FT_VISIBILITY_TARGETS)  // usampler2DMS: ftLineKey + 1 of the hit, 0: none
#define FT_SSBO_DEFERRED_LIST 73   // uvec4 header (x: entries, y: tiles), uvec4 (x, y, sample, mask) per entry, then the tiles
#define FT_IMAGE_SHADED 0          // image2DMS rgba32f: the shaded target's colour, which the shading kernel writes per sample
#define FT_DEFERRED_TILE 8u        // the compaction's tiles: 8 × 8 pixels, one work group each
#define FT_WG_DEFERRED_COMPACT (FT_DEFERRED_TILE * FT_DEFERRED_TILE)
#define FT_WG_DEFERRED_TILES 64    // tiles per work group of the tile listing
#define FT_WG_DEFERRED_SHADE 64

// Soft yarn shadows by PCSS (common/pcss.h, 001 §4.5 eq. 17, docs/soft-shadows.md;
// FiberRenderer's lobe maps and the frame's lookup): UBO 17, SSBO 70–73 are this group's.
#define FT_UBO_PCSS 17             // PcssParams
#define FT_SSBO_PCSS_LOBE_MAPS 70  // float[lobe layers][N][N]: the SRBF lobes' shadow maps, stored depth in [0, 1]
#define FT_SSBO_PCSS_REQUESTS 71   // vec4 (p, light or lobe index) lookup requests (harness)
#define FT_SSBO_PCSS_RESULTS 72    // float T̃ per request
#define FT_WG_PCSS 64

// Shading inputs (scene/shading_inputs.h): everything a shaded frame reads
// besides the fibers, bound together by gpu/fiber_renderer.cpp. A new
// precomputed input takes its slot here.
#define FT_UBO_SHADING 4           // ShadingParams (common/fiber_shading.h)
#define FT_SSBO_AMBIENT_TABLE 21   // vec4[FT_AMBIENT_TABLE_SIZE]: rgb A(θ_k) (common/bcsdf.h)
#define FT_SSBO_LOBE_NORM_TABLE 38 // vec2[FT_LOBE_NORM_TABLE_SIZE]: (Z_R, Z_TT) at ftLobeNormTexelAngle (common/bcsdf.h)
// Dual scattering in the frame (FT_APPEARANCE_DUAL_SCATTERING): SSBO 56–60
// (51–55 are reserved for the SRBF work). The frame's ξ layout uses the ξ
// group's UBO slot FT_UBO_XI, bound by FiberRenderer before each shaded draw
// (the harness evaluator binds its own before each dispatch).
#define FT_SSBO_FRAME_DS_TABLE 56  // vec4[FT_DS_ROWS·FT_DS_TABLE_SIZE]: the DS table (common/dual_scattering.h)
#define FT_SSBO_FRAME_XI_M 57      // vec4[N_θ][N_v][N_u]: rgb ξ_M, scaled layout (common/ds_correction.h)
#define FT_SSBO_FRAME_XI_N 58      // vec4[N_φ][N_v][N_u]: rgb ξ_N
#define FT_SSBO_FRAME_PSI_M 59     // vec4[N_θ][N_v][N_u]: rgb Ψ_{G,M}^Fiber
#define FT_SSBO_FRAME_PSI_N 60     // vec4[N_φ][N_v][N_u]: rgb Ψ_{G,N}^Fiber
// SRBF environment lighting in the frame (FT_APPEARANCE_ENVIRONMENT, 001 §4.5
// eq. 16, common/srbf_lighting.h): UBO 14–15 and SSBO 61–64 are this group's.
#define FT_UBO_FRAME_SRBF 14        // SrbfEnvironment, then ivec4 the I_M table's dimensions
#define FT_SSBO_FRAME_SRBF_TABLE 61 // vec4[ftSrbfTableSize]: rgb I(θ_o, θ_j, Δφ, λ) of the frame's fabric

// Dual-scattering correction ξ and fiber-level shadowing (common/ds_correction.h,
// 001 §4.3): UBO 12 and SSBO 45–50 are this group's.
#define FT_UBO_XI 12               // DsCorrectionLayout
#define FT_SSBO_XI_M 45            // vec4[N_θ][N_v][N_u]: rgb ξ_M
#define FT_SSBO_XI_N 46            // vec4[N_φ][N_v][N_u]: rgb ξ_N
#define FT_SSBO_XI_PSI_M 47        // vec4[N_θ][N_v][N_u]: rgb Ψ_{G,M}^Fiber
#define FT_SSBO_XI_PSI_N 48        // vec4[N_φ][N_v][N_u]: rgb Ψ_{G,N}^Fiber
#define FT_SSBO_XI_REQUESTS 49     // vec4 (u, v, θ, φ) per lookup request (harness)
#define FT_SSBO_XI_RESULTS 50      // vec4 rgb ξ_M ξ_N Ψ_M Ψ_N per request

// Dual scattering (common/dual_scattering.h, gpu/dual_scattering_gpu.h; Zinke
// et al. 2008 as 001 §4.1 uses it): SSBO 42–44 are this group's.
#define FT_SSBO_DS_INPUT 42        // FabricParams, then vec4 requests (evaluation: 2 per request)
#define FT_SSBO_DS_TABLE 43        // vec4[FT_DS_ROWS·N]: the table, texel-major (common/dual_scattering.h)
#define FT_SSBO_DS_OUTPUT 44       // bake: vec4[(FT_DS_ROWS + 4)·N]; evaluation: vec4[6] per request

// SRBF environment lighting (common/srbf.h, common/srbf_bcsdf.h; 001 §4.5):
// UBO 13 and SSBO 51–55 are this group's (gpu/srbf_fit_gpu.h, gpu/srbf_table_gpu.h).
#define FT_UBO_SRBF 13               // SrbfEnvironment: 16 lobes + the DC term
#define FT_SSBO_SRBF_ENV_PIXELS 51   // vec4[W·H]: the equirect map's rgb, row 0 at the top
#define FT_SSBO_SRBF_SUMS 52         // the fit's reductions: vec4 b_j (rgb) then float-in-vec4 K_ab
#define FT_SSBO_SRBF_TABLE 53        // vec4[ftSrbfTableSize]: rgb I(θ_o, θ_j, Δφ, λ)
#define FT_SSBO_SRBF_INPUT 54        // FabricParams, then vec4 requests (lookups)
#define FT_SSBO_SRBF_OUTPUT 55       // vec4 results of lookups
#define FT_WG_SRBF 64

// Flyaway fibers (common/flyaway.h, 001 §4.4 eq. 12–13; docs/flyaways.md):
// UBO 16 and SSBO 65–69 are this group's.
#define FT_UBO_FLYAWAY 16              // FlyawayParams (the bake's; the frame binds its own copy here too)
#define FT_SSBO_FLYAWAY_POINTS 65      // vec4[slots][FT_FLYAWAY_POINTS]: xyz, w = t
#define FT_SSBO_FLYAWAY_HEADERS 66     // vec4 per slot: (present, kept, zMin, zMax)
#define FT_SSBO_FLYAWAY_TEXELS 67      // uint[3][H][W]: RGBA8 (packUnorm4x8), 0 = empty
#define FT_SSBO_FLYAWAY_FRAME 68       // uint[3][H][W]: the frame's copy of the texels (fiber_strip.frag.glsl)
#define FT_WG_FLYAWAY 64
// Segment visibility functions of 004 §4.1 (common/segment_visibility.h,
// gpu/segment_visibility_gpu.h): UBO 18–19 and SSBO 74–85 are this group's.
#define FT_UBO_SVF 18                // SvfParams
#define FT_SSBO_SVF_IMAGES 74        // uint[images][W·H]: the binary visibility images (1 = visible)
#define FT_SSBO_SVF_SSDF 75          // float[images][W·H]: the SSDF (radians, + visible)
#define FT_SSBO_SVF_NEAREST 76       // int[images][W·H/2]: nearest axis of each z > 0 pixel
#define FT_SSBO_SVF_WEIGHTS 77       // float[images][Q]: the SG weights w_k,q
#define FT_SSBO_SVF_PCA 78           // float: mean[W·H], then basis[C][W·H], then coefficients[images][C]
#define FT_SSBO_SVF_DECODE 79        // vec2[images][W·H]: (PCA-reconstructed SSDF, V^ssg)
// (llvmpipe has 80 SSBO binding points, 0–79: 80–85 of this group's range are unusable there.)
#define FT_WG_SVF 64
#define FT_WG_PRT_VOL 64             // exemplar volume: voxels (build) and pixels (sampler) per work group

// Fabric PRT of 004 beyond visibility (single scattering §5.2, multiple
// scattering §4.2–4.3 and §5.3, exemplar volume §5.1). llvmpipe has only 80
// SSBO bindings and 0–79 are nearly all named, so the harness evaluators of
// every prt/* group share one request/result pair (each runs alone as its own
// compute program), and each group's own data takes one of the last free slots.
#define FT_SSBO_PRT_REQUESTS 39      // harness requests of the prt/* evaluators (layout per group)
#define FT_SSBO_PRT_RESULTS 40       // their results
#define FT_UBO_PRT_SS 20             // single scattering (common/prt_single_scattering.h)
#define FT_SSBO_PRT_SS_TABLE 41      // its tables (𝒢(μ; λ) per BCSDF lobe)
#define FT_WG_PRT_SS 64              // its compute program: 𝒢 texels (bake) or requests per work group
#define FT_UBO_PRT_MS 21             // multiple scattering (common/prt_multiple_scattering.h)
#define FT_SSBO_PRT_MS_TRANSFER 62   // the IIRTF matrices A_C per cell
#define FT_SSBO_PRT_MS_TABLES 63     // C_S and C_G
#define FT_UBO_PRT_VOL 22            // exemplar volume (common/exemplar_volume.h)
#define FT_SSBO_PRT_VOL_IDS 64       // the segment-id volume; after its voxels, the candidate lists and segment table (capsule ids)
#define FT_SSBO_PRT_VOL_SEGMENTS 69  // the segment table (direction, midpoint, cell)
// SSBO 73 is taken by deferred shading (FT_SSBO_DEFERRED_LIST): no slot below 80 is free.
#define FT_SSBO_PRT_FRAME 35         // the PRT frame's per-pixel records (common/prt_frame.h PrtFramePixel)
#define FT_UBO_PRT_FRAME 23          // PrtFrameParams (common/prt_frame.h)
#define FT_WG_PRT_FRAME 64           // its compute program: pixels per work group
// The single-pass GPU frame (gpu/prt_frame_gpu.h PrtFrameRendererGpu). Its one
// storage buffer (image, c_T per cell, shading per segment, rotation scratch)
// binds at FT_SSBO_PRT_FRAME: llvmpipe has no SSBO binding 80 or above.
#define FT_UBO_PRT_FRAME_GPU 24      // PrtFrameGpuParams (common/prt_frame.h)

// Lobe bits of a BCSDF evaluation request (gpu/bcsdf_gpu.h, bcsdf_eval.comp.glsl).
#define FT_BCSDF_LOBE_R 1u
#define FT_BCSDF_LOBE_TT 2u

// Work-group sizes (local_size_x).
#define FT_WG_FRAMES 64

// Knots one invocation of the frame kernel propagates per dispatch: Mesa's
// gallivm ends any loop after 65,535 iterations, so longer curves are done in
// several dispatches that carry the normal across (yarn_frames.comp.glsl).
#define FT_FRAME_CHUNK 8192u
#define FT_WG_DECIDE 64
#define FT_WG_SCAN 1024
#define FT_WG_GENERATE 64
#define FT_WG_SAMPLES 64
#define FT_WG_KNIT 64
#define FT_WG_KNIT_UPSAMPLE 64
#define FT_WG_BCSDF 64
#define FT_WG_SELF_SHADOW 64
#define FT_WG_CORE_TEXTURE 64
#define FT_WG_AO 64
#define FT_WG_XI 64
#define FT_WG_DS 64
#define FT_WG_PRT_MS 64  // common/prt_multiple_scattering.h (004 §4.3, §5.3.1)

// Index value that restarts a GL_LINE_STRIP (glPrimitiveRestartIndex).
#define FT_RESTART_INDEX 0xFFFFFFFFu

// Fiber types, stored in FiberVertex.id.w bits 0..7.
#define FT_FIBER_CORE 0u
#define FT_FIBER_MIGRATION 1u
#define FT_FIBER_LOOP 2u
#define FT_FIBER_HAIR 3u

// Migration phase of eq. 2 (YarnParams.migrationPhase): an independent random
// phase per fiber, as the presets were fitted (Zhao et al. 2016, public fitting
// code), or θ_i, the fiber's own polar angle, as eq. 2 of Wu & Yuksel 2017 writes it.
#define FT_MIGRATION_PHASE_INDEPENDENT 0u
#define FT_MIGRATION_PHASE_FIBER_ANGLE 1u

// Fiber id used for a ply's core fiber in FiberVertex.id.z (low 16 bits).
#define FT_CORE_FIBER_ID 0xFFFFu

// Hard limits that keep ids packable into 16 bits and tessellation legal.
#define FT_MAX_PLIES 8u
#define FT_MAX_FIBERS_PER_PLY 4096u
#define FT_MAX_SUBDIVISIONS 64u

#endif  // FT_CONSTANTS_H
