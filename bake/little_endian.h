// little_endian.h — the byte order of the bakes' binary outputs: 32- and
// 64-bit words little-endian, floats as their IEEE-754 bits, whatever the
// host (the outputs are compared byte for byte across machines and rank counts).
#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace ft {

static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559);

inline void putU32(std::vector<std::byte>& out, uint32_t u) {
  for (int b = 0; b < 4; ++b) out.push_back(std::byte((u >> (8 * b)) & 0xffu));
}
inline void putU64(std::vector<std::byte>& out, uint64_t u) {
  putU32(out, uint32_t(u & 0xffffffffu));
  putU32(out, uint32_t(u >> 32));
}
inline void putF32(std::vector<std::byte>& out, float f) { putU32(out, std::bit_cast<uint32_t>(f)); }
inline uint32_t getU32(const std::byte* in) {
  uint32_t u = 0;
  for (int b = 0; b < 4; ++b) u |= uint32_t(in[b]) << (8 * b);
  return u;
}
inline uint64_t getU64(const std::byte* in) { return uint64_t(getU32(in)) | (uint64_t(getU32(in + 4)) << 32); }
inline float getF32(const std::byte* in) { return std::bit_cast<float>(getU32(in)); }

}  // namespace ft
