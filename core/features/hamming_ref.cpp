// Hamming distance in C: the specification hamming_neon.cpp reproduces (brief.h).
#include <cstring>

#include "core/features/brief.h"

namespace ale::features::internal {

namespace {

// Bits set in v: sums of 2, 4, then 8 bits side by side, the four byte sums added by the multiply
// into the top byte.
inline int popcount32(std::uint32_t v) {
  v -= (v >> 1) & 0x55555555u;
  v = (v & 0x33333333u) + ((v >> 2) & 0x33333333u);
  v = (v + (v >> 4)) & 0x0F0F0F0Fu;
  return static_cast<int>((v * 0x01010101u) >> 24);
}

}  // namespace

int hamming_ref(const Descriptor& a, const Descriptor& b) {
  int d = 0;
  for (std::size_t i = 0; i < a.bytes.size(); i += 4) {
    std::uint32_t x = 0, y = 0;
    std::memcpy(&x, a.bytes.data() + i, 4);
    std::memcpy(&y, b.bytes.data() + i, 4);
    d += popcount32(x ^ y);
  }
  return d;
}

}  // namespace ale::features::internal
