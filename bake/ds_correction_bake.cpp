// ds_correction_bake.cpp — `fibertwin bake ds-correction`: the dual-scattering
// correction ξ and fiber-level shadowing Ψ_G^Fiber of Huang et al. 2025 (001)
// §4.3 eq. 9–11, §5.1 (reference/ds_correction.h, docs/ds-correction.md).
// One shard per light direction (θ_a, φ_b): the path tracing of one yarn of
// the all-fiber reference; rank 0 factors the directions in shard order
// (factorDsCorrection) and writes one file.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <bit>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "bake/bake.h"
#include "reference/ds_correction.h"

namespace ft {
namespace {

// Shard bytes: per texel 10 float64 (L_* rgb, Ψ_G rgb, g rgb, hits), little-endian.
constexpr size_t kValuesPerTexel = 10;

void putDoubleLe(std::byte* out, double d) {
  const uint64_t u = std::bit_cast<uint64_t>(d);
  for (int b = 0; b < 8; ++b) out[b] = std::byte((u >> (8 * b)) & 0xffu);
}
double getDoubleLe(const std::byte* in) {
  uint64_t u = 0;
  for (int b = 0; b < 8; ++b) u |= uint64_t(in[b]) << (8 * b);
  return std::bit_cast<double>(u);
}

class DsCorrectionBake final : public Bake {
 public:
  void addOptions(CLI::App& app) override {
    app.add_option("--yarn", s_.yarn, "yarn preset (its flyaways are left out)")->capture_default_str();
    app.add_option("--set", s_.presetOverrides,
                   "override a yarn preset parameter by its data/yarn-presets.tsv column, name=value (repeatable)")
        ->allow_extra_args(false);
    app.add_option("--fabric", s_.fabric, "BCSDF preset (data/fabric-bcsdf.tsv)")->capture_default_str();
    app.add_option("--height", s_.height, "texels across the yarn, N_v (N_u follows from the twist period)")
        ->capture_default_str();
    app.add_option("--theta-samples", s_.thetaSamples, "longitudinal light directions N_θ")->capture_default_str();
    app.add_option("--phi-samples", s_.phiSamples, "azimuthal light directions N_φ")->capture_default_str();
    app.add_option("--pixels-per-texel", s_.pixelsPerTexel, "camera pixels per texel side")->capture_default_str();
    app.add_option("--spp", s_.samplesPerPixel, "path-traced samples per camera pixel")->capture_default_str();
    app.add_option("--max-depth", s_.maxDepth, "scattering events per path")->capture_default_str();
    app.add_option("--periods", s_.periods, "ply-twist periods of yarn (odd; the middle one is baked)")
        ->capture_default_str();
    app.add_option("--seed", s_.seed, "seed of the path tracer")->capture_default_str();
  }

  void prepare() override {
    checkDsCorrectionSettings(s_);  // InputError naming the setting before the scene is built
    scene_ = std::make_unique<DsCorrectionScene>(s_);
  }

  size_t shardCount() const override { return size_t(scene_->directionCount()); }

  std::vector<std::byte> runShard(size_t shard) const override {
    if (shard >= shardCount()) throw std::out_of_range(fmt::format("bake {}: no shard {}", name(), shard));
    const DsDirectionSums sums = scene_->trace(int(shard));
    std::vector<std::byte> out(sums.hits.size() * kValuesPerTexel * 8);
    std::byte* p = out.data();
    for (size_t t = 0; t < sums.hits.size(); ++t) {
      for (int c = 0; c < 3; ++c) putDoubleLe(p + 8 * c, sums.reference[t][c]);
      for (int c = 0; c < 3; ++c) putDoubleLe(p + 8 * (3 + c), sums.shadowing[t][c]);
      for (int c = 0; c < 3; ++c) putDoubleLe(p + 8 * (6 + c), sums.local[t][c]);
      putDoubleLe(p + 72, sums.hits[t]);
      p += kValuesPerTexel * 8;
    }
    return out;
  }

  void write(std::span<const std::vector<std::byte>> shards, const std::filesystem::path& out) const override {
    const DsCorrectionLayout l = scene_->layout();
    const size_t texels = size_t(l.size.x) * l.size.y;
    if (shards.size() != shardCount())
      throw std::runtime_error(fmt::format("bake {}: {} shards, expected {}", name(), shards.size(), shardCount()));
    std::vector<DsDirectionSums> directions(shards.size());
    for (size_t k = 0; k < shards.size(); ++k) {
      if (shards[k].size() != texels * kValuesPerTexel * 8)
        throw std::runtime_error(fmt::format("bake {}: shard {} has {} bytes, expected {}", name(), k,
                                             shards[k].size(), texels * kValuesPerTexel * 8));
      DsDirectionSums& d = directions[k];
      d.reference.resize(texels);
      d.shadowing.resize(texels);
      d.local.resize(texels);
      d.hits.resize(texels);
      const std::byte* p = shards[k].data();
      for (size_t t = 0; t < texels; ++t, p += kValuesPerTexel * 8) {
        for (int c = 0; c < 3; ++c) d.reference[t][c] = getDoubleLe(p + 8 * c);
        for (int c = 0; c < 3; ++c) d.shadowing[t][c] = getDoubleLe(p + 8 * (3 + c));
        for (int c = 0; c < 3; ++c) d.local[t][c] = getDoubleLe(p + 8 * (6 + c));
        d.hits[t] = getDoubleLe(p + 72);
      }
    }
    const double samplesPerTexel = double(s_.samplesPerPixel) * s_.pixelsPerTexel * s_.pixelsPerTexel;
    const DsCorrectionTextures t = factorDsCorrection(l, directions, samplesPerTexel);
    // Only what the textures depend on: nothing of ranks, threads, time or host.
    nlohmann::ordered_json settings;
    settings["yarn"] = s_.yarn;
    settings["set"] = s_.presetOverrides;
    settings["fabric"] = s_.fabric;
    settings["height"] = s_.height;
    settings["theta_samples"] = s_.thetaSamples;
    settings["phi_samples"] = s_.phiSamples;
    settings["pixels_per_texel"] = s_.pixelsPerTexel;
    settings["spp"] = s_.samplesPerPixel;
    settings["max_depth"] = s_.maxDepth;
    settings["periods"] = s_.periods;
    settings["seed"] = s_.seed;
    settings["segments"] = scene_->segmentCount();
    writeDsCorrection(out, t, settings.dump());
  }

 private:
  DsCorrectionSettings s_{};
  std::unique_ptr<DsCorrectionScene> scene_;
};

}  // namespace

std::unique_ptr<Bake> makeDsCorrectionBake() { return std::make_unique<DsCorrectionBake>(); }

}  // namespace ft
