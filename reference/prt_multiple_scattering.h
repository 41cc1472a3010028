// prt_multiple_scattering.h — the CPU reference of local multiple scattering
// of Khungurn et al. 2017 (004) §4.2, §4.3, §5.3.1 (common/
// prt_multiple_scattering.h for the conventions; docs/prt-multiple-scattering.md):
//   * prtMsTablesCpu: C_S and C_G in double (common/'s quadrature);
//   * IirtfScene + iirtfSegmentSum / iirtfCellCpu: the IIRTF A_C by path
//     tracing through the tiled exemplar (Embree, the BCSDF importance
//     sampling of reference/bcsdf_sampling.h, next-event estimation to the
//     directional light, Russian roulette after 3 bounces) and the estimator
//     of 004 §4.2c;
//   * prtMsRadianceCpu: L̃^multi of one query (004 §5.3.1) in double;
//   * prtMsVgloFilterCpu / prtMsVgloSampleCpu: V̄_glo (004 §5.3.2), the
//     normalised Gaussian filter of a V_glo grid and 004's CPU Monte Carlo.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "common/prt_multiple_scattering.h"
#include "reference/exemplar.h"

namespace ft {

// Planted fault (validation/faults.def), CPU only: the IIRTF bake's standard error without the
// stratification factor 1/|C| (reference/prt_multiple_scattering.cpp, iirtfCellCpu).
inline bool ftFaultMsStderrCellCount = false;
#define FT_FAULT_MS_STDERR_CELL_COUNT_ON ::ft::ftFaultMsStderrCellCount

// ---- tables (004 §4.3) --------------------------------------------------------
struct PrtMsTables {
  int thetaO = FT_MS_THETA_O, lambdaNodes = FT_MS_LAMBDA_NODES;
  std::vector<double> cs;  // [θ_o][j][rgb]: thetaO × 36 × 3
  std::vector<double> cg;  // [λ node][l]: lambdaNodes × FT_SH_BANDS
};
// Throws InputError for node counts < 2 (naming them).
PrtMsTables prtMsTablesCpu(const FabricParams& fabric, int thetaINodes = FT_MS_THETA_I_NODES,
                           int phiNodes = FT_MS_PHI_NODES);
// Φ_p,j(θ_i) of pass 0: [lobe 0 R, 1 TT][θ_i][j] (exposed for the GPU cross-check).
std::vector<double> prtMsPhiCpu(const FabricParams& fabric, int thetaINodes, int phiNodes);

// ---- the IIRTF (004 §4.2) -----------------------------------------------------
// An IIRTF matrix: [channel][j1][j0], 36 × 36 per channel (entry a[j0, j1]
// of 004 §4.2a at row j1, column j0: c_T = A c_d).
inline constexpr size_t kIirtfMatrixSize = size_t(3) * FT_SH_COEFFS * FT_SH_COEFFS;
// The band max(l1, l0) of entry i of an IIRTF matrix (or of concatenated matrices): j = l(l + 1) + m.
inline int iirtfEntryBand(size_t i) {
  const size_t e = i % (size_t(FT_SH_COEFFS) * FT_SH_COEFFS);
  const auto band = [](size_t j) { return int(std::sqrt(double(j) + 0.5)); };
  return std::max(band(e / FT_SH_COEFFS), band(e % FT_SH_COEFFS));
}

// Embree scene of the tiled exemplar (round linear curves); rays ignore one
// fiber (the one they leave: 004 §4.1's rule for segment visibility, kept
// for every ray here [F]).
class IirtfScene {
 public:
  // Throws InputError naming a degenerate segment, std::runtime_error when Embree fails.
  explicit IirtfScene(std::span<const ExemplarSegment> tiled);
  ~IirtfScene();
  IirtfScene(IirtfScene&&) noexcept;
  IirtfScene& operator=(IirtfScene&&) noexcept;
  struct Hit {
    float t = 0.0f;
    uint32_t segment = 0;
    glm::vec3 normal{0.0f};  // geometric, unit
  };
  bool intersect(glm::vec3 org, glm::vec3 dir, uint32_t ignoreFiber, Hit& hit) const;
  bool occluded(glm::vec3 org, glm::vec3 dir, uint32_t ignoreFiber) const;
  // The light of an infinite flat fabric reaches p from ω0 only through its top face [F]: true
  // when the ray leaves the tiled copies' box through a side below their top (it would cross
  // fabric beyond the tiling), or ω0 points down.
  bool entersThroughSide(glm::vec3 p, glm::vec3 w0) const;
  const std::vector<ExemplarSegment>& segments() const;
  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

struct IirtfSettings {
  int tiles = 5;              // N × N tiling; the cells are those of the centre copy
  double cellFactor = 1.0;    // ℓ̃ = cellFactor · ℓ (004 §4.2: ℓ … 2ℓ)
  double cellSize = 0.0;      // > 0: ℓ̃ in fabric units (ℓ still measured and reported)
  int pathsPerCell = 5000;    // 004: 50,000; rounded up to a multiple of the cell's segments
  int maxDepth = 64;          // scattering events per path
  double albedo = 1.0;        // scale of the BCSDF (a test knob: 0 gives A = 0 exactly)
  int ellPaths = 2000;        // paths of the ℓ estimate
  uint32_t seed = 1;
};
// InputError naming the option (--tiles, --cell-factor, ...).
void checkIirtfSettings(const IirtfSettings& s);

// Cells of the block (004 §4.2): the box [0, P)² × [z_lo, z_hi] of the
// segment midpoints split into nx × ny × nz equal cells with sides as close to
// ℓ̃ as whole numbers allow; segment k belongs to the cell of its midpoint.
struct IirtfCells {
  int nx = 1, ny = 1, nz = 1;
  glm::dvec3 origin{0.0}, side{1.0};
  std::vector<uint32_t> cellOf;                 // per block segment
  std::vector<std::vector<uint32_t>> members;   // per cell, ascending
  size_t count() const { return members.size(); }
};
IirtfCells makeIirtfCells(const Exemplar& block, double target);

// ℓ: mean distance between successive scattering events of paths entering
// the tiled flat fabric from above (notes-appearance §7.8 [F]), with the
// number of such distances.
struct MeanFreePath {
  double ell = 0.0;
  uint64_t distances = 0;
  uint64_t rays = 0;
};
MeanFreePath estimateMeanFreePath(const IirtfScene& scene, const Exemplar& block, int tiles,
                                  const FabricParams& fabric, const IirtfSettings& s);

// The radiance T(ω0, ω1, x) (rgb) of one path from x (inside fiber
// `ownFiber`) along ω1, light from ω0 of unit irradiance; `rays` counts the
// rays traced. RandomStream keyed by (k, path, seed): bcsdf_sampling.h.
glm::dvec3 iirtfPathRadiance(const IirtfScene& scene, const FabricParams& fabric, double albedo, int maxDepth,
                             glm::vec3 x, uint32_t ownFiber, glm::vec3 w0, glm::vec3 w1, uint32_t stream,
                             uint32_t path, uint32_t seed, uint64_t& rays);

// ω0 uniform on the upper hemisphere, ω1 uniform on the sphere (004 §4.2c),
// from four uniform numbers.
void iirtfDirections(double u0, double u1, double u2, double u3, glm::dvec3& w0, glm::dvec3& w1);
// Adds T Y(ω0)⊗Y(ω1) / (p(ω0) p(ω1)) into a matrix (kIirtfMatrixSize doubles)
// and, when sumSq is not empty, its square into sumSq (the per-path second
// moments of the standard error).
void iirtfAccumulate(std::span<double> sum, glm::dvec3 T, glm::dvec3 w0, glm::dvec3 w1,
                     std::span<double> sumSq = {});

// Σ over `paths` paths from block segment k (the centre copy's) of the
// estimator term, in path order; `rays` accumulates the rays traced.
std::vector<double> iirtfSegmentSum(const IirtfScene& scene, const Exemplar& block, int tiles,
                                    const FabricParams& fabric, const IirtfSettings& s, uint32_t k, int paths,
                                    uint64_t& rays);
// A_C of one cell: 004 §4.2c with k stratified (path i from segment
// members[i mod |C|], so p(k) = 1/|C|), paths = pathsPerCell rounded up to a
// multiple of |C|; the per-segment sums in blocks (TBB) added in a fixed order.
// An empty cell is all zeros.
// stdError: the standard error of each entry of a from the same paths
// (per-path second moments): stratified over the cell's segments,
// SE² = Σ_k s_k² / (n |C|²) with s_k² the sample variance of segment k's n
// path terms; with one path per segment the pooled variance of all paths
// over their count (which also holds the between-segment spread: larger);
// infinite for a single path; 0 for an empty cell (A = 0 exactly).
struct IirtfCell {
  std::vector<double> a;         // kIirtfMatrixSize
  std::vector<double> stdError;  // kIirtfMatrixSize
  uint64_t paths = 0, rays = 0;
};
IirtfCell iirtfCellCpu(const IirtfScene& scene, const Exemplar& block, int tiles, const FabricParams& fabric,
                       const IirtfSettings& s, const std::vector<uint32_t>& members);

// Noise-aware SH order of one cell (docs/prt-multiple-scattering.md, "Noise or bias"): the
// relative noise of band l is sqrt(Σ SE² / Σ a²) over the entries with max(l1, l0) = l (all
// channels); the cell keeps the bands below the first l ≥ 1 whose noise exceeds `cut` and its
// other entries are set to 0. Returns the bands kept (1..FT_SH_BANDS).
int prtMsNoiseCut(IirtfCell& cell, double cut);

// ---- per frame (004 §5.3.1) ----------------------------------------------------
// L̃^multi of one query with A_C (kIirtfMatrixSize values, any precision the
// caller converted to double) and the tables, first `bands` bands.
glm::dvec3 prtMsRadianceCpu(const PrtMsTables& tables, std::span<const double> a, int bands, const PrtMsQuery& q);

// ---- V̄_glo (004 §5.3.2) ----------------------------------------------------------
// The normalised Gaussian filter of a V_glo grid (row-major, width × height,
// texels of side `texel` fabric units, A = the grid), σ_glo in fabric units:
// common/'s weights, one pass per axis in double. InputError naming the value
// for sizes that do not match, a non-positive texel or σ, a non-finite V.
std::vector<double> prtMsVgloFilterCpu(std::span<const double> v, int width, int height, double texel, double sigma);
// 004's CPU estimator of V̄_glo at x over the unbounded fabric plane: x′ = x +
// σ_glo (g1, g2), g Gaussian (Box–Muller on the shared counter hash keyed by
// (stream, seed)), the mean of V_glo(x′) over `samples` draws (the kernel is
// the sampling density, so the ratio of 004's two integrals is the plain mean).
double prtMsVgloSampleCpu(const std::function<double(glm::dvec2)>& vGlo, glm::dvec2 x, double sigma, int samples,
                          uint32_t stream, uint32_t seed);

}  // namespace ft
