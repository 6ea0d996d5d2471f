#include "core/enhance/gamma.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__ARM_NEON)
#include <arm_neon.h>
#endif

namespace ale::enhance {

double cdf_gamma(const FrameStats& stats, const GammaParams& p) {
  if (stats.pixels == 0) return 1.0;
  const int t = std::clamp(p.cdf_point, 0, 255);
  std::uint64_t cum = 0;
  for (int v = 0; v <= t; ++v) cum += stats.histogram[static_cast<std::size_t>(v)];
  if (cum == 0) return 1.0;  // nothing at or below t: the frame needs no lift
  const double c = static_cast<double>(cum) / static_cast<double>(stats.pixels);
  return std::clamp(p.alpha / c, p.gamma_min, 1.0);
}

void gamma_lut(double gamma, Lut& lut) {
  for (int i = 0; i < 256; ++i)
    lut[static_cast<std::size_t>(i)] =
        static_cast<std::uint8_t>(std::lround(255.0 * std::pow(static_cast<double>(i) / 255.0, gamma)));
}

void lut_row(const std::uint8_t* in, std::uint8_t* out, int width, const std::uint8_t* lut) {
  int x = 0;
#if defined(__ARM_NEON)
  // Each 32-byte slice k of the table answers the indices in [32k, 32k + 32): vtbx leaves the
  // other lanes alone, and subtracting 32 (mod 256) after each slice brings the next in range.
  // Inline assembly because a table operand must be four consecutive d registers, and with
  // intrinsics GCC 12 copies every slice into place (four vorr per slice). Per 32 pixels: one
  // load, 8 slice loads, 32 look-ups, 14 subtractions, one store and the loop (59 instructions).
  if (width >= 32) {
    const std::uint8_t* src = in;
    std::uint8_t* dst = out;
    const std::uint8_t* const src_end = in + (width & ~31);
    const std::uint8_t* slice = nullptr;
#define ALE_LUT_SLICE(op) \
  "vld1.8 {d16-d19}, [%[slice]]!\n\t" op " d4, {d16-d19}, d0\n\t" op " d5, {d16-d19}, d1\n\t" op \
  " d6, {d16-d19}, d2\n\t" op " d7, {d16-d19}, d3\n\t"
#define ALE_LUT_NEXT "vsub.i8 q0, q0, q15\n\tvsub.i8 q1, q1, q15\n\t" ALE_LUT_SLICE("vtbx.8")
    asm volatile(
        "vmov.i8 q15, #32\n\t"
        "1:\n\t"
        "vld1.8 {d0-d3}, [%[src]]!\n\t"
        "mov %[slice], %[lut]\n\t"
        ALE_LUT_SLICE("vtbl.8") ALE_LUT_NEXT ALE_LUT_NEXT ALE_LUT_NEXT ALE_LUT_NEXT ALE_LUT_NEXT ALE_LUT_NEXT
        ALE_LUT_NEXT
        "vst1.8 {d4-d7}, [%[dst]]!\n\t"
        "cmp %[src], %[src_end]\n\t"
        "bne 1b\n\t"
        : [src] "+r"(src), [dst] "+r"(dst), [slice] "=&r"(slice)
        : [lut] "r"(lut), [src_end] "r"(src_end)
        : "d0", "d1", "d2", "d3", "d4", "d5", "d6", "d7", "d16", "d17", "d18", "d19", "d30", "d31", "cc", "memory");
#undef ALE_LUT_NEXT
#undef ALE_LUT_SLICE
    x = width & ~31;
  }
#endif
  // Four pixels per word load and store: about half the instructions of a byte loop.
  for (; x + 4 <= width; x += 4) {
    std::uint32_t q;
    std::memcpy(&q, in + x, 4);
    const std::uint32_t r = std::uint32_t{lut[q & 0xFFu]} | std::uint32_t{lut[(q >> 8) & 0xFFu]} << 8 |
                            std::uint32_t{lut[(q >> 16) & 0xFFu]} << 16 | std::uint32_t{lut[q >> 24]} << 24;
    std::memcpy(out + x, &r, 4);
  }
  for (; x < width; ++x) out[x] = lut[in[x]];
}

Status apply_lut(GrayView src, MutableGrayView dst, const Lut& lut) {
  ALE_RETURN_IF_ERROR(check_view(src, "lut source"));
  ALE_RETURN_IF_ERROR(check_view(dst, "lut destination"));
  if (src.width != dst.width || src.height != dst.height)
    return invalid_argument("apply_lut: source and destination sizes differ");
  for (int y = 0; y < src.height; ++y) lut_row(src.row(y), dst.row(y), src.width, lut.data());
  return {};
}

}  // namespace ale::enhance
