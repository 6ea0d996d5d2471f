// Applying a 256-entry LUT with NEON table look-ups, bit-exact with apply_lut_ref() (gamma.h).
// Each 32-byte slice k of the table answers the indices in [32k, 32k + 32): vtbx leaves the other
// lanes alone, and subtracting 32 (mod 256) after each slice brings the next in range. Inline
// assembly because a table operand must be four consecutive d registers, and with intrinsics
// GCC 12 copies every slice into place (four vorr per slice). Per 32 pixels: one load, 8 slice
// loads, 32 look-ups, 14 subtractions, one store and the loop (59 instructions, about 1.9 a pixel
// against 3.75 for the reference's word loop).
//
// A row's last pixels (fewer than 32) take the reference's word loop, not an overlapping 32-pixel
// step: the feature cells' rows (36 to 42 pixels) would pay 59 instructions for 4 to 10 pixels,
// and a step overlapping pixels already mapped in place would map them twice.
#include "core/enhance/gamma.h"

#if defined(__ARM_NEON) && defined(__arm__)

namespace ale::enhance::internal {

void apply_lut_neon(GrayView src, MutableGrayView dst, const std::uint8_t* lut) {
  const int width = src.width;
  const int vec_width = width & ~31;
  for (int y = 0; y < src.height; ++y) {
    const std::uint8_t* const in = src.row(y);
    std::uint8_t* const out = dst.row(y);
    if (vec_width != 0) {
      const std::uint8_t* s = in;
      std::uint8_t* d = out;
      const std::uint8_t* const s_end = in + vec_width;
      const std::uint8_t* slice = nullptr;
#define ALE_LUT_SLICE(op) \
  "vld1.8 {d16-d19}, [%[slice]]!\n\t" op " d4, {d16-d19}, d0\n\t" op " d5, {d16-d19}, d1\n\t" op \
  " d6, {d16-d19}, d2\n\t" op " d7, {d16-d19}, d3\n\t"
#define ALE_LUT_NEXT "vsub.i8 q0, q0, q15\n\tvsub.i8 q1, q1, q15\n\t" ALE_LUT_SLICE("vtbx.8")
      asm volatile(
          "vmov.i8 q15, #32\n\t"
          "1:\n\t"
          "vld1.8 {d0-d3}, [%[s]]!\n\t"
          "mov %[slice], %[lut]\n\t"
          ALE_LUT_SLICE("vtbl.8") ALE_LUT_NEXT ALE_LUT_NEXT ALE_LUT_NEXT ALE_LUT_NEXT ALE_LUT_NEXT ALE_LUT_NEXT
          ALE_LUT_NEXT
          "vst1.8 {d4-d7}, [%[d]]!\n\t"
          "cmp %[s], %[s_end]\n\t"
          "bne 1b\n\t"
          : [s] "+r"(s), [d] "+r"(d), [slice] "=&r"(slice)
          : [lut] "r"(lut), [s_end] "r"(s_end)
          : "d0", "d1", "d2", "d3", "d4", "d5", "d6", "d7", "d16", "d17", "d18", "d19", "d30", "d31", "cc",
            "memory");
#undef ALE_LUT_NEXT
#undef ALE_LUT_SLICE
    }
    lut_row_words(in, out, vec_width, width, lut);
  }
}

}  // namespace ale::enhance::internal

#endif  // __ARM_NEON && __arm__
