#include "reference/ds_correction.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/dual_scattering.h"
#include "reference/dual_scattering.h"
#include "reference/fiber_reference.h"
#include "reference/fiber_trace.h"
#include "scene/camera.h"
#include "scene/fabric.h"
#include "scene/input_error.h"
#include "scene/lighting.h"
#include "scene/yarn_model.h"
#include "scene/yarn_radius.h"

namespace ft {

namespace {

void checkRange(const char* name, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi))
    throw InputError(fmt::format("ds-correction: {} {} is outside [{}, {}]", name, value, lo, hi));
}

// The camera stands this many periods away: the eye rays over the texture
// then spread by P/(1000 P) = 0.06°, against the narrowest lobe's 1°.
constexpr double kCameraDistancePeriods = 1000.0;

}  // namespace

void checkDsCorrectionSettings(const DsCorrectionSettings& s) {
  checkRange("--height", s.height, 1, 512);
  checkRange("--theta-samples", s.thetaSamples, 1, 64);
  checkRange("--phi-samples", s.phiSamples, 1, 64);
  checkRange("--pixels-per-texel", s.pixelsPerTexel, 1, 16);
  checkRange("--spp", s.samplesPerPixel, 1, 65536);
  checkRange("--max-depth", s.maxDepth, 1, 256);
  checkRange("--periods", s.periods, 3, 21);
  if (s.periods % 2 == 0) throw InputError(fmt::format("ds-correction: --periods {} must be odd (the middle one is baked)", s.periods));
  overrideYarnPreset(findYarnPreset(s.yarn), s.presetOverrides);
  findFabricPreset(s.fabric);
}

struct DsCorrectionScene::Impl {
  DsCorrectionSettings settings;
  DsCorrectionLayout layout{};
  std::unique_ptr<FiberTraceScene> scene;
  Camera camera;
  ShadingParams shading{};
  std::vector<glm::vec4> dsRows;  // the dual-scattering table (reference/dual_scattering.h)
  glm::vec3 axisPoint{0.0f};      // the yarn axis at the middle period's start
};

DsCorrectionScene::DsCorrectionScene(const DsCorrectionSettings& settings) : impl_(std::make_unique<Impl>()) {
  checkDsCorrectionSettings(settings);
  Impl& m = *impl_;
  m.settings = settings;
  // The yarn's regular fibers only: 001 bakes flyaways apart (§4.4).
  std::vector<std::string> overrides = settings.presetOverrides;
  overrides.insert(overrides.end(), {"hair_density=0", "loop_density=0"});
  const YarnPreset preset = overrideYarnPreset(findYarnPreset(settings.yarn), overrides);
  const double period = preset.yarnAlpha;
  const double outer = (preset.yarnRadius + std::max(preset.ellipseLong, preset.ellipseShort) * preset.rMax) * 1.05;
  const int nv = settings.height;
  const int nu = std::max(1, static_cast<int>(std::floor(nv * period / (2.0 * outer))));
  const double halfWidth = period * nv / (2.0 * nu);  // ≥ outer: square texels
  m.layout.size = glm::uvec4(nu, nv, settings.thetaSamples, settings.phiSamples);
  m.layout.yarn = glm::vec4(float(period), float(halfWidth), 0.0f, 0.0f);

  // A straight yarn along +x from 0, so that the length coordinate is x.
  YarnModel model;
  model.name = fmt::format("straight {} yarn", settings.yarn);
  YarnCurve curve;
  const int pointsPerPeriod = 16;
  for (int k = 0; k <= settings.periods * pointsPerPeriod; ++k)
    curve.points.emplace_back(float(k * period / pointsPerPeriod), 0.0f, 0.0f);
  model.curves.push_back(curve);
  const YarnBuffers buffers = buildYarnBuffers(model);

  FiberOptions fo;
  fo.allFibers = true;
  fo.maxSubdivisions = 32;
  const FittedFibers fibers = fitFibers(preset, 0.0, "the preset's own scale", fo);

  const double mid = (settings.periods / 2 + 0.5) * period;
  m.axisPoint = glm::vec3(float((settings.periods / 2) * period), 0.0f, 0.0f);
  const double distance = kCameraDistancePeriods * period;
  m.camera.eye = glm::vec3(float(mid), 0.0f, float(distance));
  m.camera.target = glm::vec3(float(mid), 0.0f, 0.0f);
  m.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  m.camera.width = nu * settings.pixelsPerTexel;
  m.camera.height = nv * settings.pixelsPerTexel;
  m.camera.fovyDegrees = float(2.0 * std::atan(halfWidth / distance) * 180.0 / M_PI);
  m.camera.zNear = float(distance - 4.0 * halfWidth);  // ray origins next to the yarn: no precision lost
  m.camera.zFar = float(distance + 4.0 * halfWidth);
  // Every fiber drawn at the subdivision cap (chord error 0), none culled.
  const ViewParams view = makeViewParams(m.camera, 1.0f, false, false, 0.0f);
  const std::vector<FrameNormal> frames = computeKnotFramesCpu(buffers);
  const FiberInput input{&buffers, &fibers.table, fibers.params, view};
  m.scene = std::make_unique<FiberTraceScene>(generateFibersCpu(input, frames), fibers.params);

  Lighting lighting;
  lighting.fabric = settings.fabric;
  lighting.lights = {DirectionalLight{glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(1.0f)}};
  lighting.ambient = glm::vec3(0.0f);
  lighting.diffuse = glm::vec3(0.0f);  // the BCSDF alone (notes §0.2): energy-conserving paths
  m.shading = makeShadingParams(lighting);
  m.dsRows = bakeDualScatteringCpu(m.shading.fabric).rows;
}

