// ARM NEON CLAHE interpolation, bit-exact with interpolate_row_ref() (clahe_ref.cpp).
//
// Like the reference, a pixel costs one 32-bit load from the row band's table of packed LUT
// quads (the four tiles around it), gathered into a row buffer per run of columns with one table;
// eight gathered quads are then de-interleaved with one vld4 and blended with 8- and 16-bit
// multiplies, and the band table is filled with vst4.
// Histograms and LUTs are shared with the reference (scalar by nature).
#include "core/enhance/clahe.h"

#include <algorithm>
#include <cstring>

#if defined(__ARM_NEON)
#include <arm_neon.h>
#endif

namespace ale::enhance {

bool clahe_neon_compiled() {
#if defined(__ARM_NEON)
  return true;
#else
  return false;
#endif
}

#if defined(__ARM_NEON)

void ClaheContext::fill_band_quads(int band) {
  const int tx_n = params_.tiles_x;
  const int ty_n = params_.tiles_y;
  const std::size_t lut_row = static_cast<std::size_t>(tx_n) * 256u;
  const std::uint8_t* top = luts_.data() + static_cast<std::size_t>(band > 0 ? band - 1 : 0) * lut_row;
  const std::uint8_t* bot = luts_.data() + static_cast<std::size_t>(band < ty_n ? band : ty_n - 1) * lut_row;
  auto* out = reinterpret_cast<std::uint8_t*>(quads_.data());
  for (int k = 0; k <= tx_n; ++k) {
    const std::size_t left = static_cast<std::size_t>(k > 0 ? k - 1 : 0) * 256u;
    const std::size_t right = static_cast<std::size_t>(k < tx_n ? k : tx_n - 1) * 256u;
    for (int v = 0; v < 256; v += 16) {
      uint8x16x4_t q;
      q.val[0] = vld1q_u8(top + left + v);
      q.val[1] = vld1q_u8(top + right + v);
      q.val[2] = vld1q_u8(bot + left + v);
      q.val[3] = vld1q_u8(bot + right + v);
      vst4q_u8(out, q);
      out += 64;
    }
  }
  quad_band_ = band;
}

void ClaheContext::apply_neon(GrayView src, MutableGrayView dst) {
  build_tile_luts(src);
  quad_band_ = -1;
  const int32x4_t shift = vdupq_n_s32(-shift_);
  const int vec_end = width_ & ~7;
  std::uint32_t* gathered = row_quads_.data();
  for (int y = 0; y < height_; ++y) {
    const RowPlan rp = row_plan_[static_cast<std::size_t>(y)];
    if (rp.band != quad_band_) fill_band_quads(rp.band);
    const std::uint8_t* s = src.row(y);
    std::uint8_t* d = dst.row(y);
    // Gather the row's quads in runs of columns that share a tile pair (one table each), four
    // pixels per word load; then blend eight pixels per step without table look-ups.
    for (const ColumnRun& run : col_runs_) {
      const std::uint32_t* table = quads_.data() + run.offset;
      int x = run.x_begin;
      const int x_end = std::min(run.x_end, vec_end);
      for (; x + 4 <= x_end; x += 4) {
        std::uint32_t q;
        std::memcpy(&q, s + x, 4);
        gathered[x] = table[q & 0xFFu];
        gathered[x + 1] = table[(q >> 8) & 0xFFu];
        gathered[x + 2] = table[(q >> 16) & 0xFFu];
        gathered[x + 3] = table[q >> 24];
      }
      for (; x < x_end; ++x) gathered[x] = table[s[x]];
    }
    // Locals, not members: the stores to d could alias them, which made the compiler reload the
    // weight pointers and re-insert the row weights in every iteration.
    const std::uint8_t* w_left = w_left_.data();
    const std::uint8_t* w_right = w_right_.data();
    const uint16x4_t w_top = vdup_n_u16(rp.w_top);
    const uint16x4_t w_bottom = vdup_n_u16(rp.w_bottom);
    for (int x = 0; x < vec_end; x += 8) {
      const uint8x8x4_t l = vld4_u8(reinterpret_cast<const std::uint8_t*>(gathered + x));
      const uint8x8_t wl = vld1_u8(w_left + x);
      const uint8x8_t wr = vld1_u8(w_right + x);
      const uint16x8_t h_top = vmlal_u8(vmull_u8(l.val[0], wl), l.val[1], wr);
      const uint16x8_t h_bot = vmlal_u8(vmull_u8(l.val[2], wl), l.val[3], wr);
      uint32x4_t lo = vmull_u16(vget_low_u16(h_top), w_top);
      uint32x4_t hi = vmull_u16(vget_high_u16(h_top), w_top);
      lo = vmlal_u16(lo, vget_low_u16(h_bot), w_bottom);
      hi = vmlal_u16(hi, vget_high_u16(h_bot), w_bottom);
      lo = vrshlq_u32(lo, shift);
      hi = vrshlq_u32(hi, shift);
      vst1_u8(d + x, vqmovn_u16(vcombine_u16(vmovn_u32(lo), vmovn_u32(hi))));
    }
    if (vec_end < width_) interpolate_row_ref(s, d, y, vec_end, width_);
  }
}

#else

// Never dispatched without NEON (apply() refuses kNeon); kept so the class links everywhere.
void ClaheContext::fill_band_quads(int band) { fill_band_quads_ref(band); }
void ClaheContext::apply_neon(GrayView src, MutableGrayView dst) { apply_ref(src, dst); }

#endif

}  // namespace ale::enhance
