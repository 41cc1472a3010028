#include "validation/vertex_compare.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <unordered_map>
#include <unordered_set>

#include "common/constants.h"

namespace ft {

void ErrorHistogram::add(double error) {
  if (!std::isfinite(error)) {  // NaN/Inf: counted as the worst error, not as an exact zero
    ++counts.back();
    return;
  }
  int bin = error > 0.0 ? static_cast<int>(std::floor(std::log10(error) - firstDecade)) : 0;
  bin = std::clamp(bin, 0, static_cast<int>(counts.size()) - 1);
  ++counts[static_cast<size_t>(bin)];
}

uint64_t vertexKey(const FiberVertex& v) {
  // segment | ply (8 bits) | fiber (16 bits) | vertex (8 bits)
  const uint64_t ply = (v.id.z >> 16) & 0xFFu, fiber = v.id.z & 0xFFFFu, vertex = (v.id.w >> 8) & 0xFFu;
  return (static_cast<uint64_t>(v.id.y) << 32) | (ply << 24) | (fiber << 8) | vertex;
}

namespace {
uint64_t strandKey(const FiberVertex& v) { return vertexKey(v) >> 8; }
std::string describe(const FiberVertex& v) {
  return fmt::format("yarn {} segment {} ply {} fiber {} vertex {} type {} period {} at ({:.7g}, {:.7g}, {:.7g}) w {:.4g}",
                     v.id.x, v.id.y, v.id.z >> 16, v.id.z & 0xFFFFu, (v.id.w >> 8) & 0xFFu, v.id.w & 0xFFu,
                     v.id.w >> 16, v.position.x, v.position.y, v.position.z, v.position.w);
}
}  // namespace

StreamComparison compareStreams(std::span<const FiberVertex> cpu, std::span<const FiberVertex> gpu,
                                double relativeFloor) {
  StreamComparison r;
  std::unordered_map<uint64_t, const FiberVertex*> gpuByKey;
  gpuByKey.reserve(gpu.size());
  std::unordered_set<uint64_t> gpuStrands, cpuStrands;
  int notes = 0;
  auto note = [&](const std::string& s) {
    if (notes++ < 8) r.firstMismatches += s + "\n";
  };
  for (const FiberVertex& v : gpu) {
    auto [it, inserted] = gpuByKey.emplace(vertexKey(v), &v);
    if (!inserted) {
      const FiberVertex& o = *it->second;
      if (o.position != v.position || o.id != v.id) {
        ++r.duplicateDisagree;
        note("GPU emitted one vertex twice with different values: " + describe(o) + " / " + describe(v));
      }
    }
    gpuStrands.insert(strandKey(v));
  }
  r.gpuVertices = gpuByKey.size();
  r.gpuFibers = gpuStrands.size();
  r.cpuVertices = cpu.size();
  double sumSq = 0.0;
  uint64_t matched = 0;
  for (const FiberVertex& c : cpu) {
    cpuStrands.insert(strandKey(c));
    auto it = gpuByKey.find(vertexKey(c));
    if (it == gpuByKey.end()) {
      ++r.missing;
      note("missing on GPU: " + describe(c));
      continue;
    }
    const FiberVertex& g = *it->second;
    ++matched;
    if (g.id != c.id) {
      ++r.idMismatch;
      note("tag differs: CPU " + describe(c) + " / GPU " + describe(g));
    }
    const glm::dvec3 d = glm::dvec3(glm::vec3(g.position)) - glm::dvec3(glm::vec3(c.position));
    const double err = glm::length(d);
    r.histogram.add(err);
    if (err > r.maxAbs && notes < 8 && err > 1e-3 * relativeFloor)
      note(fmt::format("position differs by {:.3g}: CPU {} / GPU {}", err, describe(c), describe(g)));
    r.maxAbs = maxKeepNaN(r.maxAbs, err);
    const double mag = std::max(static_cast<double>(glm::length(glm::vec3(c.position))), relativeFloor);
    r.maxRel = maxKeepNaN(r.maxRel, err / mag);
    r.maxWidthAbs = maxKeepNaN(r.maxWidthAbs, std::abs(static_cast<double>(g.position.w) - c.position.w));
    sumSq += err * err;
  }
  r.cpuFibers = cpuStrands.size();
  r.extra = r.gpuVertices - matched;
  r.rmse = matched ? std::sqrt(sumSq / static_cast<double>(matched)) : 0.0;
  if (r.extra) {
    int shown = 0;
    std::unordered_set<uint64_t> cpuKeys;
    for (const FiberVertex& c : cpu) cpuKeys.insert(vertexKey(c));
    for (const auto& [k, v] : gpuByKey)
      if (!cpuKeys.count(k) && shown++ < 3) note("extra on GPU: " + describe(*v));
  }
  return r;
}

uint64_t countNonFinite(std::span<const FiberVertex> vertices, std::string* first) {
  uint64_t n = 0;
  for (const FiberVertex& v : vertices) {
    if (std::isfinite(v.position.x) && std::isfinite(v.position.y) && std::isfinite(v.position.z) &&
        std::isfinite(v.position.w))
      continue;
    if (n++ == 0 && first) *first = "non-finite vertex: " + describe(v) + "\n";
  }
  return n;
}

}  // namespace ft
