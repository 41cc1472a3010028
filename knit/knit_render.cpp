#include "knit/knit_render.h"

#include <fmt/format.h>

#include <stdexcept>

#include "scene/input_error.h"

namespace ft {

FittedFibers knitFibers(const YarnPreset& preset, const KnitOptions& options, const FiberOptions& fiber) {
  return fitFibers(preset, options.yarnRadius, "the knot yarn radius", fiber);
}

YarnBuffers knitRestBuffers(const StitchMesh& rest, const KnitOptions& options) {
  const KnitSetup setup = buildKnitSetup(rest, rest, options);
  return buildYarnBuffers(knitYarnModel(setup, liftKnitPoints(setup, initialKnitPoints(setup)), true));
}

YarnBuffers knitFrameBuffers(const YarnModel& frame, const YarnBuffers& rest) {
  YarnBuffers buffers = buildYarnBuffers(frame);
  if (ftFaultKnitLengthNotAdopted) return buffers;
  try {
    adoptLengthCoordinates(buffers, rest);
  } catch (const std::invalid_argument& e) {
    throw InputError(fmt::format("{}: its yarns do not match the rest state's ({})", frame.name, e.what()));
  }
  return buffers;
}

Camera knitCamera(const KnitSetup& framed, int width, int height) {
  return frameModel(knitYarnModel(framed, liftKnitPoints(framed, initialKnitPoints(framed)), false), kKnitViewDir,
                    width, height);
}

}  // namespace ft
