// The DS correction bake's pieces that need no path tracing
// (reference/ds_correction.h, common/ds_correction.h; 001 §4.3 eq. 9–11,
// notes-rendering A7): the two rank-1 fits on separable data (C3), the whole
// factorisation + lookup chain on synthetic separable sums (the runtime
// reproduces them exactly), the bake's light convention tied to the runtime's
// angles, the grey ξ keeping the prediction's colour, and the file's round
// trip and refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "reference/ds_correction.h"
#include "scene/input_error.h"
#include "scene/lighting.h"
#include "scene/shading_inputs.h"
#include "scene/yarn_preset.h"
#include "scene/yarn_radius.h"

namespace ft {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(DsCorrection, LogRankOneIsExactOnSeparableData) {
  const int nt = 5, np = 7;
  std::vector<double> v(size_t(nt * np));
  for (int a = 0; a < nt; ++a)
    for (int b = 0; b < np; ++b) v[size_t(a * np + b)] = (0.5 + a) * std::exp(std::sin(b));
  const std::vector<double> f = factorLogRankOne(v, nt, np);
  for (int a = 0; a < nt; ++a)
    for (int b = 0; b < np; ++b) EXPECT_NEAR(f[size_t(a)] * f[size_t(nt + b)] / v[size_t(a * np + b)], 1.0, 1e-12);
}

TEST(DsCorrection, WeightedRankOneIsExactOnSeparableData) {
  const int nt = 4, np = 6;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.01, 2.0);
  std::vector<double> target(size_t(nt * np)), basis(target.size()), weight(target.size());
  for (int a = 0; a < nt; ++a)
    for (int b = 0; b < np; ++b) {
      const size_t i = size_t(a * np + b);
      basis[i] = u(rng);
      weight[i] = u(rng);
      target[i] = (1.0 + a * a) * (3.0 - 0.4 * b) * basis[i];
    }
  const std::vector<double> f = factorWeightedRankOne(target, basis, weight, nt, np, 64);
  for (int a = 0; a < nt; ++a)
    for (int b = 0; b < np; ++b)
      EXPECT_NEAR(f[size_t(a)] * f[size_t(nt + b)] * basis[size_t(a * np + b)] / target[size_t(a * np + b)], 1.0, 1e-9);
}

// Sums whose L_* = k_M(a) k_N(b) c(texel) Ψ̄ ḡ with separable Ψ̄: the runtime's
// ξ_M ξ_N Ψ_M Ψ_N ḡ, read through the shared lookup at the texel centres,
// must give L_* back (the pixel → texel → lookup chain).
namespace {

// Synthetic sums of a 4 × 4 direction grid over `texels` texels: fill(a, b, texel, sums).
template <class Fill>
std::vector<DsDirectionSums> syntheticDirections(size_t texels, Fill fill) {
  std::vector<DsDirectionSums> dirs;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      DsDirectionSums s{std::vector<glm::dvec3>(texels), std::vector<glm::dvec3>(texels), std::vector<glm::dvec3>(texels),
                        std::vector<double>(texels, 0.0)};
      for (size_t t = 0; t < texels; ++t) fill(a, b, t, s);
      dirs.push_back(s);
    }
  return dirs;
}

}  // namespace

TEST(DsCorrection, FactoredTexturesReproduceSeparableSums) {
  DsCorrectionLayout l{};
  l.size = glm::uvec4(6, 3, 4, 4);
  l.yarn = glm::vec4(0.45f, 0.07f, 0.0f, 0.0f);
  const size_t texels = 18;
  const std::vector<DsDirectionSums> dirs = syntheticDirections(texels, [](int a, int b, size_t t, DsDirectionSums& s) {
    if (t == 7) return;  // one texel no sample hits
    const double hits = 3.0 + double(t % 4);
    const double psi = (0.2 + 0.2 * a) * (0.9 - 0.1 * b) * (0.5 + 0.02 * double(t));
    const double g = 0.3 + 0.1 * a + 0.05 * double((b * 7 + int(t)) % 5);  // not separable
    const double k = (1.0 + a) * (2.0 - 0.3 * b) * (1.0 + 0.1 * double(t));
    s.hits[t] = hits;
    s.shadowing[t] = glm::dvec3(psi * hits, 0.5 * psi * hits, psi * hits);
    s.local[t] = glm::dvec3(g * hits);
    s.reference[t] = glm::dvec3(k * psi * g * hits, 0.5 * k * psi * g * hits, 2.0 * k * psi * g * hits);
  });
  const DsCorrectionTextures t = factorDsCorrection(l, dirs, 16.0);
  for (size_t d = 0; d < dirs.size(); ++d) {
    EXPECT_LT(t.errorCorrected[d], 1e-5) << "direction " << d;
    EXPECT_LT(t.totalCorrected[d], 1e-5) << "direction " << d;
  }
  EXPECT_EQ(t.coverage[7], 0.0f);
  EXPECT_EQ(t.xiM[7], glm::vec4(1.0f, 1.0f, 1.0f, 0.0f));
  EXPECT_FLOAT_EQ(t.coverage[3], 6.0f / 16.0f);
}

