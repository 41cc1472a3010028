// prt_frame.h — the CPU reference of the fabric PRT frame of Khungurn et al.
// 2017 (004) §5 and its path-traced reference (004 §6.2, Fig. 13;
// docs/prt-frame.md): the tiled flat exemplar (reference/exemplar.h) seen
// by an orthographic camera over the centre block,
//   * PRT: the exemplar volume's G-buffer (reference/exemplar_volume.h, 004
//     §5.1) → per pixel single scattering (reference/prt_single_scattering.h,
//     SSDF for directional lights and λ ≥ 200, sums of SGs for λ ≤ 100) plus
//     multiple scattering (reference/prt_multiple_scattering.h, the IIRTF of
//     the hit segment's cell in SH), composed by common/prt_frame.h;
//   * path tracing: the same eye rays through the real capsules (Embree), the
//     path radiance of reference/prt_multiple_scattering.h (BCSDF sampling,
//     next-event estimation to the light, Russian roulette), the SG light by
//     sampling its direction from G/M (a pdf: the light's radiance integrates to 1).
// Bakes (segment visibility, IIRTF) run lazily for the segments and cells a
// view hits; their time is reported apart from the frame's.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "image/image.h"
#include "reference/exemplar.h"
#include "reference/exemplar_volume.h"
#include "reference/prt_multiple_scattering.h"
#include "reference/segment_visibility.h"

namespace ft {

struct PrtFrameSettings {
  std::string fabric = "fleece";  // data/fabric-bcsdf.tsv row
  ExemplarSettings exemplar;      // the block (fibersPerPly 0: the preset's count)
  int tiles = 5;                  // N × N copies (Embree scenes)
  int width = 32, height = 32;    // the image
  int volumeSamples = 256;        // N per eye ray (004 §5.1; midpoint ids)
  // The G-buffer's id (docs/exemplar-volume.md "Ids"): FT_VOL_IDS_CAPSULE (the first exact
  // capsule hit among the volume's candidates) or FT_VOL_IDS_MIDPOINT (004 §5.1's nearest midpoint).
  uint32_t volumeIds = FT_VOL_IDS_CAPSULE;
  bool embreeGBuffer = false;     // experiment: the G-buffer from Embree first hits on the capsules, not the volume
  int voxelsPerDiameter = 1;      // volume voxels per fiber diameter (1: h ≈ 2 r_f, notes §8.7)
  int svfSize = 32;               // the visibility image is svfSize × svfSize (004: 128)
  int bands = 5;                  // SH bands L + 1 of multiple scattering (004 Table 1: L = 4 for Fleece)
  double cellFactor = 2.0;        // ℓ̃ = cellFactor ℓ (004 §4.2: ℓ … 2ℓ)
  int pathsPerCell = 2000;        // IIRTF paths per cell (004: 50,000)
  int ellPaths = 300;             // paths of the ℓ estimate
  int msThetaINodes = 1024, msPhiNodes = 256;  // C_S quadrature
  int ptSamples = 16;             // path-traced samples per pixel
  int maxDepth = 64;              // scattering events per path (both the IIRTF bake and the reference)
  uint32_t seed = 1;
};
// InputError naming the option (--width, --svf-size, ...).
void checkPrtFrameSettings(const PrtFrameSettings& s);

// One configuration: the eye direction and the light (004 Fig. 13 sweeps both).
struct PrtFrameView {
  glm::vec3 wo{0.0f, 0.0f, 1.0f};     // unit, towards the eye (z > 0: above the fabric)
  glm::vec3 light{0.0f, 0.0f, 1.0f};  // unit ω_d or SG axis ξ (towards the light)
  float lambda = 0.0f;                // 0: directional of unit irradiance, else the SG light G(ω; ξ, λ)/M(λ)
};
// InputError naming the field for non-unit / non-finite directions, an eye below the fabric or λ < 0.
void checkPrtFrameView(const PrtFrameView& v);

struct PrtFrameImage {
  int width = 0, height = 0;
  std::vector<glm::vec3> rgb;  // row 0 at the top
  uint64_t covered = 0;        // pixels with a fiber hit
  double seconds = 0.0;        // the frame alone (no bake)
  double averageStdError = 0.0;  // path tracing: standard error of average() from the per-pixel sample variances
  double average() const;      // mean of (r + g + b)/3 over all pixels (004 Fig. 13's average intensity)
  double coveredAverage() const { return covered ? average() * double(rgb.size()) / double(covered) : 0.0; }
};
struct PrtFrameParts {
  PrtFrameImage total, single, multi;
  std::vector<uint32_t> ids;  // the G-buffer: 1 + block segment, 0 = miss
};

// What the GPU twin needs of a scene (gpu/prt_frame_gpu.h): the volume's
// layout, segment table and candidates, the baked per-segment data (zeros for
// segments not baked yet) and the IIRTF matrices (zeros for cells not baked).
struct PrtFrameData {
  FabricParams fabric{};
  VolParams layout{};
  std::vector<VolSegment> segments;
  VolumeCandidates candidates;
  int svfSize = 0, axes = 0;
  float lambdaSvf = 0.0f;
  std::vector<float> ssdf;              // [segment][n²]
  std::vector<glm::vec4> segmentData;   // per segment: (R_k angle, IIRTF cell, 0, 0)
  std::vector<float> weights;           // [segment][Q]
  std::vector<float> transfer;          // [cell][kIirtfMatrixSize]
};

class PrtFrameScene {
 public:
  // Builds the block, its tiling, the volume and the Embree scenes; throws InputError for bad settings.
  explicit PrtFrameScene(const PrtFrameSettings& settings);
  ~PrtFrameScene();
  PrtFrameScene(PrtFrameScene&&) noexcept;
  PrtFrameScene& operator=(PrtFrameScene&&) noexcept;

