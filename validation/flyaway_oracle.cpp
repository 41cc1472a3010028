// The flyaway oracle: no include of common/ (see flyaway_oracle.h).
#include "validation/case_support.h"
#include "validation/flyaway_oracle.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

namespace ft::oracle {

namespace {

constexpr double kClampMass = 0.0013498980316301;  // Φ(−3): the mass ftNormal-style clamping moves to ±3σ

double phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

// Kolmogorov–Smirnov distance of a sample against a CDF.
double ksDistance(std::vector<double> x, const std::function<double(double)>& cdf) {
  if (x.empty()) return 1.0;
  std::sort(x.begin(), x.end());
  const double n = double(x.size());
  double d = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double f = cdf(x[i]);
    d = std::max({d, (i + 1) / n - f, f - i / n});
  }
  return d;
}

// KS critical distance at significance 1e-3 (1.95/√n), plus the clamp's atoms.
double ksTolerance(size_t n) { return 1.95 / std::sqrt(double(std::max<size_t>(n, 1))) + kClampMass + 1e-6; }

// E[g(X)] for X ~ N(μ, σ) clamped at μ ± 3σ (Simpson on [−3, 3], atoms at the ends).
double clampedNormalMean(double mu, double sigma, const std::function<double(double)>& g) {
  if (!(sigma > 0.0)) return g(mu);
  const int n = 4000;
  const double h = 6.0 / n;
  double s = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double z = -3.0 + i * h;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    s += w * g(mu + sigma * z) * std::exp(-0.5 * z * z) / std::sqrt(2.0 * kPi);
  }
  return s * h / 3.0 + kClampMass * (g(mu - 3.0 * sigma) + g(mu + 3.0 * sigma));
}

struct P3 {
  double x, y, z;
};
P3 point(const FlyawayCurve& c, size_t k) { return {c.xyz[3 * k], c.xyz[3 * k + 1], c.xyz[3 * k + 2]}; }
double radius(const P3& p) { return std::hypot(p.x, p.y); }

StatResult ksNormal(const std::string& name, const std::vector<double>& x, double mu, double sigma, const std::string& what) {
  // No draws (a preset without flyaways): nothing to test here; the counts say whether none were due.
  if (x.empty()) return {name, 0.0, 0.0, what + ": no draws (the count checks decide whether that is right)"};
  if (!(sigma > 0.0)) {
    double e = 0.0;
    for (double v : x) e = std::max(e, std::abs(v - mu));
    return {name, e / std::max(std::abs(mu), 1e-9), 1e-4, what + ": σ = 0, every draw must equal μ (relative)"};
  }
  return {name, ksDistance(x, [&](double v) { return phi((v - mu) / sigma); }), ksTolerance(x.size()),
          fmt::format("{}: KS distance against N({:.4g}, {:.4g}) clamped at ±3σ, n = {}; 1.95/√n (p = 1e-3) + Φ(−3)",
                      what, mu, sigma, x.size())};
}

StatResult ksUniform(const std::string& name, const std::vector<double>& x, double lo, double hi, const std::string& what) {
  if (x.empty()) return {name, 0.0, 0.0, what + ": no draws (the count checks decide whether that is right)"};
  return {name, ksDistance(x, [&](double v) { return std::clamp((v - lo) / (hi - lo), 0.0, 1.0); }),
          1.95 / std::sqrt(double(std::max<size_t>(x.size(), 1))),
          fmt::format("{}: KS distance against U[{:.4g}, {:.4g}), n = {}; 1.95/√n (p = 1e-3)", what, lo, hi, x.size())};
}

// Poisson counts: |mean − λ| in standard errors, and the dispersion var/mean.
void poissonChecks(std::vector<StatResult>& out, const std::string& name, const std::vector<double>& counts, double lambda,
                   const std::string& what) {
  const double n = double(counts.size());
  double mean = 0.0, var = 0.0;
  for (double c : counts) mean += c;
  mean /= n;
  for (double c : counts) var += (c - mean) * (c - mean);
  var /= std::max(1.0, n - 1.0);
  out.push_back({name + ".mean_z", std::abs(mean - lambda) / std::sqrt(std::max(lambda, 1e-12) / n), 4.0,
                 fmt::format("{}: |mean − λ| / √(λ/n), mean {:.3f}, λ = {:.3f}, n = {} patterns; 4 standard errors", what,
                             mean, lambda, counts.size())});
  if (lambda > 0.0)
    out.push_back({name + ".dispersion_z", std::abs(var / std::max(mean, 1e-12) - 1.0) / std::sqrt(2.0 / std::max(1.0, n - 1.0)),
                   4.0,
                   fmt::format("{}: |var/mean − 1| over its sampling sd √(2/(n−1)), var/mean {:.3f}; 4 sd (Poisson: 1)",
                               what, var / std::max(mean, 1e-12))});
}

}  // namespace