// ξ is one factor for the three channels, fitted to their sum
// (docs/ds-correction.md "Why ξ is grey"); the colour is the prediction's
// Ψ_c ḡ_c. Data whose correction is grey and separable, with coloured Ψ and
// ḡ: every channel is reproduced through the lookup, and ξ's rgb are equal.
TEST(DsCorrection, GreyXiKeepsThePredictionsColour) {
  DsCorrectionLayout l{};
  l.size = glm::uvec4(5, 2, 4, 4);
  l.yarn = glm::vec4(0.45f, 0.07f, 0.0f, 0.0f);
  const size_t texels = 10;
  const std::vector<DsDirectionSums> dirs = syntheticDirections(texels, [](int a, int b, size_t t, DsDirectionSums& s) {
    const double hits = 4.0;
    const glm::dvec3 psi = glm::dvec3(0.3 + 0.15 * a, 0.2 + 0.1 * a, 0.5) * (1.0 - 0.2 * b) * (0.6 + 0.03 * double(t));
    const glm::dvec3 g(0.2 + 0.1 * a + 0.04 * double((b * 3 + int(t)) % 4), 0.05 + 0.02 * b, 0.7 - 0.1 * a);
    const double k = (0.5 + a) * (3.0 - 0.5 * b) * (1.0 + 0.05 * double(t));
    s.hits[t] = hits;
    s.shadowing[t] = psi * hits;
    s.local[t] = g * hits;
    s.reference[t] = k * psi * g * hits;
  });
  const DsCorrectionTextures t = factorDsCorrection(l, dirs, 16.0);
  for (const std::vector<glm::vec4>* xi : {&t.xiM, &t.xiN})
    for (const glm::vec4& x : *xi) {
      EXPECT_EQ(x.x, x.y);
      EXPECT_EQ(x.x, x.z);
    }
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      for (size_t k = 0; k < texels; ++k) {
        const glm::vec2 uv((float(k % 5) + 0.5f) / 5.0f, (float(k / 5) + 0.5f) / 2.0f);
        const glm::vec3 corr = evaluateDsCorrectionCpu(t, uv, glm::vec2(ftXiThetaSample(a, 4), ftXiPhiSample(b, 4)));
        const DsDirectionSums& s = dirs[size_t(a * 4 + b)];
        for (int c = 0; c < 3; ++c) {
          const double want = s.reference[k][c] / s.hits[k], got = double(corr[c]) * s.local[k][c] / s.hits[k];
          EXPECT_NEAR(got / want, 1.0, 1e-4) << "direction " << a << "," << b << " texel " << k << " channel " << c;
        }
      }
}

TEST(DsCorrection, BakeLightConventionMatchesTheRuntimeAngles) {
  const glm::vec3 t(1.0f, 0.0f, 0.0f), wo(0.0f, 0.0f, 1.0f);
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b) {
      const float theta = ftXiThetaSample(a, 8), phi = ftXiPhiSample(b, 8);
      const glm::vec2 got = ftXiRelativeAngles(t, dsCorrectionLightDirection(theta, phi), wo);
      EXPECT_NEAR(got.x, theta, 1e-6);
      EXPECT_NEAR(std::remainder(double(got.y) - phi, 2 * kPi), 0.0, 1e-6);
    }
}

