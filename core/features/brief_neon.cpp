// BRIEF bits on armhf, bit-exact with describe_ref() (brief.h). Scalar Thumb-2 assembly, not NEON:
// the bits come from 512 byte gathers, which NEON cannot do, but the build's NEON kernels and this
// one are one path. Per pair two byte loads at (centre + offset), cmp (carry = first >= second)
// and adc acc, acc, acc (acc = 2 acc + carry): 5 instructions per bit, where GCC compiles the
// reference's loop to about 10 (it shifts, compares and adds the carry under an IT block). Two
// pairs are loaded ahead of their compares so the in-order Cortex-A7 does not wait on each load.
#include "core/features/brief.h"

#if defined(__ARM_NEON) && defined(__thumb2__)

namespace ale::features::internal {

namespace {

#define ALE_BRIEF_TWO_BITS                          \
  "ldrd %[a0], %[b0], [%[p]], #8\n\t"              \
  "ldrd %[a1], %[b1], [%[p]], #8\n\t"              \
  "ldrb %[a0], [%[c], %[a0]]\n\t"                  \
  "ldrb %[b0], [%[c], %[b0]]\n\t"                  \
  "ldrb %[a1], [%[c], %[a1]]\n\t"                  \
  "ldrb %[b1], [%[c], %[b1]]\n\t"                  \
  "cmp %[a0], %[b0]\n\t"                           \
  "adc %[acc], %[acc], %[acc]\n\t"                 \
  "cmp %[a1], %[b1]\n\t"                           \
  "adc %[acc], %[acc], %[acc]\n\t"

inline std::uint32_t not_less_word(const std::uint8_t* centre, const std::int32_t*& p) {
  std::uint32_t acc = 0;
  for (int k = 0; k < 4; ++k) {
    std::uint32_t a0, b0, a1, b1;
    asm(ALE_BRIEF_TWO_BITS ALE_BRIEF_TWO_BITS ALE_BRIEF_TWO_BITS ALE_BRIEF_TWO_BITS
        : [acc] "+r"(acc), [p] "+r"(p), [a0] "=&r"(a0), [b0] "=&r"(b0), [a1] "=&r"(a1), [b1] "=&r"(b1)
        : [c] "r"(centre)
        : "cc", "memory");
  }
  return acc;
}
#undef ALE_BRIEF_TWO_BITS

}  // namespace

void describe_neon(GrayView smoothed, int x, int y, const RotatedPattern& rotated, int bin, Descriptor& out) {
  describe_words(smoothed, x, y, rotated, bin, out, not_less_word);
}

}  // namespace ale::features::internal

#endif  // __ARM_NEON && __thumb2__
