// segment_visibility_bake.cpp — `fibertwin bake segment-visibility`: the
// segment visibility functions of Khungurn et al. 2017 (004) §4.1 for every
// segment of a plain-weave exemplar block (reference/exemplar.h), seen from
// the centre copy of an N × N tiling (reference/segment_visibility.h).
// Shards are ranges of segments (images, SSDF, R_k, weights: independent per
// segment); write() runs the one global step, the PCA of all SSDFs, on rank 0
// over the shards in shard order — deterministic for any rank count
// (docs/bakes.md; tests/bake_mpi_test.sh compares the bytes).
#include "bake/segment_visibility_bake.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "bake/bake.h"
#include "bake/little_endian.h"
#include "reference/exemplar.h"
#include "reference/segment_visibility.h"
#include "scene/input_error.h"

namespace ft {
namespace {

class SegmentVisibilityBake final : public Bake {
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
    app.add_option("--tiles", tiles_, "N of the N × N tiling (004 §4.1: images from the centre copy)")
        ->capture_default_str();
    app.add_option("--width", svf_.width, "image pixels in φ (004: 128)")->capture_default_str();
    app.add_option("--height", svf_.height, "image pixels in θ (004: 128)")->capture_default_str();
    app.add_option("--axes", svf_.axes, "Q, SGs per segment (004: 48)")->capture_default_str();
    app.add_option("--lambda", svf_.lambda, "λ_svf (004: 128)")->capture_default_str();
    app.add_option("--components", components_, "PCA components of the SSDFs (004: 48)")->capture_default_str();
    app.add_option("--seed", svf_.seed, "key of the per-segment rotations R_k")->capture_default_str();
    app.add_option("--segments-per-shard", perShard_, "segments per shard (0: about 64 shards)")
        ->capture_default_str();
  }

  void prepare() override {
    checkSvfSettings(svf_);
    if (components_ < 1 || components_ > 1024)
      throw InputError(fmt::format("--components: {} (1..1024)", components_));
    if (perShard_ < 0) throw InputError(fmt::format("--segments-per-shard: {} (≥ 0)", perShard_));
    block_ = makePlainWeaveExemplar(ex_);
    if (block_.segments.empty()) throw InputError(fmt::format("bake {}: the exemplar has no segments", name()));
    tiled_ = tileExemplar(block_, tiles_);
    scene_ = std::make_shared<SvfScene>(tiled_);
    const size_t S = block_.segments.size();
    per_ = perShard_ > 0 ? size_t(perShard_) : std::max<size_t>(1, (S + 63) / 64);
  }

  size_t shardCount() const override { return (block_.segments.size() + per_ - 1) / per_; }

  size_t pixels() const { return size_t(svf_.width) * size_t(svf_.height); }
  // A segment in a shard: image bits, SSDF, angle, weights.
  size_t segmentBytes() const { return (pixels() + 7) / 8 + 4 * pixels() + 4 + 4 * size_t(svf_.axes); }

  std::vector<std::byte> runShard(size_t shard) const override {
    if (shard >= shardCount()) throw std::out_of_range(fmt::format("no shard {}", shard));
    const size_t k0 = shard * per_, k1 = std::min(block_.segments.size(), k0 + per_);
    std::vector<SvfSegment> segs(k1 - k0);
    tbb::parallel_for(k0, k1, [&](size_t k) { segs[k - k0] = svfSegmentCpu(*scene_, block_, tiles_, uint32_t(k), svf_); });
    std::vector<std::byte> out;
    out.reserve(segs.size() * segmentBytes());
    for (const SvfSegment& s : segs) {
      std::vector<std::byte> bits((pixels() + 7) / 8, std::byte{0});
      for (size_t p = 0; p < pixels(); ++p)
        if (s.image[p]) bits[p / 8] |= std::byte(1u << (p % 8));
      out.insert(out.end(), bits.begin(), bits.end());
      for (float v : s.ssdf) putF32(out, v);
      putF32(out, s.angle);
      for (float w : s.weights) putF32(out, w);
    }
    return out;
  }

