// ambient_occlusion_bake.cpp — `fibertwin bake ambient-occlusion`: the yarn
// AO texture of Wu & Yuksel 2019 (000) §4.2 with the CPU reference's exact
// line integral (reference/ambient_occlusion.h), at the preset's own scale
// (AO is scale-free: docs/ambient-occlusion.md "Scale"), sharded by blocks of
// texel rows. A shard evaluates its texels with ambientOcclusionAtCpu keyed
// by the texel index, which reproduces bakeAmbientOcclusionCpu texel for
// texel (tests/bake_test.cpp checks it bit for bit). The settings are those
// of AoSettings (the render's texture uses its defaults).
#include "bake/ambient_occlusion_bake.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>

#include "bake/bake.h"
#include "reference/ambient_occlusion.h"
#include "scene/input_error.h"
#include "scene/yarn_density.h"
#include "scene/yarn_preset.h"

namespace ft {
namespace {

static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559);

void putFloatLe(std::byte* out, float f) {
  const uint32_t u = std::bit_cast<uint32_t>(f);
  for (int b = 0; b < 4; ++b) out[b] = std::byte((u >> (8 * b)) & 0xffu);
}
float getFloatLe(const std::byte* in) {
  uint32_t u = 0;
  for (int b = 0; b < 4; ++b) u |= uint32_t(in[b]) << (8 * b);
  return std::bit_cast<float>(u);
}

class AmbientOcclusionBake final : public Bake {
 public:
  void addOptions(CLI::App& app) override {
    app.add_option("--yarn", yarn_, "yarn preset whose ply-density field is baked")->capture_default_str();
    app.add_option("--set", sets_,
                   "override a yarn preset parameter by its data/yarn-presets.tsv column, name=value (repeatable)")
        ->allow_extra_args(false);
    // ≥ 8: the fit written into the header needs 4 radial bins of one texel (n/2 of them).
    app.add_option("--size", settings_.resolution, "texels across the texture (n × n, n ≥ 8 for the cubic fit)")
        ->capture_default_str()
        ->check(CLI::Range(8, 4096));
    app.add_option("--directions", settings_.directions, "stratified directions per texel")
        ->capture_default_str()
        ->check(CLI::Range(1, 65536));
    app.add_option("--kappa", settings_.kappa, "κ of exp(-κτ) (0: 2 r_f, notes §0.3)")
        ->capture_default_str()
        ->check(CLI::Range(0.0f, 1e30f));
    app.add_option("--seed", settings_.seed, "seed of the direction jitter")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    app.add_option("--rows-per-shard", rowsPerShard_,
                   "texel rows per shard (0: ⌈n/64⌉, about 64 shards); the output does not depend on it")
        ->capture_default_str()
        ->check(CLI::Range(0, 4096));
  }

  void prepare() override {
    if (!std::isfinite(settings_.kappa))  // CLI::Range lets NaN through
      throw InputError(fmt::format("--kappa: {} is not a finite number ≥ 0", settings_.kappa));
    preset_ = overrideYarnPreset(findYarnPreset(yarn_), sets_);  // InputError naming the preset / column
    try {
      params_ = makeAoParams(makeYarnDensity(preset_), settings_);
    } catch (const std::invalid_argument& e) {
      throw InputError(fmt::format("bake {}: --yarn {}: {}", name(), yarn_, e.what()));
    }
    const int n = int(params_.resolution);
    rows_ = rowsPerShard_ > 0 ? std::min(rowsPerShard_, n) : std::max(1, (n + 63) / 64);
  }

  size_t shardCount() const override { return size_t((int(params_.resolution) + rows_ - 1) / rows_); }

  std::vector<std::byte> runShard(size_t shard) const override {
    const uint32_t n = params_.resolution;
    const uint32_t j0 = uint32_t(shard) * uint32_t(rows_), j1 = std::min(n, j0 + uint32_t(rows_));
    if (shard >= shardCount()) throw std::out_of_range(fmt::format("no shard {}", shard));
    std::vector<glm::vec3> points;
    std::vector<uint32_t> ids;
    points.reserve(size_t(j1 - j0) * n);
    ids.reserve(points.capacity());
    for (uint32_t j = j0; j < j1; ++j)
      for (uint32_t i = 0; i < n; ++i) {  // the texel centres and jitter keys of bakeAmbientOcclusionCpu
        points.emplace_back(ftAoTexelCentre(params_.halfWidth, n, i), ftAoTexelCentre(params_.halfWidth, n, j), 0.0f);
        ids.push_back(j * n + i);
      }
    const AoBakeCpu ao = ambientOcclusionAtCpu(params_, points, ids);
    std::vector<std::byte> out(ao.ao.size() * 4);
    for (size_t t = 0; t < ao.ao.size(); ++t) putFloatLe(out.data() + 4 * t, ao.ao[t]);
    return out;
  }