TEST(DsCorrection, FileRoundTripAndRefusals) {
  DsCorrectionTextures t;
  t.layout.size = glm::uvec4(2, 2, 2, 3);
  t.layout.yarn = glm::vec4(0.5f, 0.1f, 0.0f, 0.0f);
  for (int k = 0; k < 8; ++k) t.xiM.push_back(glm::vec4(1.0f + k, 2.0f, 3.0f, 0.0f));
  for (int k = 0; k < 12; ++k) t.xiN.push_back(glm::vec4(0.5f * k, 1.0f, 1.0f, 0.0f));
  t.psiM = t.xiM;
  t.psiN = t.xiN;
  t.coverage = {0.0f, 0.5f, 1.0f, 0.25f};
  const std::filesystem::path p = std::filesystem::temp_directory_path() / "ft_ds_correction_test.bin";
  writeDsCorrection(p, t, "{\"spp\": 4}");
  const DsCorrectionTextures r = readDsCorrection(p);
  EXPECT_EQ(r.layout.size, t.layout.size);
  EXPECT_EQ(r.xiN, t.xiN);
  EXPECT_EQ(r.coverage, t.coverage);
  // Truncated: the message names the file and the array.
  std::filesystem::resize_file(p, std::filesystem::file_size(p) - 4);
  try {
    readDsCorrection(p);
    FAIL() << "a truncated file was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("coverage is truncated"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
  }
  std::ofstream(p) << "not json\n";
  EXPECT_THROW(readDsCorrection(p), InputError);
  std::filesystem::remove(p);
}

TEST(DsCorrection, SettingsOutOfRangeAreRefused) {
  DsCorrectionSettings s;
  s.periods = 4;
  EXPECT_THROW(checkDsCorrectionSettings(s), InputError);
  s = {};
  s.height = 0;
  EXPECT_THROW(checkDsCorrectionSettings(s), InputError);
  s = {};
  s.yarn = "no-such-yarn";
  EXPECT_THROW(checkDsCorrectionSettings(s), InputError);
}

}  // namespace
// The frame's reading of a bake (scene/shading_inputs.h frameDsCorrection):
// P and W scaled to the fitted preset, rim texels under half coverage not
// applied, a bake for another yarn or fabric refused, identity without a file.
TEST(DsCorrection, FrameInputs) {
  const YarnPreset own = findYarnPreset("cotton1");
  const YarnPreset fitted = scaleYarnPreset(own, 3.0);
  Lighting l;
  l.fabric = "cotton";
  ShadingInputs in;
  in.params = makeShadingParams(l);
  AppearanceOptions o = AppearanceOptions::none();
  o.dualScattering = true;
  frameDsCorrection(in, &fitted, o);
  EXPECT_EQ(in.params.flags.w, FT_APPEARANCE_DUAL_SCATTERING);
  ASSERT_EQ(in.xiM.size(), 1u);
  EXPECT_EQ(in.psiN[0], glm::vec4(1, 1, 1, 0));

  DsCorrectionTextures t;
  t.layout.size = glm::uvec4(2, 1, 1, 1);
  t.layout.yarn = glm::vec4(float(own.yarnAlpha), 0.25f, 0.0f, 0.0f);
  t.xiM = {glm::vec4(2, 2, 2, 0), glm::vec4(5, 5, 5, 0)};
  t.xiN = t.psiM = t.psiN = {glm::vec4(1, 1, 1, 0), glm::vec4(7, 7, 7, 0)};
  t.coverage = {1.0f, 0.2f};  // texel 1 is a rim texel
  const std::filesystem::path p = std::filesystem::temp_directory_path() / "ft_ds_correction_frame_test.bin";
  writeDsCorrection(p, t, R"({"yarn": "cotton1", "fabric": "cotton"})");
  o.dsCorrectionFile = p;
  ShadingInputs a;
  a.params = in.params;
  frameDsCorrection(a, &fitted, o);
  EXPECT_EQ(a.params.flags.w, FT_APPEARANCE_DUAL_SCATTERING | FT_APPEARANCE_DS_CORRECTION);
  EXPECT_NEAR(a.dsCorrection.yarn.x, 3.0 * own.yarnAlpha, 1e-5 * own.yarnAlpha);
  EXPECT_NEAR(a.dsCorrection.yarn.y, 0.75f, 1e-6f);
  EXPECT_EQ(a.xiM[0], glm::vec4(2, 2, 2, 0));
  EXPECT_EQ(a.xiM[1], glm::vec4(1, 1, 1, 0));
  EXPECT_EQ(a.psiN[1], glm::vec4(1, 1, 1, 0));
  // Another yarn or another fabric: refused, naming the option and the file.
  const YarnPreset other = findYarnPreset("rayon2");
  ShadingInputs b;
  b.params = in.params;
  try {
    frameDsCorrection(b, &other, o);
    FAIL() << "a bake for another yarn was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--ds-correction"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
  }
  Lighting silk;
  silk.fabric = "silk";
  b.params = makeShadingParams(silk);
  EXPECT_THROW(frameDsCorrection(b, &fitted, o), InputError);
  o.dsCorrectionFile = std::filesystem::path("/nonexistent/xi.bin");
  EXPECT_THROW(frameDsCorrection(b, &fitted, o), InputError);
  std::filesystem::remove(p);
}

}  // namespace ft