DsCorrectionScene::~DsCorrectionScene() = default;
DsCorrectionScene::DsCorrectionScene(DsCorrectionScene&&) noexcept = default;

const DsCorrectionSettings& DsCorrectionScene::settings() const { return impl_->settings; }
DsCorrectionLayout DsCorrectionScene::layout() const { return impl_->layout; }
int DsCorrectionScene::directionCount() const { return impl_->settings.thetaSamples * impl_->settings.phiSamples; }
size_t DsCorrectionScene::segmentCount() const { return impl_->scene->segmentCount(); }

// t × ω_o = x × z = −y.
glm::vec3 dsCorrectionLightDirection(float theta, float phi) {
  if (ftFaultXiBakeLightMirrored) phi = -phi;
  return glm::vec3(std::sin(theta), -std::cos(theta) * std::sin(phi), std::cos(theta) * std::cos(phi));
}

glm::vec3 DsCorrectionScene::lightDirection(int d) const {
  const int np = impl_->settings.phiSamples;
  return dsCorrectionLightDirection(ftXiThetaSample(d / np, impl_->settings.thetaSamples), ftXiPhiSample(d % np, np));
}

DsDirectionSums DsCorrectionScene::trace(int d) const {
  const Impl& m = *impl_;
  const size_t texels = size_t(m.layout.size.x) * m.layout.size.y;
  DsDirectionSums sums{std::vector<glm::dvec3>(texels, glm::dvec3(0.0)), std::vector<glm::dvec3>(texels, glm::dvec3(0.0)),
                       std::vector<glm::dvec3>(texels, glm::dvec3(0.0)), std::vector<double>(texels, 0.0)};
  ShadingParams s = m.shading;
  const glm::vec3 wd = lightDirection(d);
  s.lightDirection[0] = glm::vec4(wd, 0.0f);
  TraceOptions o;
  o.samplesPerPixel = m.settings.samplesPerPixel;
  o.shadows = true;
  o.multipleScattering = true;
  o.maxDepth = m.settings.maxDepth;
  o.seed = m.settings.seed + uint32_t(d) * 0x9E3779B9u;  // each direction its own streams
  const int pixelsPerTexel = m.settings.pixelsPerTexel;
  const int width = m.camera.width;
  // A texel spans pixelsPerTexel² pixels, maybe of different tiles (threads):
  // sum per pixel (TraceOptions::onHit runs on the pixel's thread), then per
  // texel in pixel order, so the sums do not depend on the thread count.
  const size_t pixels = size_t(width) * m.camera.height;
  std::vector<glm::dvec3> pixelRef(pixels, glm::dvec3(0.0)), pixelPsi(pixels, glm::dvec3(0.0)), pixelLocal(pixels, glm::dvec3(0.0));
  std::vector<uint32_t> pixelHits(pixels, 0);
  const FabricParams& fabric = s.fabric;
  o.onHit = [&](const TraceSample& h) {
    const FiberAngles a = ftFiberAngles(h.tangent, wd, h.wo);
    // The local part of eq. 8 at this sample, the runtime's (notes A7):
    // (f + d_b f_back^dir) cos θ_d, f_back^dir from the table at Zinke's
    // difference angle (ftDsThetaD), no flyaways (k_fly = 1).
    const glm::vec3 back = ftDsBackscatter(lookupDsCpu(m.dsRows, ftDsThetaD(a)), a, glm::vec3(0.0f));
    const glm::vec3 local = ftDsRuntime(ftBcsdf(fabric, a), back, 1.0f) * std::cos(a.thetaI);
    // The global part Ψ_G = V + (1 − V) T_f(n): n fibers crossed towards the
    // light, each passed forward at the light's own inclination θ_i to them
    // (a yarn's fibers run nearly parallel; forward scattering keeps θ).
    const uint32_t n = m.scene->fibersCrossed(h.position, wd, h.strip);
    const glm::vec3 psi = n == 0 ? glm::vec3(1.0f) : ftDsForwardTransmittance(lookupDsCpu(m.dsRows, a.thetaI), float(n));
    pixelRef[h.pixel] += glm::dvec3(h.radiance);
    pixelPsi[h.pixel] += glm::dvec3(psi);
    pixelLocal[h.pixel] += glm::dvec3(local);
    ++pixelHits[h.pixel];
  };
  traceFibers(*m.scene, m.camera, s, {}, o);
  // Texel of a pixel: the camera frames [kP, (k + 1)P] × [−W, W] exactly;
  // row 0 is at the top, y = +W, where v = 0 (v runs along t × ω_o = −y).
  for (size_t p = 0; p < pixels; ++p) {
    if (pixelHits[p] == 0) continue;
    const int x = int(p % width), y = int(p / width);
    const int i = x / pixelsPerTexel, j = y / pixelsPerTexel;
    const size_t texel = size_t(j) * m.layout.size.x + size_t(i);
    sums.reference[texel] += pixelRef[p];
    sums.shadowing[texel] += pixelPsi[p];
    sums.local[texel] += pixelLocal[p];
    sums.hits[texel] += pixelHits[p];
  }
  return sums;
}

