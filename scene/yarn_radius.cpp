#include "scene/yarn_radius.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <unordered_map>
#include <vector>

#include "scene/input_error.h"

namespace ft {

namespace {

struct Chord {
  glm::vec3 a, b;
  uint32_t curve;
  double arcA, arcB;  // arc length along the curve's polyline at a and b
};

double pointChordDistance(const glm::vec3& p, const Chord& c, double& arcAtClosest) {
  const glm::dvec3 a(c.a), b(c.b), q(p);
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(q - a, ab) / len2, 0.0, 1.0) : 0.0;
  arcAtClosest = c.arcA + t * (c.arcB - c.arcA);
  return glm::length(q - (a + t * ab));
}

// Uniform grid of chords keyed by integer cell coordinates.
struct ChordGrid {
  double cell = 1.0;
  glm::dvec3 origin{0.0};
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
  static uint64_t key(int64_t x, int64_t y, int64_t z) {
    return (static_cast<uint64_t>(x & 0x1FFFFF) << 42) | (static_cast<uint64_t>(y & 0x1FFFFF) << 21) |
           static_cast<uint64_t>(z & 0x1FFFFF);
  }
  glm::i64vec3 cellOf(const glm::vec3& p) const {
    const glm::dvec3 c = glm::floor((glm::dvec3(p) - origin) / cell);
    return glm::i64vec3(c);
  }
};

}  // namespace

YarnRadiusEstimate estimateYarnRadius(const YarnModel& model) {
  std::vector<Chord> chords;
  std::vector<std::pair<uint32_t, double>> samples;  // (curve, arc) of every control point
  std::vector<glm::vec3> samplePoints;
  std::vector<double> spacings;
  std::vector<double> curveLength(model.curves.size(), 0.0);
  for (uint32_t ci = 0; ci < model.curves.size(); ++ci) {
    const YarnCurve& c = model.curves[ci];
    const size_t n = c.points.size();
    const size_t count = c.closed ? n : (n > 0 ? n - 1 : 0);
    double arc = 0.0;
    for (size_t i = 0; i < count; ++i) {
      const glm::vec3 a = c.points[i], b = c.points[(i + 1) % n];
      const double len = glm::distance(glm::dvec3(a), glm::dvec3(b));
      chords.push_back({a, b, ci, arc, arc + len});
      samples.push_back({ci, arc});
      samplePoints.push_back(a);
      spacings.push_back(len);
      arc += len;
    }
    curveLength[ci] = arc;
    if (!c.closed && n > 0) {
      samples.push_back({ci, arc});
      samplePoints.push_back(c.points[n - 1]);
    }
  }
  if (spacings.empty()) throw InputError(fmt::format("{}: no yarn segments to estimate a yarn radius from", model.name));

  std::nth_element(spacings.begin(), spacings.begin() + spacings.size() / 2, spacings.end());
  const double medianSpacing = spacings[spacings.size() / 2];
  const Bounds bounds = modelBounds(model);
  const double extent = std::max(glm::length(glm::dvec3(bounds.hi) - glm::dvec3(bounds.lo)), 1e-30);
  // The mode needs no more than ~20,000 control points, evenly spread.
  const size_t stride = std::max<size_t>(1, (samples.size() + 19999) / 20000);
  size_t queried = 0;
  for (size_t i = 0; i < samples.size(); i += stride) ++queried;

  // Cells start a few control-point spacings wide (a knit's neighbours are
  // about that close) and grow 4× while fewer than half the queries find a
  // neighbour within three rings of cells (sparse models, long chords).
  std::vector<double> nearest;
  for (double cell = std::max(2.0 * medianSpacing, extent * 1e-7);; cell *= 4.0) {
    ChordGrid grid;
    grid.cell = cell;
    grid.origin = glm::dvec3(bounds.lo);
    // A chord is registered in the cells of points along it at most half a
    // cell apart (at most 256 of them: a chord far longer than the cells is
    // only partly registered), so every point of it lies within one cell of
    // a cell that lists it.
    for (uint32_t k = 0; k < chords.size(); ++k) {
      const double len = glm::distance(glm::dvec3(chords[k].a), glm::dvec3(chords[k].b));
      const int steps = static_cast<int>(std::min(256.0, std::ceil(2.0 * len / cell)));
      uint64_t last = ~0ull;
      for (int i = 0; i <= steps; ++i) {
        const glm::vec3 q = glm::mix(chords[k].a, chords[k].b, steps > 0 ? float(i) / float(steps) : 0.0f);
        const glm::i64vec3 c = grid.cellOf(q);
        const uint64_t key = ChordGrid::key(c.x, c.y, c.z);
        if (key != last) grid.cells[key].push_back(k), last = key;
      }
    }
    nearest.clear();
    const int maxRing = 3;
    for (size_t i = 0; i < samples.size(); i += stride) {
      const glm::vec3 p = samplePoints[i];
      const glm::i64vec3 c = grid.cellOf(p);
      double best = std::numeric_limits<double>::infinity();
      for (int r = 0; r <= maxRing; ++r) {
        if (best <= (r - 2) * grid.cell) break;  // nothing nearer can lie further out
        for (int64_t x = c.x - r; x <= c.x + r; ++x)
          for (int64_t y = c.y - r; y <= c.y + r; ++y)
            for (int64_t z = c.z - r; z <= c.z + r; ++z) {
              if (std::max({std::abs(x - c.x), std::abs(y - c.y), std::abs(z - c.z)}) != r) continue;  // shell only
              auto it = grid.cells.find(ChordGrid::key(x, y, z));
              if (it == grid.cells.end()) continue;
              for (uint32_t k : it->second) {
                double arc = 0.0;
                const double d = pointChordDistance(p, chords[k], arc);
                if (d >= best) continue;
                if (chords[k].curve == samples[i].first) {
                  double along = std::abs(arc - samples[i].second);
                  if (model.curves[samples[i].first].closed)
                    along = std::min(along, curveLength[samples[i].first] - along);
                  if (along <= 3.0 * d) continue;  // the same pass of the yarn
                }
                best = d;
              }
            }
      }
      if (std::isfinite(best) && best > 0.0) nearest.push_back(best);
    }
    if (2 * nearest.size() >= queried || cell > extent) break;
  }
  YarnRadiusEstimate e;
  e.samples = queried;
  e.withNeighbour = nearest.size();
  if (nearest.empty()) return e;  // found == false

  // Mode of the nearest-pass distances over [0, 2·median].
  std::vector<double> sorted = nearest;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  const int bins = 64;
  const double width = 2.0 * median / bins;
  std::vector<size_t> counts(bins, 0);
  std::vector<double> sums(bins, 0.0);
  for (double d : nearest) {
    const int b = static_cast<int>(d / width);
    if (b < bins) ++counts[b], sums[b] += d;
  }
  const int peak = static_cast<int>(std::max_element(counts.begin(), counts.end()) - counts.begin());
  e.found = true;
  e.contactSpacing = static_cast<float>(sums[peak] / counts[peak]);
  e.radius = 0.5f * e.contactSpacing;
  return e;
}