  void write(std::span<const std::vector<std::byte>> shards, const std::filesystem::path& out) const override {
    const size_t S = block_.segments.size(), P = pixels(), Q = size_t(svf_.axes), bitBytes = (P + 7) / 8;
    if (shards.size() != shardCount())
      throw std::runtime_error(fmt::format("bake {}: {} shards, expected {}", name(), shards.size(), shardCount()));
    std::vector<std::byte> images;
    std::vector<float> ssdf, angle, weights;
    ssdf.reserve(S * P);
    for (size_t k = 0; k < shards.size(); ++k) {
      const size_t n = std::min(S, (k + 1) * per_) - k * per_;
      if (shards[k].size() != n * segmentBytes())
        throw std::runtime_error(fmt::format("bake {}: shard {} has {} bytes, expected {}", name(), k,
                                             shards[k].size(), n * segmentBytes()));
      const std::byte* at = shards[k].data();
      for (size_t i = 0; i < n; ++i) {
        images.insert(images.end(), at, at + bitBytes);
        at += bitBytes;
        for (size_t p = 0; p < P; ++p, at += 4) ssdf.push_back(getF32(at));
        angle.push_back(getF32(at));
        at += 4;
        for (size_t q = 0; q < Q; ++q, at += 4) weights.push_back(getF32(at));
      }
    }
    for (size_t i = 0; i < ssdf.size(); ++i)
      if (!std::isfinite(ssdf[i]))
        throw std::runtime_error(fmt::format("bake {}: segment {} pixel {}: SSDF {}", name(), i / P, i % P, ssdf[i]));
    for (size_t i = 0; i < weights.size(); ++i)
      if (!std::isfinite(weights[i]) || weights[i] < 0.0f)
        throw std::runtime_error(fmt::format("bake {}: segment {} axis {}: weight {}", name(), i / Q, i % Q, weights[i]));
    // The global step: PCA of all SSDFs in segment order (Eigen, double, one thread).
    const SvfPca pca = svfPcaCpu(ssdf, S, int(P), components_);
    const size_t C = size_t(pca.components);
    double explained = 0.0;
    for (double e : pca.eigenvalues) explained += e;

    nlohmann::ordered_json h;
    h["format"] = kSvfFileFormat;
    h["version"] = 1;
    h["bake"] = name();
    h["paper"] = "Khungurn et al. 2017 (004) §4.1: binary visibility image, SSDF + PCA, sum of SGs";
    h["exemplar"] = {{"pattern", "plain-weave"}, {"yarn", ex_.yarn}, {"set", ex_.sets},
                     {"fibers_per_ply", ex_.fibersPerPly}, {"spans", ex_.spansPerYarn},
                     {"subdivisions", ex_.subdivisions}, {"fiber_radius", ex_.fiberRadius}, {"tiles", tiles_},
                     {"period", block_.period}, {"amplitude", block_.amplitude}, {"label", block_.label}};
    h["segments"] = S;
    h["fibers"] = block_.fibers;
    h["width"] = svf_.width;
    h["height"] = svf_.height;
    h["axes"] = svf_.axes;
    h["lambda"] = svf_.lambda;
    h["seed"] = svf_.seed;
    h["components"] = C;
    h["pca_explained_variance"] = pca.totalVariance > 0.0 ? explained / pca.totalVariance : 1.0;
    h["layout"] = "after this line, little-endian: segments S×(float32 a.xyz b.xyz radius, uint32 fiber); "
                  "svf S×(1+Q+C) float32 (R_k angle, w_1..Q, PCA coefficients); mean W·H float32; basis C×W·H "
                  "float32; images S×ceil(W·H/8) bytes (pixel p = y·W + x at byte p/8 bit p%8, 1 = visible)";
    std::vector<std::byte> body;
    body.reserve(S * (32 + 4 * (1 + Q + C) + bitBytes) + 4 * P * (1 + C));
    for (const ExemplarSegment& s : block_.segments) {
      for (float v : {s.a.x, s.a.y, s.a.z, s.b.x, s.b.y, s.b.z, s.radius}) putF32(body, v);
      putU32(body, s.fiber);
    }
    for (size_t k = 0; k < S; ++k) {
      putF32(body, angle[k]);
      for (size_t q = 0; q < Q; ++q) putF32(body, weights[k * Q + q]);
      for (size_t c = 0; c < C; ++c) putF32(body, float(pca.coefficients[k * C + c]));
    }
    for (double v : pca.mean) putF32(body, float(v));
    for (double v : pca.basis) putF32(body, float(v));
    body.insert(body.end(), images.begin(), images.end());
    std::ofstream f(out, std::ios::binary | std::ios::trunc);
    if (!f) throw InputError(fmt::format("--out: cannot write '{}'", out.string()));
    f << h.dump() << '\n';
    f.write(reinterpret_cast<const char*>(body.data()), std::streamsize(body.size()));
    f.close();
    if (!f) throw InputError(fmt::format("--out: writing '{}' failed", out.string()));
  }

 private:
  ExemplarSettings ex_{};
  SvfSettings svf_{};
  int tiles_ = 7;
  int components_ = 48;
  int perShard_ = 0;
  Exemplar block_;
  std::vector<ExemplarSegment> tiled_;
  std::shared_ptr<SvfScene> scene_;
  size_t per_ = 1;
};

}  // namespace

std::unique_ptr<Bake> makeSegmentVisibilityBake() { return std::make_unique<SegmentVisibilityBake>(); }

