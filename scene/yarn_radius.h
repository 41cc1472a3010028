// yarn_radius.h — the yarn thickness a yarn-level model was built for, and a
// preset scaled to it.
//
// A model's centre lines carry their yarn radius implicitly: where two yarns
// touch, their centre lines are one yarn diameter apart. The fitted presets
// (Zhao, Luan & Bala 2016) come in the units of their CT scans, so a preset
// dropped onto a model as it is may be several times too thin or too thick.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "scene/yarn_fibers.h"
#include "scene/yarn_model.h"
#include "scene/yarn_preset.h"

namespace ft {

struct YarnRadiusEstimate {
  bool found = false;           // false: no pass has a neighbour (one straight yarn)
  float radius = 0.0f;          // half the contact spacing
  float contactSpacing = 0.0f;  // typical centre-line distance of touching yarns
  size_t samples = 0;           // control points measured (at most ~20,000, evenly spread)
  size_t withNeighbour = 0;     // of which had another yarn pass within reach
};

// For every control point, the distance to the nearest other yarn pass: a
// chord of another curve, or of the same curve where the arc between the two
// points is over 3× their distance (the yarn left and came back, as a knitted
// row does). Touching passes are the nearest ones, and in a knit they are the
// most common, so the contact spacing is the mode of these distances
// (a histogram over [0, 2·median] in 64 bins, refined by the bin's mean).
// A model with no neighbouring passes (one straight yarn) has no thickness
// to read: found = false.
YarnRadiusEstimate estimateYarnRadius(const YarnModel& model);

// The preset with every length multiplied by `factor` (ply radius, ellipse
// axes, twist pitches, flyaway lengths and radii) and the per-length
// densities divided by it: the same yarn, `factor` times larger. Ratios and
// angles are kept. Throws InputError for a non-positive or non-finite factor.
YarnPreset scaleYarnPreset(const YarnPreset& preset, double factor);

// A preset's yarn radius as it touches its neighbours: from the axis to the
// farthest regular fiber, yarn_radius/2 + max(e_N, e_B)·ρ_max (flyaways
// excluded: they reach past the contact).
double presetEnvelopeRadius(const YarnPreset& preset);

// How a preset is fitted to a model (`validate`, `render`, `knit` and the
// benches share it): to `yarnRadius` when given, else to the model's
// estimated radius, else (nothing to estimate from) at its own scale, which
// `source` says. `scale` = fitted radius / presetEnvelopeRadius.
struct FittedPreset {
  YarnPreset preset;
  double scale = 1.0;
  double radius = 0.0;
  std::string source;  // "estimated from <model>" or "--yarn-radius"
};
FittedPreset fitYarnPreset(const YarnPreset& preset, const YarnModel& model, std::optional<double> yarnRadius);

// The preset fitted to the model (options.yarnRadius > 0 overrides the
// estimate), then makeFiberSetup: its fiber table and YarnParams. The drawn
// fiber radius scales with the preset, like every other length.
struct FittedFibers : FiberSetup {
  FittedPreset fit;
};
FittedFibers fitFibers(const YarnPreset& preset, const YarnModel& model, const FiberOptions& options);

// The same, to a radius already estimated (estimateYarnRadius is not free on
// big models: callers that fit several presets estimate once); 0: the
// preset's own scale (nothing to estimate from).
FittedFibers fitFibers(const YarnPreset& preset, double yarnRadius, std::string source, const FiberOptions& options);

}  // namespace ft
