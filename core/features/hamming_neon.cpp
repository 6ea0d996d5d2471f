// Hamming distance with NEON, bit-exact with hamming_ref() (brief.h): the two 16-byte halves
// XORed, vcnt counts each byte's bits (at most 8, so the halves' counts add in bytes), and three
// pairwise widening sums reduce the 16 byte counts to two 64-bit lanes. About 15 instructions
// where the libgcc popcount calls of a plain __builtin_popcountll loop cost about 100 on ARMv7.
#include "core/features/brief.h"

#if defined(__ARM_NEON)
#include <arm_neon.h>

namespace ale::features::internal {

int hamming_neon(const Descriptor& a, const Descriptor& b) {
  static_assert(sizeof(a.bytes) == 32, "two 16-byte halves");
  const std::uint8_t* pa = a.bytes.data();
  const std::uint8_t* pb = b.bytes.data();
  const uint8x16_t lo = veorq_u8(vld1q_u8(pa), vld1q_u8(pb));
  const uint8x16_t hi = veorq_u8(vld1q_u8(pa + 16), vld1q_u8(pb + 16));
  const uint8x16_t counts = vaddq_u8(vcntq_u8(lo), vcntq_u8(hi));
  const uint64x2_t sums = vpaddlq_u32(vpaddlq_u16(vpaddlq_u8(counts)));
  const uint64x1_t total = vadd_u64(vget_low_u64(sums), vget_high_u64(sums));
  return static_cast<int>(vget_lane_u32(vreinterpret_u32_u64(total), 0));
}

}  // namespace ale::features::internal

#endif  // __ARM_NEON
