// layout_probe.comp.glsl — declares one block per shared struct so that
// tests/shared_layout_test.cpp can compare GL's offsets and strides with the C++
// side. Every block is used (so it is active): element 0 of each storage buffer
// is copied to element 1, and the two uniform blocks are copied into the probe
// buffer, which also checks the bytes end to end.
#include "common/constants.h"
#include "common/yarn_params.h"
#include "common/view_params.h"
#include "common/fiber_shading.h"
#include "common/yarn_buffers.h"
#include "common/fiber_vertex.h"
#include "common/knit_stitch.h"
#include "common/core_texture.h"
#include "common/ambient_occlusion.h"
#include "common/shadow_map.h"
#include "common/occlusion_cull.h"
#include "common/srbf.h"
#include "common/flyaway.h"
#include "common/segment_visibility.h"
#include "common/pcss.h"
#include "common/exemplar_volume.h"
float ftPcssFetch(int source, uint i) { return 0.0; }  // the lookups are not run here
float prtSsTable[1];  // the shared body reads its table by this name (no storage block left here)
#include "common/prt_single_scattering.h"
#include "common/prt_frame.h"

layout(local_size_x = 1) in;

layout(std140, binding = FT_UBO_YARN_PARAMS) uniform YarnBlock { YarnParams yarn; };
layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };

layout(std430, binding = FT_SSBO_CONTROL_POINTS) buffer ControlPointBuf {
  ControlPoint data[];
} controlPoints;
layout(std430, binding = FT_SSBO_CURVES) buffer CurveInfoBuf { CurveInfo data[]; } curves;
layout(std430, binding = FT_SSBO_SEGMENTS) buffer SegmentRefBuf { SegmentRef data[]; } segments;
layout(std430, binding = FT_SSBO_FRAMES) buffer FrameNormalBuf { FrameNormal data[]; } frames;
layout(std430, binding = FT_SSBO_FIBER_TABLE) buffer FiberCoordBuf { FiberCoord data[]; } fiberTable;
layout(std430, binding = FT_SSBO_VERTICES) buffer FiberVertexBuf { FiberVertex data[]; } vertices;
layout(std430, binding = FT_SSBO_DECISIONS) buffer SegmentDecisionBuf { SegmentDecision data[]; } decisions;
layout(std430, binding = FT_SSBO_DRAW_COMMAND) buffer DrawElementsCommandBuf {
  DrawElementsCommand data[];
} commands;
layout(std430, binding = FT_SSBO_SAMPLES) buffer YarnSampleBuf { YarnSample data[]; } samples;
layout(std140, binding = FT_UBO_KNIT_PARAMS) uniform KnitParamsBlock { KnitSolveParams knit; };
layout(std430, binding = FT_SSBO_KNIT_STITCHES) buffer KnitStitchGpuBuf { KnitStitchGpu data[]; } knitStitches;
layout(std430, binding = FT_SSBO_KNIT_ENERGY) buffer KnitEnergyGpuBuf { KnitEnergyGpu data[]; } knitEnergies;
layout(std430, binding = FT_SSBO_KNIT_POINTS) buffer KnitParamsCopyBuf { KnitSolveParams knitCopy; };
layout(std140, binding = FT_UBO_SHADING) uniform ShadingBlock { ShadingParams shading; };
layout(std430, binding = FT_SSBO_AMBIENT_TABLE) buffer ShadingCopyBuf { ShadingParams shadingCopy; };
layout(std140, binding = FT_UBO_CORE_TEXTURE) uniform CoreTextureBlock { CoreTextureParams core; };
layout(std430, binding = FT_SSBO_CORE_TEX0) buffer CoreCopyBuf { CoreTextureParams coreCopy; };
layout(std140, binding = FT_UBO_AMBIENT_OCCLUSION) uniform AoBlock { AmbientOcclusionParams ao; };
layout(std430, binding = FT_SSBO_AO_OUTPUT) buffer AoCopyBuf { AmbientOcclusionParams aoCopy; };
layout(std140, binding = FT_UBO_SHADOW_MAP) uniform ShadowMapBlock { ShadowMapParams shadowMapParams; };
layout(std140, binding = FT_UBO_OCCLUSION) uniform OcclusionBlock { OcclusionPyramid pyramid; };
layout(std140, binding = FT_UBO_SRBF) uniform SrbfBlock { SrbfEnvironment srbf; };
layout(std140, binding = FT_UBO_FLYAWAY) uniform FlyawayBlock { FlyawayParams fly; };
layout(std140, binding = FT_UBO_SVF) uniform SvfBlock { SvfParams svf; };
layout(std140, binding = FT_UBO_PCSS) uniform PcssBlock { PcssParams pcss; };
layout(std140, binding = FT_UBO_PRT_VOL) uniform VolBlock { VolParams vol; };
layout(std140, binding = FT_UBO_PRT_SS) uniform PrtSsBlock { PrtSsParams prtSs; };
layout(std140, binding = FT_UBO_PRT_FRAME_GPU) uniform PrtFrameGpuBlock { PrtFrameGpuParams prtFrame; };
layout(std430, binding = FT_SSBO_LAYOUT_PROBE) buffer ParamsCopyBuf {
  YarnParams yarnCopy;
  ViewParams viewCopy;
} paramsCopy;