std::vector<double> factorLogRankOne(std::span<const double> values, int nTheta, int nPhi) {
  std::vector<double> out(size_t(nTheta + nPhi), 0.0);
  double all = 0.0;
  for (int a = 0; a < nTheta; ++a)
    for (int b = 0; b < nPhi; ++b) {
      const double l = std::log(values[size_t(a * nPhi + b)]);
      out[size_t(a)] += l / nPhi;
      out[size_t(nTheta + b)] += l / nTheta;
      all += l / (double(nTheta) * nPhi);
    }
  for (int a = 0; a < nTheta; ++a) out[size_t(a)] = std::exp(out[size_t(a)]);
  for (int b = 0; b < nPhi; ++b) out[size_t(nTheta + b)] = std::exp(out[size_t(nTheta + b)] - all);
  return out;
}

std::vector<double> factorWeightedRankOne(std::span<const double> target, std::span<const double> basis,
                                          std::span<const double> weight, int nTheta, int nPhi, int iterations) {
  // Alternating least squares: with y fixed, x_a = Σ_b w T g y / Σ_b w g² y² (and
  // likewise for y); each step lowers the residual, and data ≥ 0 keep x, y ≥ 0.
  std::vector<double> x(size_t(nTheta), 1.0), y(size_t(nPhi), 1.0);
  const auto at = [&](std::span<const double> v, int a, int b) { return v[size_t(a * nPhi + b)]; };
  for (int it = 0; it < iterations; ++it) {
    for (int a = 0; a < nTheta; ++a) {
      double num = 0.0, den = 0.0;
      for (int b = 0; b < nPhi; ++b) {
        num += at(weight, a, b) * at(target, a, b) * at(basis, a, b) * y[size_t(b)];
        den += at(weight, a, b) * at(basis, a, b) * at(basis, a, b) * y[size_t(b)] * y[size_t(b)];
      }
      x[size_t(a)] = den > 0.0 ? num / den : 1.0;
    }
    for (int b = 0; b < nPhi; ++b) {
      double num = 0.0, den = 0.0;
      for (int a = 0; a < nTheta; ++a) {
        num += at(weight, a, b) * at(target, a, b) * at(basis, a, b) * x[size_t(a)];
        den += at(weight, a, b) * at(basis, a, b) * at(basis, a, b) * x[size_t(a)] * x[size_t(a)];
      }
      y[size_t(b)] = den > 0.0 ? num / den : 1.0;
    }
  }
  // The scale between the factors is free: give y a geometric mean of 1.
  double logMean = 0.0;
  for (double v : y) logMean += std::log(std::max(v, 1e-30)) / nPhi;
  const double k = std::exp(logMean);
  std::vector<double> out;
  for (double v : x) out.push_back(v * k);
  for (double v : y) out.push_back(v / k);
  return out;
}