  const PrtFrameSettings& settings() const;
  const Exemplar& block() const;
  // The volume rays of a view (orthographic, the centre block's P × P square seen along −ω_o).
  VolParams rays(const PrtFrameView& view) const;
  // PRT: total, and its single and multiple parts. Bakes what the view needs first (bakeSeconds).
  PrtFrameParts renderPrt(const PrtFrameView& view);
  // Path tracing: maxDepth 1 gives single scattering alone (next-event estimation at the first hit).
  PrtFrameImage renderPathTraced(const PrtFrameView& view, int samples, int maxDepth) const;
  PrtFrameData gpuData() const;
  double bakeSeconds() const;  // all lazy bakes so far (and ℓ, the tables, the volume)
  double meanFreePath() const;
  size_t cellCount() const;
  size_t svfBaked() const;     // segments whose visibility is baked
  size_t cellsBaked() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// The image as linear RGBA (alpha 1).
ImageRgbaF toImage(const PrtFrameImage& image);

// 004 Fig. 13's figures of one configuration, and the images' differences.
struct PrtFrameComparison {
  double averagePrt = 0.0, averageReference = 0.0;  // average intensity (mean of r, g, b over all pixels)
  double averageRelError = 0.0;  // |PRT − reference| / reference of the averages
  double coveredPrt = 0.0, coveredReference = 0.0;  // average intensity over each image's covered pixels
  double pixelRmse = 0.0;        // RMSE over pixels of the per-pixel intensity difference
  double flipMean = 0.0;         // HDR-FLIP mean (image/flip.h), reference = the path-traced image
  uint64_t nonFinite = 0;        // NaN/Inf values in either image
};
// InputError when the sizes differ. flip = false leaves flipMean 0.
PrtFrameComparison comparePrtFrame(const PrtFrameImage& prt, const PrtFrameImage& reference, bool flip = true);

// A direction from the normalised SG G(ω; ξ, λ)/M(λ) (λ > 0), from two uniform numbers
// (cos Δ = 1 + ln(1 − u(1 − e^{−2λ}))/λ about ξ).
glm::dvec3 sampleSgDirection(glm::dvec3 xi, double lambda, double u0, double u1);

}  // namespace ft
