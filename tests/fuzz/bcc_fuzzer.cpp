// bcc_fuzzer.cpp — libFuzzer target for parseBcc. Only InputError may escape
// the parser; anything else (another exception, a sanitizer report) is a bug.
// An accepted model must also satisfy what the generators rely on, so the
// fuzzer checks those invariants too (a silently wrong model is a bug as well).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "scene/bcc_reader.h"
#include "scene/input_error.h"

namespace {

void check(bool ok) {
  if (!ok) __builtin_trap();
}

void checkModel(const ft::YarnModel& m, size_t inputSize) {
  check(!m.curves.empty());
  size_t points = 0;
  for (const ft::YarnCurve& c : m.curves) {
    const size_t n = c.points.size();
    check(n >= (c.closed ? 3u : 2u));
    check(c.basis == FT_BASIS_CATMULL_ROM);
    for (size_t i = 0; i < n; ++i) {
      const glm::vec3 p = c.points[i];
      check(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
      if (i > 0) check(p != c.points[i - 1]);
    }
    if (c.closed) check(c.points.back() != c.points.front());
    points += n;
  }
  // Never more data out than the file held: 64-byte header, 4 + 12 n per curve.
  check(64 + 4 * m.curves.size() + 12 * points <= inputSize);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::span bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    checkModel(ft::parseBcc(bytes, "fuzz.bcc"), size);
  } catch (const ft::InputError&) {
  }
  return 0;
}