double presetEnvelopeRadius(const YarnPreset& p) {
  return p.yarnRadius / 2.0 + std::max(p.ellipseLong, p.ellipseShort) * p.rhoMax;
}

YarnPreset scaleYarnPreset(const YarnPreset& preset, double k) {
  if (!(k > 0.0) || !std::isfinite(k))
    throw InputError(fmt::format("yarn preset {}: scale factor {} must be a positive number", preset.name, k));
  YarnPreset s = preset;
  s.yarnAlpha *= k;
  s.alpha *= k;
  s.yarnRadius *= k;
  s.ellipseLong *= k;
  s.ellipseShort *= k;
  for (NormalParam* n : {&s.hairZe, &s.hairR0, &s.hairRe, &s.loopR1}) n->mu *= k, n->sigma *= k;
  s.hairDensity /= k;
  s.loopDensity /= k;
  return s;  // R_max, ε, β, s_i, ρ are in ply-disk units or per turn; pe is an angle
}

FittedPreset fitYarnPreset(const YarnPreset& preset, const YarnModel& model, std::optional<double> yarnRadius) {
  FittedPreset f;
  if (yarnRadius) {
    if (!(*yarnRadius > 0.0) || !std::isfinite(*yarnRadius))
      throw InputError(fmt::format("--yarn-radius: {} must be a positive number", *yarnRadius));
    f.radius = *yarnRadius;
    f.source = "--yarn-radius";
  } else if (const YarnRadiusEstimate e = estimateYarnRadius(model); e.found) {
    f.radius = e.radius;
    f.source = "estimated from " + model.name;
  } else {
    f.radius = presetEnvelopeRadius(preset);
    f.source = "no yarn of " + model.name + " passes near another: the preset's own scale";
  }
  f.scale = f.radius / presetEnvelopeRadius(preset);
  f.preset = scaleYarnPreset(preset, f.scale);
  return f;
}

FittedFibers fitFibers(const YarnPreset& preset, double yarnRadius, std::string source, const FiberOptions& options) {
  FittedFibers f;
  f.fit = fitYarnPreset(preset, YarnModel{}, yarnRadius == 0.0 ? presetEnvelopeRadius(preset) : yarnRadius);
  f.fit.source = std::move(source);
  FiberOptions o = options;
  o.fiberRadius = static_cast<float>(options.fiberRadius * f.fit.scale);
  static_cast<FiberSetup&>(f) = makeFiberSetup(f.fit.preset, o);
  return f;
}

FittedFibers fitFibers(const YarnPreset& preset, const YarnModel& model, const FiberOptions& options) {
  if (options.yarnRadius > 0.0f) return fitFibers(preset, options.yarnRadius, "--yarn-radius", options);
  if (options.yarnRadius != 0.0f || !std::isfinite(options.yarnRadius))
    throw InputError(fmt::format("--yarn-radius: {} must be a positive number", options.yarnRadius));
  const FittedPreset fit = fitYarnPreset(preset, model, std::nullopt);
  return fitFibers(preset, fit.radius, fit.source, options);
}

}  // namespace ft
