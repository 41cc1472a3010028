// iirtf_bake.cpp — `fibertwin bake iirtf`: the incoming indirect radiance
// transfer functions A_C of Khungurn et al. 2017 (004) §4.2 for every cell of
// a plain-weave exemplar block (reference/exemplar.h), path traced through the
// N × N tiling (reference/prt_multiple_scattering.h). prepare() measures the
// mean free path ℓ (notes-appearance §7.8 [F]) and splits the block into cells
// of side near ℓ̃ = factor·ℓ; a shard is one cell, its paths keyed by (segment,
// path, seed) and summed in a fixed grouping, so the file is the same for any
// rank or thread count (docs/bakes.md; tests/bake_mpi_test.sh compares bytes).
#include "bake/iirtf_bake.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "bake/bake.h"
#include "bake/little_endian.h"
#include "reference/exemplar.h"
#include "reference/prt_multiple_scattering.h"
#include "scene/fabric.h"
#include "scene/input_error.h"

namespace ft {
namespace {

class IirtfBake final : public Bake {
 public:
  void addOptions(CLI::App& app) override {
    app.add_option("--yarn", ex_.yarn, "yarn preset of the plain-weave exemplar")->capture_default_str();
    app.add_option("--set", ex_.sets, "override a yarn preset parameter, name=value (repeatable)")
        ->allow_extra_args(false);
    app.add_option("--fibers-per-ply", ex_.fibersPerPly, "fibers per ply (0: the preset's fiber_num)")
        ->capture_default_str();
    app.add_option("--spans", ex_.spansPerYarn, "Catmull-Rom spans per yarn per period")->capture_default_str();
    app.add_option("--subdivisions", ex_.subdivisions, "straight segments per fiber per span")->capture_default_str();
    app.add_option("--fiber-radius", ex_.fiberRadius, "fiber radius at the preset's scale")->capture_default_str();
    app.add_option("--fabric", fabric_, "BCSDF row of data/fabric-bcsdf.tsv")->capture_default_str();
    app.add_option("--tiles", s_.tiles, "N of the N × N tiling (odd; the cells are the centre copy's)")
        ->capture_default_str();
    app.add_option("--cell-factor", s_.cellFactor, "target cell side ℓ̃ in units of the mean free path ℓ (004: 1-2)")
        ->capture_default_str();
    app.add_option("--cell-size", s_.cellSize, "target cell side in fabric units (0: cell-factor · ℓ)")
        ->capture_default_str();
    app.add_option("--paths", s_.pathsPerCell, "paths per cell (004: 50,000)")->capture_default_str();
    app.add_option("--max-depth", s_.maxDepth, "scattering events per path")->capture_default_str();
    app.add_option("--ell-paths", s_.ellPaths, "paths of the mean-free-path estimate")->capture_default_str();
    app.add_option("--bands", bands_, "SH bands L + 1 the renderer is to use (004: 5 or 6; 36 coefficients stored)")
        ->capture_default_str();
    app.add_option("--seed", s_.seed, "key of every path's random numbers")->capture_default_str();
  }

  void prepare() override {
    checkIirtfSettings(s_);
    if (s_.pathsPerCell < 2)
      throw InputError(fmt::format("--paths: {} (≥ 2: the file holds each entry's standard error)", s_.pathsPerCell));
    if (bands_ < 1 || bands_ > FT_SH_BANDS) throw InputError(fmt::format("--bands: {} (1..{})", bands_, FT_SH_BANDS));
    fabricParams_ = findFabricPreset(fabric_).params();
    block_ = makePlainWeaveExemplar(ex_);
    if (block_.segments.empty()) throw InputError(fmt::format("bake {}: the exemplar has no segments", name()));
    scene_ = std::make_shared<IirtfScene>(tileExemplar(block_, s_.tiles));
    ell_ = estimateMeanFreePath(*scene_, block_, s_.tiles, fabricParams_, s_);
    if (!(ell_.ell > 0.0) && !(s_.cellSize > 0.0))
      throw InputError(fmt::format("bake {}: no path scattered twice: ℓ unknown; give --cell-size", name()));
    target_ = s_.cellSize > 0.0 ? s_.cellSize : s_.cellFactor * ell_.ell;
    cells_ = makeIirtfCells(block_, target_);
  }