  void write(std::span<const std::vector<std::byte>> shards, const std::filesystem::path& out) const override {
    const size_t n = params_.resolution;
    if (shards.size() != shardCount())
      throw std::runtime_error(fmt::format("bake {}: {} shards, expected {}", name(), shards.size(), shardCount()));
    std::vector<float> ao;
    ao.reserve(n * n);
    for (size_t k = 0; k < shards.size(); ++k) {
      const size_t rows = std::min(n, (k + 1) * size_t(rows_)) - k * size_t(rows_);
      if (shards[k].size() != rows * n * 4)
        throw std::runtime_error(
            fmt::format("bake {}: shard {} has {} bytes, expected {}", name(), k, shards[k].size(), rows * n * 4));
      for (size_t b = 0; b < shards[k].size(); b += 4) ao.push_back(getFloatLe(shards[k].data() + b));
    }
    // A3 C1: AO ∈ (0, 1]; a NaN or an out-of-range texel is a broken bake, not a texture.
    for (size_t t = 0; t < ao.size(); ++t)
      if (!std::isfinite(ao[t]) || !(ao[t] > 0.0f) || ao[t] > 1.0f + 1e-6f)
        throw std::runtime_error(fmt::format("bake {}: texel {} (i {}, j {}) is {}, not in (0, 1]", name(), t, t % n,
                                             t / n, ao[t]));
    const AoCubicFit fit = fitAoCubic(std::span<const float>(ao), int(n));
    // Only what the texels depend on (and the fit of 000 §4.2 the frame uses):
    // nothing of the rank count, threads, shard split, time or host.
    nlohmann::ordered_json h;
    h["format"] = kAoTextureFormat;
    h["version"] = 1;
    h["bake"] = name();
    h["paper"] = "Wu & Yuksel 2019 (000) §4.2, exact line integral of the ply density";
    h["yarn"] = yarn_;
    h["set"] = sets_;
    h["resolution"] = n;
    h["directions"] = params_.directions;
    h["direction_mode"] = params_.directionMode == FT_AO_DIRECTIONS_STRATIFIED ? "stratified" : "equal";
    h["seed"] = params_.seed;
    h["kappa"] = params_.kappa;
    h["half_width"] = params_.halfWidth;
    h["psi"] = 0.0;
    h["layout"] = "after this line: resolution² float32 little-endian, texel (i, j) at j·n + i, centre "
                  "(-W + (i + ½)2W/n, -W + (j + ½)2W/n), W = half_width";
    h["cubic"] = {fit.coefficients.x, fit.coefficients.y, fit.coefficients.z, fit.coefficients.w};
    h["cubic_rms_residual"] = fit.rmsResidual;
    std::ofstream f(out, std::ios::binary | std::ios::trunc);
    if (!f) throw InputError(fmt::format("--out: cannot write '{}'", out.string()));
    f << h.dump() << '\n';
    std::vector<std::byte> bytes(ao.size() * 4);
    for (size_t t = 0; t < ao.size(); ++t) putFloatLe(bytes.data() + 4 * t, ao[t]);
    f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    f.close();
    if (!f) throw InputError(fmt::format("--out: writing '{}' failed", out.string()));
  }

 private:
  std::string yarn_ = "cotton1";
  std::vector<std::string> sets_;
  AoSettings settings_{};
  int rowsPerShard_ = 0;
  YarnPreset preset_;
  AmbientOcclusionParams params_{};
  int rows_ = 1;
};

}  // namespace

std::unique_ptr<Bake> makeAmbientOcclusionBake() { return std::make_unique<AmbientOcclusionBake>(); }

AoTextureFile readAoTextureFile(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(fmt::format("{}: cannot open", path.string()));
  std::string line;
  if (!std::getline(f, line)) throw InputError(fmt::format("{}: empty", path.string()));
  AoTextureFile file;
  try {
    file.header = nlohmann::json::parse(line);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: byte 0: the header line is not JSON ({})", path.string(), e.what()));
  }
  if (!file.header.is_object() || file.header.value("format", "") != kAoTextureFormat ||
      file.header.value("version", 0) != 1 || !file.header.contains("resolution") ||
      !file.header["resolution"].is_number_unsigned())
    throw InputError(fmt::format("{}: byte 0: not a {} version 1 file", path.string(), kAoTextureFormat));
  const size_t n = file.header["resolution"].get<size_t>();
  if (n < 2 || n > 4096) throw InputError(fmt::format("{}: resolution {} (2..4096)", path.string(), n));
  std::vector<char> bytes(n * n * 4);
  f.read(bytes.data(), std::streamsize(bytes.size()));
  if (size_t(f.gcount()) != bytes.size() || f.peek() != std::char_traits<char>::eof())
    throw InputError(fmt::format("{}: byte {}: expected exactly {} texel bytes after the header", path.string(),
                                 line.size() + 1, bytes.size()));
  file.ao.resize(n * n);
  for (size_t t = 0; t < file.ao.size(); ++t) file.ao[t] = getFloatLe(reinterpret_cast<const std::byte*>(bytes.data()) + 4 * t);
  return file;
}

}  // namespace ft