std::vector<StatResult> flyawayStatistics(const FlyawayModel& m, const std::vector<FlyawayCurve>& curves, int patterns,
                                          std::string& details) {
  std::vector<double> r0, re, ze, pe, th0, z0B, z0I;
  double shapeErr = 0.0, thetaErr = 0.0, zErr = 0.0, halfErr = 0.0;
  std::map<std::pair<int, int>, double> present, kept;
  size_t malformed = 0;
  for (const FlyawayCurve& c : curves) {
    if (c.xyz.empty()) continue;
    if (c.xyz.size() < 6 || c.xyz.size() % 3) {
      ++malformed;
      continue;
    }
    const size_t n = c.xyz.size() / 3 - 1;
    present[{c.pattern, c.set}] += 1.0;
    const P3 a = point(c, 0), b = point(c, n);
    const double R0 = radius(a), R1 = radius(b);
    r0.push_back(R0 - m.rootOffset);
    (c.set == 0 ? z0B : z0I).push_back(a.z);
    ze.push_back(b.z - a.z);
    double zmin = a.z, zmax = a.z;
    for (size_t k = 0; k <= n; ++k) zmin = std::min(zmin, point(c, k).z), zmax = std::max(zmax, point(c, k).z);
    const bool keep = c.set == 0 ? (zmin < 0.0 && zmax >= 0.0 && zmax - zmin < m.period - 2.0 * m.margin)
                                 : (zmin >= m.margin && zmax <= m.period - m.margin);
    if (keep) kept[{c.pattern, c.set}] += 1.0;
    // R stays positive (so θ is defined) when R_0 + (μ_e − 3σ_e) > 0: a
    // condition on R_0 alone, independent of R_e, so R_e's law is unchanged.
    if (!(R0 > 1e-6 && R0 + m.reMu - 3.0 * m.reSigma > 1e-6 * std::max(1.0, R0))) continue;
    th0.push_back(std::fmod(std::atan2(a.y, a.x) + 2.0 * kPi, 2.0 * kPi));
    const double Re = R1 - R0;
    re.push_back(Re);
    double theta = 0.0;
    std::vector<double> thetas{0.0};
    for (size_t k = 1; k <= n; ++k) {
      const P3 p = point(c, k), q = point(c, k - 1);
      double d = std::atan2(p.y, p.x) - std::atan2(q.y, q.x);
      d = std::remainder(d, 2.0 * kPi);
      theta += d;
      thetas.push_back(theta);
    }
    pe.push_back(theta);
    // Eq. 12–13 along the curve: R(t) = R_0 + R_e (1 − (1 − t)^α), θ and z linear in t.
    const double scale = std::max(std::abs(Re) + R0, 1e-9);
    for (size_t k = 0; k <= n; ++k) {
      const double t = double(k) / double(n);
      const P3 p = point(c, k);
      shapeErr = std::max(shapeErr, std::abs(radius(p) - (R0 + Re * (1.0 - std::pow(1.0 - t, m.alpha)))) / scale);
      thetaErr = std::max(thetaErr, std::abs(thetas[k] - theta * t));
      zErr = std::max(zErr, std::abs(p.z - (a.z + (b.z - a.z) * t)) / m.period);
    }
    if (n % 2 == 0 && std::abs(Re) > 0.05 * R0) {
      const double q = (radius(point(c, n / 2)) - R0) / Re;
      halfErr = std::max(halfErr, std::abs(q - (1.0 - std::pow(0.5, m.alpha))));
    }
  }
  std::vector<StatResult> out;
  out.push_back({"curves.malformed", double(malformed), 0.0, "curves without whole points: never"});
  out.push_back(ksNormal("r0_ks", r0, m.r0Mu, m.r0Sigma, "R_0 − ply offset = Zhao's r_0"));
  out.push_back(ksNormal("re_ks", re, m.reMu, m.reSigma, "R_e = R(1) − R(0) (eq. 13 at t = 1)"));
  out.push_back(ksNormal("ze_ks", ze, m.zeMu, m.zeSigma, "z_e = z(1) − z(0) (eq. 12)"));
  out.push_back(ksNormal("pe_ks", pe, m.peMu, m.peSigma, "θ_e = unwrapped θ(1) − θ(0) (eq. 12)"));
  out.push_back(ksUniform("theta0_ks", th0, 0.0, 2.0 * kPi, "θ_0 = atan2(y, x) at t = 0 (orientation)"));
  out.push_back(ksUniform("z0_boundary_ks", z0B, -m.zReach, m.zReach, "z_0 of boundary candidates"));
  out.push_back(ksUniform("z0_interior_ks", z0I, 0.0, m.period, "z_0 of interior candidates"));
  out.push_back({"shape.max_rel", shapeErr, 1e-4,
                 fmt::format("max over points |R(t) − (R_0 + R_e (1 − (1 − t)^α))| / (|R_e| + R_0), α = {}: float points, 1e-4", m.alpha)});
  out.push_back({"alpha.half_max_abs", halfErr, 1e-3,
                 "eq. 13's curvature at t = ½: (R(½) − R_0)/R_e = 1 − 2^−α, curves with |R_e| > 0.05 R_0; float points"});
  out.push_back({"theta.linear_max_rad", thetaErr, 1e-4, "θ(t) − θ_0 = θ_e t (eq. 12): float atan2 of float points"});
  out.push_back({"z.linear_max_rel", zErr, 1e-5, "z(t) − z_0 = z_e t (eq. 12), over P: float points"});
  // Counts per pattern: candidates Poisson(ρ · length), kept ones thinned.
  std::vector<double> cB, cI, kB, kI;
  for (int p = 0; p < patterns; ++p) {
    cB.push_back(present[{p, 0}]);
    kB.push_back(kept[{p, 0}]);
    for (int s = 1; s <= 3; ++s) cI.push_back(present[{p, s}]), kI.push_back(kept[{p, s}]);
  }
  const double lB = m.densityPerLength * 2.0 * m.zReach, lI = m.densityPerLength * m.period;
  poissonChecks(out, "count.boundary", cB, lB, "boundary candidates per pattern, ρ·2Z");
  poissonChecks(out, "count.interior", cI, lI, "interior candidates per layer, ρ·P");
  const double span = m.period - 2.0 * m.margin;
  const double eKB = m.densityPerLength * clampedNormalMean(m.zeMu, m.zeSigma, [&](double v) { return std::abs(v) < span ? std::abs(v) : 0.0; });
  const double eKI = m.densityPerLength * clampedNormalMean(m.zeMu, m.zeSigma, [&](double v) { return std::max(0.0, span - std::abs(v)); });
  std::vector<StatResult> keptStats;
  poissonChecks(keptStats, "kept.boundary", kB, eKB, "boundary curves crossing z = 0 per pattern, ρ E|z_e|");
  poissonChecks(keptStats, "kept.interior", kI, eKI, "interior curves inside [m, P − m] per layer, ρ E max(0, P − 2m − |z_e|)");
  for (StatResult& s : keptStats)
    if (s.name.find("mean_z") != std::string::npos) out.push_back(s);  // thinned Poisson: the mean is the claim
  details = fmt::format("n: R_0 {}, R_e {}, θ_e {}; λ_B {:.2f}, λ_I {:.2f}, E kept B {:.2f}, I {:.2f}", r0.size(), re.size(),
                        pe.size(), lB, lI, eKB, eKI);
  return out;
}