  size_t shardCount() const override { return cells_.count(); }

  static constexpr size_t kShardBytes = 2 * kIirtfMatrixSize * 4 + 16;  // A_C, its standard error, paths, rays

  std::vector<std::byte> runShard(size_t shard) const override {
    if (shard >= shardCount()) throw std::out_of_range(fmt::format("no shard {}", shard));
    const IirtfCell c = iirtfCellCpu(*scene_, block_, s_.tiles, fabricParams_, s_, cells_.members[shard]);
    std::vector<std::byte> out;
    out.reserve(kShardBytes);
    for (size_t i = 0; i < kIirtfMatrixSize; ++i) {
      if (!std::isfinite(c.a[i]))
        throw std::runtime_error(fmt::format("cell {}: entry {} of A_C is {}", shard, i, c.a[i]));
      putF32(out, float(c.a[i]));
    }
    for (size_t i = 0; i < kIirtfMatrixSize; ++i) {
      if (!std::isfinite(c.stdError[i]))
        throw std::runtime_error(fmt::format("cell {}: the standard error of entry {} of A_C is {} (a single path?)",
                                             shard, i, c.stdError[i]));
      putF32(out, float(c.stdError[i]));
    }
    putU64(out, c.paths);
    putU64(out, c.rays);
    return out;
  }

  void write(std::span<const std::vector<std::byte>> shards, const std::filesystem::path& out) const override {
    const size_t C = cells_.count(), S = block_.segments.size();
    if (shards.size() != C)
      throw std::runtime_error(fmt::format("bake {}: {} shards, expected {}", name(), shards.size(), C));
    uint64_t rays = ell_.rays, paths = 0;
    std::vector<std::byte> body;
    body.reserve(S * 4 + C * (8 + 2 * kIirtfMatrixSize * 4));
    for (uint32_t c : cells_.cellOf) putU32(body, c);
    std::vector<std::byte> transfer, stdErr;
    for (size_t k = 0; k < C; ++k) {
      if (shards[k].size() != kShardBytes)
        throw std::runtime_error(fmt::format("bake {}: shard {} has {} bytes, expected {}", name(), k, shards[k].size(),
                                             kShardBytes));
      const std::byte* se = shards[k].data() + kIirtfMatrixSize * 4;
      const std::byte* tail = se + kIirtfMatrixSize * 4;
      const uint64_t p = getU64(tail);
      rays += getU64(tail + 8);
      paths += p;
      putU32(body, uint32_t(cells_.members[k].size()));
      putU32(body, uint32_t(p));
      transfer.insert(transfer.end(), shards[k].data(), se);
      stdErr.insert(stdErr.end(), se, tail);
    }
    body.insert(body.end(), transfer.begin(), transfer.end());
    body.insert(body.end(), stdErr.begin(), stdErr.end());
    std::vector<float> a(C * kIirtfMatrixSize), e(C * kIirtfMatrixSize);
    for (size_t i = 0; i < a.size(); ++i) a[i] = getF32(transfer.data() + 4 * i), e[i] = getF32(stdErr.data() + 4 * i);
    const IirtfNoiseByBand noise = iirtfNoiseByBand(a, e);
    nlohmann::ordered_json h;
    h["format"] = kIirtfFileFormat;
    h["version"] = 2;
    h["bake"] = name();
    h["paper"] = "Khungurn et al. 2017 (004) §4.2: per-cell IIRTF in SH by path tracing, estimator §4.2c";
    h["exemplar"] = {{"pattern", "plain-weave"}, {"yarn", ex_.yarn}, {"set", ex_.sets},
                     {"fibers_per_ply", ex_.fibersPerPly}, {"spans", ex_.spansPerYarn},
                     {"subdivisions", ex_.subdivisions}, {"fiber_radius", ex_.fiberRadius}, {"tiles", s_.tiles},
                     {"period", block_.period}, {"amplitude", block_.amplitude}, {"label", block_.label}};
    h["fabric"] = fabric_;
    h["segments"] = S;
    h["cells"] = C;
    h["grid"] = {cells_.nx, cells_.ny, cells_.nz};
    h["cell_origin"] = {cells_.origin.x, cells_.origin.y, cells_.origin.z};
    h["cell_side"] = {cells_.side.x, cells_.side.y, cells_.side.z};
    h["mean_free_path"] = ell_.ell;
    h["mean_free_path_distances"] = ell_.distances;
    h["target_cell_side"] = target_;
    h["bands"] = bands_;
    h["coefficients"] = FT_SH_COEFFS;
    h["paths_per_cell"] = s_.pathsPerCell;
    h["paths"] = paths;
    h["rays"] = rays;
    h["max_depth"] = s_.maxDepth;
    h["seed"] = s_.seed;
    h["relative_noise_by_band"] = noise.band;
    h["relative_noise_by_band_pair"] = noise.pair;
    h["sh_convention"] = "real, no Condon-Shortley phase, j = l(l+1)+m (common/sh.h)";
    h["layout"] = "after this line, little-endian: cell_of S×uint32; cells C×(uint32 segments, uint32 paths); "
                  "transfer C×3×36×36 float32 [channel][j1][j0] (c_T = A_C c_d); stderr C×3×36×36 float32, the standard "
                  "error of each transfer entry (same layout); relative_noise_by_band[l] = sqrt(sum SE^2 / sum a^2) over "
                  "the entries with max(l1, l0) = l, relative_noise_by_band_pair[l1*6+l0] per band pair";
    std::ofstream f(out, std::ios::binary | std::ios::trunc);
    if (!f) throw InputError(fmt::format("--out: cannot write '{}'", out.string()));
    f << h.dump() << '\n';
    f.write(reinterpret_cast<const char*>(body.data()), std::streamsize(body.size()));
    f.close();
    if (!f) throw InputError(fmt::format("--out: writing '{}' failed", out.string()));
    std::string line = "relative noise of A_C by band l = max(l1, l0) (sqrt(sum SE^2 / sum a^2)):";
    for (int l = 0; l < FT_SH_BANDS; ++l) line += fmt::format(" l={} {:.3g}", l, noise.band[size_t(l)]);
    std::cout << line << '\n';
  }