SvfFile readSegmentVisibilityFile(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(fmt::format("{}: cannot open", file));
  std::string line;
  if (!std::getline(f, line)) throw InputError(fmt::format("{}: empty", file));
  SvfFile r;
  try {
    r.header = nlohmann::json::parse(line);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: byte 0: the header line is not JSON ({})", file, e.what()));
  }
  const nlohmann::json& h = r.header;
  if (!h.is_object() || h.value("format", "") != kSvfFileFormat || h.value("version", 0) != 1)
    throw InputError(fmt::format("{}: header: not a {} version 1 file", file, kSvfFileFormat));
  auto field = [&](const char* name, uint64_t lo, uint64_t hi) -> uint64_t {
    if (!h.contains(name) || !h[name].is_number_unsigned())
      throw InputError(fmt::format("{}: header field \"{}\": missing or not an unsigned integer", file, name));
    const uint64_t v = h[name].get<uint64_t>();
    if (v < lo || v > hi) throw InputError(fmt::format("{}: header field \"{}\": {} not in {}..{}", file, name, v, lo, hi));
    return v;
  };
  r.segments = size_t(field("segments", 1, uint64_t(1) << 26));
  const uint64_t fibers = field("fibers", 1, uint64_t(1) << 32);
  r.width = int(field("width", 4, 1024));
  r.height = int(field("height", 4, 1024));
  r.axes = int(field("axes", 1, 64));
  r.components = int(field("components", 0, 1024));
  const size_t S = r.segments, P = size_t(r.width) * size_t(r.height), Q = size_t(r.axes), C = size_t(r.components);
  const size_t bitBytes = (P + 7) / 8;
  const size_t expected = S * 32 + S * 4 * (1 + Q + C) + 4 * P * (1 + C) + S * bitBytes;
  // Compare with the file's size before allocating: a header may claim terabytes.
  std::error_code ec;
  const uintmax_t total = std::filesystem::file_size(path, ec);
  if (ec || total < line.size() + 1 || total - (line.size() + 1) != expected)
    throw InputError(fmt::format("{}: byte {}: expected exactly {} bytes after the header ({} segments, {}×{} pixels, "
                                 "{} axes, {} components), the file has {}",
                                 file, line.size() + 1, expected, S, r.width, r.height, Q, C,
                                 ec ? std::string("an unknown size") : std::to_string(total - std::min<uintmax_t>(total, line.size() + 1))));
  std::vector<std::byte> body(expected);
  f.read(reinterpret_cast<char*>(body.data()), std::streamsize(expected));
  if (size_t(f.gcount()) != expected || f.peek() != std::char_traits<char>::eof())
    throw InputError(fmt::format("{}: byte {}: expected exactly {} bytes after the header ({} segments, {}×{} pixels, "
                                 "{} axes, {} components)",
                                 file, line.size() + 1, expected, S, r.width, r.height, Q, C));
  const std::byte* at = body.data();
  auto finite = [&](float v, const char* section, size_t item) {
    if (!std::isfinite(v)) throw InputError(fmt::format("{}: section {}, item {}: {} is not finite", file, section, item, v));
    return v;
  };
  for (size_t k = 0; k < S; ++k) {
    for (int i = 0; i < 7; ++i, at += 4) r.segmentTable.push_back(finite(getF32(at), "segments", k));
    r.fiber.push_back(getU32(at));
    at += 4;
    if (r.fiber.back() >= fibers)
      throw InputError(fmt::format("{}: section segments, item {}: fiber {} ≥ header \"fibers\" {}", file, k,
                                   r.fiber.back(), fibers));
  }
  for (size_t k = 0; k < S; ++k) {
    r.angle.push_back(finite(getF32(at), "svf (angle)", k));
    at += 4;
    for (size_t q = 0; q < Q; ++q, at += 4) {
      const float w = finite(getF32(at), "svf (weight)", k);
      if (w < 0.0f) throw InputError(fmt::format("{}: section svf, segment {}: weight {} is {} < 0", file, k, q, w));
      r.weights.push_back(w);
    }
    for (size_t c = 0; c < C; ++c, at += 4) r.coefficients.push_back(finite(getF32(at), "svf (coefficient)", k));
  }
  for (size_t p = 0; p < P; ++p, at += 4) r.mean.push_back(finite(getF32(at), "mean", p));
  for (size_t i = 0; i < C * P; ++i, at += 4) r.basis.push_back(finite(getF32(at), "basis", i));
  r.images.resize(S * P);
  for (size_t k = 0; k < S; ++k, at += bitBytes)
    for (size_t p = 0; p < P; ++p) r.images[k * P + p] = (uint8_t(at[p / 8]) >> (p % 8)) & 1u;
  return r;
}

}  // namespace ft