std::vector<StatResult> flyawayNoiseStatistics(const FlyawayModel& m, const std::vector<FlyawayCurve>& clean,
                                               const std::vector<FlyawayCurve>& noisy) {
  std::vector<double> v;
  double maxAbs = 0.0;
  size_t mismatched = 0;
  for (size_t i = 0; i < clean.size() && i < noisy.size(); ++i) {
    const FlyawayCurve &c = clean[i], &q = noisy[i];
    if (c.xyz.size() != q.xyz.size()) {
      ++mismatched;
      continue;
    }
    if (c.xyz.empty()) continue;
    const size_t n = c.xyz.size() / 3 - 1;
    for (size_t k = 1; k <= n; ++k) {
      const P3 c0 = point(c, k - 1), c1 = point(c, k), n0 = point(q, k - 1), n1 = point(q, k);
      const double L = std::sqrt((c1.x - c0.x) * (c1.x - c0.x) + (c1.y - c0.y) * (c1.y - c0.y) + (c1.z - c0.z) * (c1.z - c0.z));
      if (!(L > 1e-3 * m.period)) continue;  // float differences would dominate a step this short
      const double inc[3] = {(n1.x - c1.x) - (n0.x - c0.x), (n1.y - c1.y) - (n0.y - c0.y), (n1.z - c1.z) - (n0.z - c0.z)};
      for (double d : inc) {
        v.push_back(d / (L * m.noise));
        maxAbs = std::max(maxAbs, std::abs(v.back()));
      }
    }
  }
  if (clean.size() != noisy.size()) mismatched += std::max(clean.size(), noisy.size()) - std::min(clean.size(), noisy.size());
  double var = 0.0;
  for (double x : v) var += x * x;
  var /= std::max<size_t>(v.size(), 1);
  std::vector<StatResult> out;
  out.push_back({"noise.slots_mismatched", double(mismatched), 0.0, "the noisy run draws the same candidates: never"});
  out.push_back({"noise.sd_z", std::abs(std::sqrt(var) - 1.0) / (0.5 * std::sqrt(0.8 / std::max<size_t>(v.size(), 1))), 4.0,
                 fmt::format("sd of step increments / (σ_n L) = {:.4f} vs 1 (U[−√3, √3]), n = {}; 4 sampling sd "
                             "(var of X² for the uniform: 0.8)",
                             std::sqrt(var), v.size())});
  out.push_back({"noise.max_over_sqrt3", maxAbs / std::sqrt(3.0), 1.0 + 2e-3,
                 "largest |increment| / (σ_n L √3): the uniform's bound; float points (2e-3)"});
  out.push_back(ksUniform("noise.ks", v, -std::sqrt(3.0), std::sqrt(3.0), "step increments / (σ_n L)"));
  return out;
}

