// knit_render.h — the knit patch as it is drawn: what `fibertwin knit`, the
// knit/appearance/* cases and ft_knit_bench share, so that the three draw the
// same frame (docs/knit-rendering.md).
//
//  * the fibers: the yarn preset fitted to the knot yarn radius r of eq. 1–2
//    (the solver's yarns touch at 2r, so that is their thickness);
//  * the buffers of a frame: its yarn curves with the REST state's length
//    coordinates (the fibers stay on the same stretch of yarn material as it
//    deforms, 000 §5 fixes s at load; adoptLengthCoordinates);
//  * the camera: one for a whole sequence, framing the interpolated yarns of
//    its most deformed (last) frame from kKnitViewDir.
#pragma once
#include <string>

#include "knit/knit_problem.h"
#include "scene/camera.h"
#include "scene/yarn_model.h"
#include "scene/yarn_radius.h"

namespace ft {

// Planted fault knit-length-not-adopted (validation/faults.def): a frame keeps
// its own arc lengths, so the fibers slide along the stretched yarn.
inline bool ftFaultKnitLengthNotAdopted = false;
#define FT_FAULT_KNIT_LENGTH_NOT_ADOPTED_ON ::ft::ftFaultKnitLengthNotAdopted

// From the patch towards the camera: mostly face-on, a little from below, so
// that the loops' depth shows.
inline constexpr glm::vec3 kKnitViewDir{0.15f, -0.35f, 1.0f};

// fitFibers(preset, options.yarnRadius, "the knot yarn radius", fiber).
FittedFibers knitFibers(const YarnPreset& preset, const KnitOptions& options, const FiberOptions& fiber);

// The rest state's yarns (the interpolated template on the rest mesh, which
// the solver leaves as it is: zero energy) flattened; their length
// coordinates are every frame's.
YarnBuffers knitRestBuffers(const StitchMesh& rest, const KnitOptions& options);

// A frame's yarns (knitYarnModel / knitYarnModelFromVertices) flattened, with
// the rest state's length coordinates. InputError naming the frame when its
// yarns do not match the rest state's.
YarnBuffers knitFrameBuffers(const YarnModel& frame, const YarnBuffers& rest);

// The sequence's camera: frames the interpolated (unsolved) yarns of `framed`
// (the last, most deformed frame) from kKnitViewDir; the optimized yarns lie
// within a yarn radius of them.
Camera knitCamera(const KnitSetup& framed, int width, int height);

}  // namespace ft