void main() {
  controlPoints.data[1] = controlPoints.data[0];
  curves.data[1] = curves.data[0];
  segments.data[1] = segments.data[0];
  frames.data[1] = frames.data[0];
  fiberTable.data[1] = fiberTable.data[0];
  vertices.data[1] = vertices.data[0];
  decisions.data[1] = decisions.data[0];
  commands.data[1] = commands.data[0];
  samples.data[1] = samples.data[0];
  paramsCopy.yarnCopy = yarn;
  paramsCopy.viewCopy = view;
  knitStitches.data[1] = knitStitches.data[0];
  knitEnergies.data[1] = knitEnergies.data[0];
  knitCopy = knit;
  shadingCopy = shading;
  coreCopy = core;
  aoCopy = ao;
  // Read, so the block is active (the storage-block limit, 16, leaves no room for a copy).
  if (shadowMapParams.count.w == 0xFFFFFFFFu) aoCopy.seed = ao.seed;  // the same value either way
  if (pyramid.size.w == 0xFFFFFFFFu && pyramid.level[FT_OCCLUSION_MAX_LEVELS - 1].w == 0u) aoCopy.seed = ao.seed;
  float srbfSum = srbf.constant.x;  // every lobe member read, so each is an active resource
  for (int j = 0; j < FT_SRBF_LOBES; ++j) srbfSum += srbf.lobes[j].axisLambda.x + srbf.lobes[j].weight.x;
  if (srbfSum == -12345.0) aoCopy.seed = ao.seed;
  // Flyaways: every member read, so each is an active resource.
  float flySum = fly.period + fly.halfWidth + fly.bodyRadius + fly.lineHalfWidth + fly.zeMu + fly.zeSigma +
                 fly.r0Mu + fly.r0Sigma + fly.reMu + fly.reSigma + fly.peMu + fly.peSigma + fly.rootOffset +
                 fly.alpha + fly.noise + fly.zReach + fly.margin + fly.poissonThresholdB + fly.poissonThresholdI;
  uint flyBits = fly.width ^ fly.height ^ fly.maxPerSet ^ fly.patterns ^ fly.chunksB ^ fly.chunksI ^ fly.seed ^ fly.pad0 ^ fly.pad1;
  if (flySum == -12345.0 && flyBits == 0x12345u) aoCopy.seed = ao.seed;
  // Every SvfParams member read, so each is an active resource.
  if (svf.width + svf.height + svf.axes + svf.segments + svf.seed + svf.components + svf.firstSegment + svf.mode ==
          0xFFFFFFFFu &&
      svf.lambda + svf.pad0 + svf.pad1 + svf.pad2 == -12345.0)
    aoCopy.seed = ao.seed;
  float pcssSum = pcss.lightTanAlpha.x + pcss.extent.x + float(pcss.count.x);  // every member read
  for (int j = 0; j < FT_PCSS_MAX_LOBES; ++j) pcssSum += pcss.lobeX[j].x + pcss.lobeY[j].x + pcss.lobeZ[j].x + pcss.lobeCone[j].x;
  if (pcssSum == -12345.0) aoCopy.seed = ao.seed;
  // Every VolParams member read, so each is an active resource.
  if (vol.origin.x + vol.camPos.x + vol.camRight.x + vol.camUp.x + vol.camDir.x == -12345.0 &&
      vol.dims.x + vol.grid.x + vol.ray.x == 0xFFFFFFFFu)
    aoCopy.seed = ao.seed;
  // Every PrtSsParams member read, so each is an active resource.
  float prtSum = prtSs.lambdaSvf;
  for (int f = 0; f < FT_PRT_SS_MAX_FABRICS; ++f)
    prtSum += prtSs.fabrics[f].colorR.x + prtSs.fabrics[f].colorTT.x + prtSs.fabrics[f].lobes.x;
  uint prtBits = prtSs.count ^ prtSs.mode ^ prtSs.fabricCount ^ prtSs.axes ^ prtSs.tableSize ^ prtSs.pad0 ^ prtSs.pad1;
  if (prtSum == -12345.0 && prtBits == 0x12345u) aoCopy.seed = ao.seed;
  // Every PrtFrameGpuParams member read, so each is an active resource.
  if (prtFrame.light.x + prtFrame.svf.x + prtFrame.fabric.colorR.x + prtFrame.fabric.colorTT.x +
          prtFrame.fabric.lobes.x == -12345.0 &&
      (prtFrame.sizes.x ^ prtFrame.ms.x ^ prtFrame.offsets.x ^ prtFrame.flags.x) == 0x12345u)
    aoCopy.seed = ao.seed;
}
