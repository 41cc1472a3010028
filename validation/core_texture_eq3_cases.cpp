// core_texture_eq3_cases.cpp — settles eq. 3 of Wu & Yuksel 2019 (000 §3.2),
// the u coordinate at which a core strip seen from azimuth ψ_rel reads the
// core-fiber texture (notes-rendering A1 check C5). Eq. 3 as extracted is
// garbled (docs/core-texture.md); its semantic form
//   u = frac(Φ(s) − k_ψ ψ_rel / 2π),  Φ(s) = s/α + k_ply s / yarn_alpha (turns)
// leaves |k_ψ| ∈ {½ (the paper's factor), 1}, its sign and k_ply ∈ {0, ±1}
// open. The case asks the explicit core fibers: for ψ ∈ {0, 30, 60, 90}° it
// ray casts them (Embree round curves, the bake's own reference,
// reference/core_texture.h) seen orthographically from azimuth ψ around the
// ply axis — the whole helix set turned by −ψ, i.e. every fiber's polar angle
// θ_i moved by −σ_f ψ/2π while its migration phase stays, which is the
// fibers seen from there, not a texture trick — and compares each texel
// (s = u α, the same v) with the ψ = 0 texture looked up at each candidate's
// u (ftCoreBundlePhaseTurns, ftCoreTextureU, sampleCoreTexture: what the
// frame does). Normalised cross-correlation of the height map h (holes 0):
// the holes and fiber edges are what the texture shows.
//
// Gating: the frame's convention (ftCoreTextureKPsi, FT_CORE_TEXTURE_K_PLY)
// is the best of all candidates at each ψ ≠ 0, and beats every alternative
// by a margin in the mean over ψ ≠ 0 (where they differ). The planted fault
// core-texture-view-sign (k_ψ's sign flipped in common/, both sides) fails it.
// Notes A1 C5 also asks NCC ≥ 0.9 for the chosen u: reported, not gating,
// because no u can reach it where the fibers migrate: the texture's column
// u' shows the migration radius of length u'α, the explicit fibers that of
// the viewed length uα, and they differ by the view term (measured: 0.92–0.97
// at 90° on cotton2 and silk1, 0.52–0.73 on the others; docs/core-texture.md).
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "common/core_texture.h"
#include "reference/core_texture.h"
#include "scene/core_texture_input.h"
#include "validation/case_support.h"
#include "validation/harness.h"

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;
const double kPsiDegrees[] = {0.0, 30.0, 60.0, 90.0};

// "Measurably lower for the alternatives": the best alternative's mean NCC
// over ψ = 30, 60, 90° at least 0.1 below the convention's (measured gap: see
// docs/core-texture.md, ≥ 0.4 on cotton1); a texture shifted by a fraction of a
// twist decorrelates by much more than that.
constexpr double kMarginTolerance = -0.1;  // best alternative − convention
const char* kMarginWhy = "notes A1 C5: every other (k_ψ, sign, k_ply) reads the fibers ≥ 0.1 NCC worse (mean over ψ ≠ 0)";

struct Convention {
  std::string name;
  float kPsi;  // signed
  float kPly;
};

double ncc(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0.0, mb = 0.0;
  for (size_t k = 0; k < a.size(); ++k) ma += a[k], mb += b[k];
  ma /= double(a.size());
  mb /= double(b.size());
  double ab = 0.0, aa = 0.0, bb = 0.0;
  for (size_t k = 0; k < a.size(); ++k) {
    ab += (a[k] - ma) * (b[k] - mb);
    aa += (a[k] - ma) * (a[k] - ma);
    bb += (b[k] - mb) * (b[k] - mb);
  }
  return aa > 0.0 && bb > 0.0 ? ab / std::sqrt(aa * bb) : std::nan("");
}