namespace {

constexpr double kDarkEpsilon = 1e-7;
constexpr int kFitIterations = 64;

double channelSum(glm::dvec3 v) { return v.x + v.y + v.z; }

// Σ_c w_c (ftXiEncode(ξ corner c) + ftXiEncode(Ψ corner c)), as the GPU sums
// its log-encoded buffers: per corner first (the two cancel).
glm::vec3 fetchLog(const std::vector<glm::vec4>& xi, const std::vector<glm::vec4>& psi, const DsCorrectionLayout& l,
                   const XiLookup& q, glm::vec3 angle) {
  glm::vec3 sum(0.0f);
  for (int c = 0; c < 8; ++c) {
    const uint32_t i = ftXiCorner(l, q, angle, c);
    sum += ftXiCornerWeight(q, angle, c) * (ftXiEncode(glm::vec3(xi[i])) + ftXiEncode(glm::vec3(psi[i])));
  }
  return sum;
}

}  // namespace

glm::vec3 evaluateDsCorrectionCpu(const DsCorrectionTextures& t, glm::vec2 uv, glm::vec2 thetaPhi) {
  const XiLookup q = ftXiLookup(t.layout, uv, thetaPhi);
  return ftXiDecode(fetchLog(t.xiM, t.psiM, t.layout, q, q.theta) + fetchLog(t.xiN, t.psiN, t.layout, q, q.phi));
}

