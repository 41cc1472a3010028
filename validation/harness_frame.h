// harness_frame.h — the shaded frame that the frame-equality cases
// (shading/occlusion-cull/*, shading/deferred/*) draw twice and compare: the
// harness model with cotton1's fibers (fitted), the named view from
// (0.3, 0.5, 1), cotton lighting, `appearance`'s inputs baked on the GPU and
// set on the context's FiberRenderer. Returns the path to draw.
#pragma once
#include <string>

#include "gpu/fiber_renderer.h"
#include "gpu/shading_inputs_gpu.h"
#include "scene/camera.h"
#include "scene/lighting.h"
#include "scene/yarn_radius.h"
#include "validation/harness.h"

namespace ft {

inline FiberPath prepareHarnessFrame(ValidationContext& ctx, const std::string& view, bool tessellation,
                                     const AppearanceOptions& appearance, int width, int height) {
  const YarnPreset& preset = findYarnPreset("cotton1");
  const FiberSetup& setup = ctx.fiberSetup(preset);
  const FittedFibers& fitted = ctx.fittedFibers(preset);
  const Camera camera = namedViewCamera(view, ctx.model(), setup.params, glm::vec3(0.3f, 0.5f, 1.0f), width, height);
  Lighting lighting;
  lighting.fabric = "cotton";
  FiberGpu& gpu = ctx.gpu<FiberGpu>();
  gpu.setModel(ctx.buffers(), setup.table);
  gpu.setParams(setup.params, makeViewParams(camera, ctx.options().lodThresholdPx, true, true));
  gpu.setSegmentList({});
  ctx.gpu<FiberRenderer>().setShading(ctx.gpu<ShadingBakeGpu>().bake(
      {makeShadingParams(lighting), &fitted.fit.preset, appearance, &setup.params, &setup.table}));
  return tessellation ? FiberPath::Tessellation : FiberPath::Compute;
}

}  // namespace ft