OracleTexel decodeFlyawayTexel(uint32_t rgba) {
  OracleTexel t;
  const double a = double((rgba >> 24) & 255u) / 255.0;
  t.covered = a >= 0.5;
  for (int c = 0; c < 3; ++c) t.t[c] = 2.0 * double((rgba >> (8 * c)) & 255u) / 255.0 - 1.0;
  return t;
}

double angleBetweenDeg(const double a[3], const double b[3]) {
  const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  if (!(la > 0 && lb > 0)) return 180.0;
  const double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / kPi;
}

std::vector<OracleTexel> flyawayRaster(const FlyawayModel& m, const std::vector<FlyawayCurve>& curves,
                                       const std::vector<int>& layers, const std::vector<double>& columnZ) {
  // The geometry of a yarn made of the given layers: B at every period
  // boundary n P (n = 0 … layers), I_{layers[n]} at n P.
  struct Drawn {
    const FlyawayCurve* c;
    double shift;
  };
  std::vector<Drawn> drawn;
  for (const FlyawayCurve& c : curves) {
    if (c.pattern != 0 || c.xyz.empty()) continue;
    const size_t n = c.xyz.size() / 3;
    double zmin = 1e300, zmax = -1e300;
    for (size_t k = 0; k < n; ++k) zmin = std::min(zmin, c.xyz[3 * k + 2]), zmax = std::max(zmax, c.xyz[3 * k + 2]);
    if (c.set == 0) {
      if (!(zmin < 0.0 && zmax >= 0.0 && zmax - zmin < m.period - 2.0 * m.margin)) continue;
      for (size_t b = 0; b <= layers.size(); ++b) drawn.push_back({&c, double(b) * m.period});
    } else {
      if (!(zmin >= m.margin && zmax <= m.period - m.margin)) continue;
      for (size_t b = 0; b < layers.size(); ++b)
        if (layers[b] + 1 == c.set) drawn.push_back({&c, double(b) * m.period});
    }
  }
  std::vector<OracleTexel> out(size_t(m.height) * columnZ.size());
  const double h2 = m.lineHalfWidth * m.lineHalfWidth;
  for (int j = 0; j < m.height; ++j) {
    const double y = (2.0 * (j + 0.5) / m.height - 1.0) * m.halfWidth;
    for (size_t i = 0; i < columnZ.size(); ++i) {
      const double z = columnZ[i];
      bool found = false;
      double bestX = 0.0, d[3] = {0, 0, 0};
      for (const Drawn& dr : drawn) {
        const size_t n = dr.c->xyz.size() / 3;
        for (size_t k = 0; k + 1 < n; ++k) {
          const P3 a = point(*dr.c, k), b = point(*dr.c, k + 1);
          const double az = a.z + dr.shift, bz = b.z + dr.shift;
          const double ey = b.y - a.y, ez = bz - az, ee = ey * ey + ez * ez;
          const double s = ee > 0.0 ? std::clamp(((y - a.y) * ey + (z - az) * ez) / ee, 0.0, 1.0) : 0.0;
          const double dy = y - (a.y + s * ey), dz = z - (az + s * ez);
          if (dy * dy + dz * dz > h2) continue;
          const double x = a.x + s * (b.x - a.x);
          if (!found || x > bestX) found = true, bestX = x, d[0] = ez, d[1] = ey, d[2] = b.x - a.x;
        }
      }
      // The regular fibers' envelope hides what lies behind its front surface.
      if (!found || (std::abs(y) < m.bodyRadius && bestX < std::sqrt(m.bodyRadius * m.bodyRadius - y * y))) continue;
      OracleTexel& t = out[size_t(j) * columnZ.size() + i];
      t.covered = true;
      const double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), sg = d[0] < 0.0 ? -1.0 : 1.0;
      for (int c = 0; c < 3; ++c) t.t[c] = l > 0 ? sg * d[c] / l : 0.0;
    }
  }
  return out;
}

}  // namespace ft::oracle