DsCorrectionTextures factorDsCorrection(const DsCorrectionLayout& l, std::span<const DsDirectionSums> directions,
                                        double samplesPerTexel) {
  const int nu = int(l.size.x), nv = int(l.size.y), nt = int(l.size.z), np = int(l.size.w);
  const size_t texels = size_t(nu) * nv;
  if (directions.size() != size_t(nt) * np)
    throw std::invalid_argument(fmt::format("factorDsCorrection: {} directions for {} x {}", directions.size(), nt, np));
  DsCorrectionTextures out;
  out.layout = l;
  out.xiM.assign(texels * nt, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f));
  out.psiM = out.xiM;
  out.xiN.assign(texels * np, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f));
  out.psiN = out.xiN;
  out.coverage.assign(texels, 0.0f);
  std::vector<double> psi(size_t(nt) * np), local(size_t(nt) * np), reference(size_t(nt) * np);
  // Each direction's squared residuals count relative to its mean radiance
  // (of the channel sum, as ξ is fitted to it): a light at grazing angles
  // lights the yarn ten times less, and unweighted it would barely move the fit.
  std::vector<double> directionWeight(directions.size(), 0.0);
  for (size_t d = 0; d < directions.size(); ++d) {
    double sum = 0.0, hits = 0.0;
    for (size_t texel = 0; texel < texels; ++texel) {
      sum += channelSum(directions[d].reference[texel]);
      hits += directions[d].hits[texel];
    }
    const double mean = hits > 0.0 ? sum / hits : 0.0;
    directionWeight[d] = mean > 0.0 ? 1.0 / (mean * mean) : 0.0;
  }
  for (size_t texel = 0; texel < texels; ++texel) {
    const double hits = directions[0].hits[texel];  // the same for every light: the camera's
    if (hits == 0.0) continue;
    // Ψ̄ per channel in the log domain (eq. 10's factorisation; exact for separable data).
    std::vector<double> fp[3];
    for (int c = 0; c < 3; ++c) {
      for (size_t d = 0; d < directions.size(); ++d) psi[d] = std::max(directions[d].shadowing[texel][c] / hits, kDarkEpsilon);
      fp[c] = factorLogRankOne(psi, nt, np);
      for (int a = 0; a < nt; ++a) out.psiM[size_t(a) * texels + texel][c] = float(fp[c][size_t(a)]);
      for (int b = 0; b < np; ++b) out.psiN[size_t(b) * texels + texel][c] = float(fp[c][size_t(nt + b)]);
    }
    // ξ, one factor for the three channels (docs/ds-correction.md "Why ξ is
    // grey"): ξ_M ξ_N so that ξ_M ξ_N Σ_c Ψ_M,c Ψ_N,c ḡ_c fits Σ_c L̄_*,c in
    // least squares; the colour is the dual-scattering prediction's. Fitted per
    // channel, ξ_c ≈ L_c / ḡ_c where ḡ is far in the tails of the BCSDF's
    // Gaussians, whose widths differ per channel: ratios of 1e3 between
    // channels, which the frame showed as coloured fireflies. A log fit of
    // L_*/(Ψ̄ ḡ) would weigh every direction alike, and where ḡ is small (off
    // the lobes) its ratios run into the thousands.
    for (size_t d = 0; d < directions.size(); ++d) {
      const int a = int(d) / np, b = int(d) % np;
      double predicted = 0.0;
      for (int c = 0; c < 3; ++c)
        predicted += fp[c][size_t(a)] * fp[c][size_t(nt + b)] * directions[d].local[texel][c] / hits;
      local[d] = predicted;
      reference[d] = channelSum(directions[d].reference[texel]) / hits;
    }
    const std::vector<double> fx = factorWeightedRankOne(reference, local, directionWeight, nt, np, kFitIterations);
    for (int c = 0; c < 3; ++c) {
      const double tint = ftFaultXiBakeNotGrey && c == 2 ? 2.0 : 1.0;  // planted: blue's ξ_M doubled
      for (int a = 0; a < nt; ++a) out.xiM[size_t(a) * texels + texel][c] = float(fx[size_t(a)] * tint);
      for (int b = 0; b < np; ++b) out.xiN[size_t(b) * texels + texel][c] = float(fx[size_t(nt + b)]);
    }
  }
  // The figures per direction, through the runtime's lookup at texel centres.
  out.meanXi.assign(directions.size(), 0.0);
  out.errorUncorrected.assign(directions.size(), 0.0);
  out.errorCorrected.assign(directions.size(), 0.0);
  out.totalCorrected.assign(directions.size(), 0.0);
  for (size_t d = 0; d < directions.size(); ++d) {
    const DsDirectionSums& s = directions[d];
    const glm::vec2 angles(ftXiThetaSample(int(d) / np, nt), ftXiPhiSample(int(d) % np, np));
    double ref = 0.0, errU = 0.0, errC = 0.0, predicted = 0.0, totalC = 0.0;
    for (size_t texel = 0; texel < texels; ++texel) {
      const double hits = s.hits[texel];
      if (hits == 0.0) continue;
      const glm::vec2 uv((float(texel % nu) + 0.5f) / nu, (float(texel / nu) + 0.5f) / nv);
      const glm::vec3 corr = evaluateDsCorrectionCpu(out, uv, angles);
      // Errors of the channel sum, the quantity ξ is fitted to (ξ is grey).
      double l = 0.0, dsPrediction = 0.0, runtime = 0.0;
      for (int c = 0; c < 3; ++c) {
        l += s.reference[texel][c];
        dsPrediction += s.shadowing[texel][c] * s.local[texel][c] / hits;
        // ξ_M ξ_N Ψ_M Ψ_N ḡ: the Ψ̄ of the texel is replaced by its factored form, as at run time.
        runtime += double(corr[c]) * s.local[texel][c];
      }
      ref += l;
      errU += std::abs(dsPrediction - l);
      errC += std::abs(runtime - l);
      totalC += runtime;
      predicted += dsPrediction;
    }
    out.meanXi[d] = predicted > 0.0 ? ref / predicted : 1.0;
    out.errorUncorrected[d] = ref > 0.0 ? errU / ref : 0.0;
    out.errorCorrected[d] = ref > 0.0 ? errC / ref : 0.0;
    out.totalCorrected[d] = ref > 0.0 ? std::abs(totalC - ref) / ref : 0.0;
  }
  for (size_t texel = 0; texel < texels; ++texel) out.coverage[texel] = float(directions[0].hits[texel] / samplesPerTexel);
  return out;
}

}  // namespace ft