CaseResult runEq3(ValidationContext& ctx, const YarnPreset& preset, const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "appearance";
  r.path = "core-texture";
  const FiberSetup& fs = ctx.fiberSetup(preset);
  const YarnParams& p = fs.params;
  const auto t0 = Clock::now();
  const CoreTextureInput base = makeCoreTextureInput(p, fs.table, FT_CORE_TEXTURE_WIDTH, FT_CORE_TEXTURE_HEIGHT);
  const CoreTexture tex = bakeCoreTextureEmbree(base);
  const float sigma = p.fiberTwistSign;
  // The frame's convention first, then every alternative of notes A1 C5.
  std::vector<Convention> conventions = {{"frame", ftCoreTextureKPsi(p), FT_CORE_TEXTURE_K_PLY}};
  for (float mag : {0.5f, 1.0f})
    for (float sign : {1.0f, -1.0f})
      for (float kPly : {0.0f, 1.0f, -1.0f}) {
        const float k = mag * sign * sigma;
        if (k == conventions[0].kPsi && kPly == conventions[0].kPly) continue;
        conventions.push_back({fmt::format("k_psi={}{}σ_f k_ply={}", sign > 0 ? "+" : "-", mag, kPly), k, kPly});
      }
  std::vector<std::vector<double>> table(conventions.size());  // [convention][ψ]
  uint64_t nonFinite = 0;
  size_t texels = 0;
  for (double psiDeg : kPsiDegrees) {
    const double psi = psiDeg * kPi / 180.0;
    CoreTextureInput turned = base;
    for (glm::vec4& f : turned.fibers) f.y -= float(sigma * psi / (2.0 * kPi));  // θ_i − σ_f ψ/2π, phase kept
    const CoreTexture ref = bakeCoreTextureEmbree(turned);
    std::vector<double> refH;
    for (const glm::vec4& t : ref.tex0) refH.push_back(t.x);
    texels = refH.size();
    for (size_t c = 0; c < conventions.size(); ++c) {
      std::vector<double> h(refH.size());
      for (uint32_t j = 0; j < ref.height; ++j)
        for (uint32_t i = 0; i < ref.columns; ++i) {
          const float u = ftCoreTexelU(base.params, i), v = ftCoreTexelV(base.params, j);
          const float s = u * base.params.alpha;  // length along the ply
          const float uc = ftCoreTextureU(ftCoreBundlePhaseTurns(p, s, conventions[c].kPly), float(psi), conventions[c].kPsi);
          const CoreTexel t = sampleCoreTexture(tex, uc, v);
          if (!std::isfinite(t.tex0.x)) ++nonFinite;
          h[size_t(j) * ref.columns + i] = t.tex0.x;
        }
      table[c].push_back(ncc(refH, h));
    }
  }
  r.cpuMilliseconds = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();

  double frameWorst = 0.0, frameMean = 0.0, bestAlt = -2.0;
  int notBest = 0;
  for (size_t k = 1; k < table[0].size(); ++k) {
    bool best = std::isfinite(table[0][k]);
    for (size_t c = 1; c < conventions.size(); ++c) best = best && table[c][k] < table[0][k];
    notBest += best ? 0 : 1;
  }
  std::string bestAltName;
  for (size_t k = 0; k < table[0].size(); ++k) frameWorst = maxKeepNaN(frameWorst, 1.0 - table[0][k]);
  auto meanNonZero = [&](const std::vector<double>& v) { return (v[1] + v[2] + v[3]) / 3.0; };
  frameMean = meanNonZero(table[0]);
  for (size_t c = 1; c < conventions.size(); ++c) {
    const double m = meanNonZero(table[c]);
    if (std::isnan(m) || m > bestAlt) {
      bestAlt = m;
      bestAltName = conventions[c].name;
    }
  }
  r.metrics = {
      nonFiniteMetric("cpu", nonFinite, "looked-up texels"),
      Metric{"ncc.frame_one_minus_min", frameWorst, 0.1, "1 - NCC",
             "informational: notes A1 C5's NCC ≥ 0.9, out of reach where the fibers migrate (see above)", false},
      Metric{"rank.frame_not_best", double(notBest), 0.0, "count of ψ",
             "the frame's convention reads the explicit fibers best at each ψ = 30, 60, 90°"},
      Metric{"ncc.best_alternative_minus_frame", bestAlt - frameMean, kMarginTolerance, "NCC", kMarginWhy},
      Metric{"texels", double(texels), 0.0, "count", "texels compared per ψ", false},
  };
  std::string details = fmt::format("NCC of h vs the explicit core fibers at ψ = 0/30/60/90°, {}×{} texels:\n",
                                    FT_CORE_TEXTURE_WIDTH, FT_CORE_TEXTURE_HEIGHT);
  for (size_t c = 0; c < conventions.size(); ++c)
    details += fmt::format("  {:<28} (k_psi {:+.1f}, k_ply {:+.0f}): {:.3f} {:.3f} {:.3f} {:.3f}  mean(ψ≠0) {:.3f}\n",
                           conventions[c].name, conventions[c].kPsi, conventions[c].kPly, table[c][0], table[c][1],
                           table[c][2], table[c][3], meanNonZero(table[c]));
  details += fmt::format("best alternative: {} ({:.3f})", bestAltName, bestAlt);
  r.details = details;
  r.finish();
  return r;
}

}  // namespace

void addCoreTextureEq3Cases(ValidationContext& ctx, std::vector<ValidationCase>& out) {
  for (const YarnPreset* preset : ctx.presets()) {
    const std::string name = "appearance/core-texture/eq3/" + preset->name;
    out.push_back({name, [preset, name](ValidationContext& c) { return runEq3(c, *preset, name); }});
  }
}

}  // namespace ft