 private:
  ExemplarSettings ex_{};
  IirtfSettings s_{};
  std::string fabric_ = "fleece";
  int bands_ = 5;
  FabricParams fabricParams_{};
  Exemplar block_;
  std::shared_ptr<IirtfScene> scene_;
  MeanFreePath ell_;
  double target_ = 0.0;
  IirtfCells cells_;
};

}  // namespace

std::unique_ptr<Bake> makeIirtfBake() { return std::make_unique<IirtfBake>(); }

IirtfFile readIirtfFile(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(fmt::format("{}: cannot open", file));
  std::string line;
  if (!std::getline(f, line)) throw InputError(fmt::format("{}: empty", file));
  IirtfFile r;
  try {
    r.header = nlohmann::json::parse(line);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: byte 0: the header line is not JSON ({})", file, e.what()));
  }
  const nlohmann::json& h = r.header;
  if (!h.is_object() || h.value("format", "") != kIirtfFileFormat)
    throw InputError(fmt::format("{}: header: not a {} file", file, kIirtfFileFormat));
  if (!h.contains("version") || !h["version"].is_number_integer() || (h["version"] != 1 && h["version"] != 2))
    throw InputError(fmt::format("{}: header field \"version\": {} (this build reads 1 and 2)", file,
                                 h.contains("version") ? h["version"].dump() : std::string("missing")));
  r.version = h["version"].get<int>();
  auto field = [&](const char* name, uint64_t lo, uint64_t hi) -> uint64_t {
    if (!h.contains(name) || !h[name].is_number_unsigned())
      throw InputError(fmt::format("{}: header field \"{}\": missing or not an unsigned integer", file, name));
    const uint64_t v = h[name].get<uint64_t>();
    if (v < lo || v > hi) throw InputError(fmt::format("{}: header field \"{}\": {} not in {}..{}", file, name, v, lo, hi));
    return v;
  };
  r.segments = size_t(field("segments", 1, uint64_t(1) << 26));
  r.cells = size_t(field("cells", 1, uint64_t(1) << 20));
  r.bands = int(field("bands", 1, FT_SH_BANDS));
  field("coefficients", FT_SH_COEFFS, FT_SH_COEFFS);
  const size_t S = r.segments, C = r.cells;
  const size_t expected = S * 4 + C * 8 + C * kIirtfMatrixSize * 4 * (r.version == 2 ? 2 : 1);
  std::error_code ec;
  const uintmax_t total = std::filesystem::file_size(path, ec);
  if (ec || total < line.size() + 1 || total - (line.size() + 1) != expected)
    throw InputError(fmt::format("{}: byte {}: expected exactly {} bytes after the header ({} segments, {} cells)", file,
                                 line.size() + 1, expected, S, C));
  std::vector<std::byte> body(expected);
  f.read(reinterpret_cast<char*>(body.data()), std::streamsize(expected));
  if (size_t(f.gcount()) != expected)
    throw InputError(fmt::format("{}: byte {}: short read of {} bytes", file, line.size() + 1, expected));
  const std::byte* at = body.data();
  for (size_t k = 0; k < S; ++k, at += 4) {
    r.cellOf.push_back(getU32(at));
    if (r.cellOf.back() >= C)
      throw InputError(fmt::format("{}: section cell_of, item {}: cell {} ≥ header \"cells\" {}", file, k, r.cellOf.back(), C));
  }
  for (size_t c = 0; c < C; ++c, at += 8) {
    r.cellSegments.push_back(getU32(at));
    r.cellPaths.push_back(getU32(at + 4));
  }
  r.transfer.resize(C * kIirtfMatrixSize);
  for (size_t i = 0; i < r.transfer.size(); ++i, at += 4) {
    r.transfer[i] = getF32(at);
    if (!std::isfinite(r.transfer[i]))
      throw InputError(fmt::format("{}: section transfer, cell {}, entry {}: {} is not finite", file,
                                   i / kIirtfMatrixSize, i % kIirtfMatrixSize, r.transfer[i]));
  }
  if (r.version == 2) {
    r.stdError.resize(C * kIirtfMatrixSize);
    for (size_t i = 0; i < r.stdError.size(); ++i, at += 4) {
      r.stdError[i] = getF32(at);
      if (!std::isfinite(r.stdError[i]) || r.stdError[i] < 0.0f)
        throw InputError(fmt::format("{}: section stderr, cell {}, entry {}: {} is not a finite value ≥ 0", file,
                                     i / kIirtfMatrixSize, i % kIirtfMatrixSize, r.stdError[i]));
    }
  }
  return r;
}

IirtfNoiseByBand iirtfNoiseByBand(const std::vector<float>& transfer, const std::vector<float>& stdError) {
  if (transfer.size() != stdError.size() || transfer.size() % kIirtfMatrixSize != 0)
    throw std::invalid_argument(fmt::format("iirtfNoiseByBand: {} transfer and {} standard error values", transfer.size(),
                                            stdError.size()));
  constexpr int B = FT_SH_BANDS, J = FT_SH_COEFFS;
  std::vector<double> se2(B * B, 0.0), a2(B * B, 0.0);
  for (size_t i = 0; i < transfer.size(); ++i) {  // the pair (l1, l0) of entry i; iirtfEntryBand is their max
    const int e = int(i % size_t(J * J));
    const int l1 = iirtfEntryBand(size_t(e / J) * J), l0 = iirtfEntryBand(size_t(e % J));
    se2[size_t(l1 * B + l0)] += double(stdError[i]) * stdError[i];
    a2[size_t(l1 * B + l0)] += double(transfer[i]) * transfer[i];
  }
  IirtfNoiseByBand r;
  r.pair.resize(B * B);
  r.band.assign(B, 0.0);
  std::vector<double> bs(B, 0.0), ba(B, 0.0);
  for (int l1 = 0; l1 < B; ++l1)
    for (int l0 = 0; l0 < B; ++l0) {
      const size_t p = size_t(l1 * B + l0);
      r.pair[p] = a2[p] > 0.0 ? std::sqrt(se2[p] / a2[p]) : 0.0;
      bs[size_t(std::max(l1, l0))] += se2[p], ba[size_t(std::max(l1, l0))] += a2[p];
    }
  for (int l = 0; l < B; ++l) r.band[size_t(l)] = ba[size_t(l)] > 0.0 ? std::sqrt(bs[size_t(l)] / ba[size_t(l)]) : 0.0;
  return r;
}

}  // namespace ft
