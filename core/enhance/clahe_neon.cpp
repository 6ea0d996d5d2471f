// ARM NEON CLAHE: LUT build and interpolation, bit-exact with build_tile_luts() and
// interpolate_row_ref() (clahe_ref.cpp).
//
// Like the reference, a pixel costs one 32-bit load from the row band's table of packed LUT
// quads (the four tiles around it), gathered into a row buffer per run of columns with one table
// (eight pixels a step, 22 instructions in Thumb-2 assembly); eight gathered quads are then
// de-interleaved with one vld4 and blended with 8- and 16-bit multiplies (30 instructions per 16 pixels in inline
// assembly, an 8-pixel step with intrinsics for the rest and a last vector that overlaps the one
// before when the width is not a multiple of 8), and the band table is filled with vst4.
// The tile grid's walk is shared with the reference (count_tiles, clahe_ref.cpp); its histogram
// kernel, and the feature cells' histogram and gap search, are below.
#include "core/enhance/clahe.h"
#include "core/enhance/kernels.h"

#include <algorithm>
#include <cstring>

#if defined(__ARM_NEON)
#include <arm_neon.h>

namespace ale::enhance {

namespace internal {

#if defined(__arm__)
namespace {

// row[x0..x1) into two histograms, as the reference's count_row. Per pixel a byte load and the
// counter's load, add and store, 8 pixels per loop test (4.25 instructions a pixel), in inline
// assembly because GCC 12 keeps eight extracted indices live at once and spills around every
// row's loop (about 25 instructions per row on top of 4.6 a pixel).
// A lambda, so that the walks in clahe.h inline it.
const auto count_row = [](const std::uint8_t* row, int x0, int x1, std::uint32_t* h0, std::uint32_t* h1) {
  const std::uint8_t* p = row + x0;
  const std::uint8_t* const end = row + x1;
  const std::uint8_t* const end8 = p + ((x1 - x0) & ~7);
  if (p != end8) {
    std::uint32_t v, c;
#define ALE_COUNT(h)                                                                            \
  "ldrb %[v], [%[p]], #1\n\tldr %[c], [%[" h "], %[v], lsl #2]\n\tadd %[c], %[c], #1\n\t" \
  "str %[c], [%[" h "], %[v], lsl #2]\n\t"
    asm volatile("1:\n\t" ALE_COUNT("h0") ALE_COUNT("h1") ALE_COUNT("h0") ALE_COUNT("h1") ALE_COUNT("h0")
                     ALE_COUNT("h1") ALE_COUNT("h0") ALE_COUNT("h1") "cmp %[p], %[end8]\n\tbne 1b\n\t"
                 : [p] "+r"(p), [v] "=&r"(v), [c] "=&r"(c)
                 : [end8] "r"(end8), [h0] "r"(h0), [h1] "r"(h1)
                 : "cc", "memory");
#undef ALE_COUNT
  }
  for (; p != end; ++p) ++h0[*p];
};

}  // namespace

void histogram_neon(GrayView image, std::uint32_t* h0, std::uint32_t* h1) { histogram_walk(image, h0, h1, count_row); }

void tile_histograms_neon(GrayView src, const int* rows, int n_rows, const int* col_end, int n_tiles,
                          std::uint32_t* hists) {
  tile_histograms_walk(src, rows, n_rows, col_end, n_tiles, hists, count_row);
}
#endif  // __arm__

int min_gap_neon(const std::uint8_t* lut, int lo, int hi, int first, int threshold) {
  // By increasing gap d, the largest rise lut[v + d] - lut[v] over the range, 16 v at a time. The
  // last vector reads up to hi + 15, where the table repeats lut[hi]: there a "pair" is (v, hi)
  // with a gap below d, or rises by 0, and a rise of more than `threshold` at a gap below d would
  // have ended an earlier d. A typical cell (range 76, first gap 14) takes a few gaps of about 5
  // vectors.
  for (int d = first; d <= hi - lo; ++d) {
    const std::uint8_t* p = lut + lo;
    const std::uint8_t* const end = lut + hi - d;  // the last v of a real pair
    uint8x16_t rise = vdupq_n_u8(0);
    for (; p <= end; p += 16) rise = vmaxq_u8(rise, vsubq_u8(vld1q_u8(p + d), vld1q_u8(p)));
    uint8x8_t r = vpmax_u8(vget_low_u8(rise), vget_high_u8(rise));
    r = vpmax_u8(r, r);
    r = vpmax_u8(r, r);
    r = vpmax_u8(r, r);
    if (vget_lane_u8(r, 0) > threshold) return d;
  }
  return 256;
}

}  // namespace internal

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

namespace {

// g[i] = table[p[i]] for the 8-pixel steps from p to p_end (at least one), advancing p and g. In
// Thumb-2 assembly: per pixel a byte load and a table load, per pair of pixels one 64-bit store
// (22 instructions per 8 pixels with the loop test, against 33 from GCC 12, which extracts bytes
// from words and stores word by word).
inline void gather8(const std::uint32_t* table, const std::uint8_t*& p, const std::uint8_t* p_end,
                    std::uint32_t*& g) {
#if defined(__thumb2__)
  std::uint32_t t0, t1;
#define ALE_GATHER_PAIR                                                                        \
  "ldrb %[t0], [%[p]], #1\n\tldrb %[t1], [%[p]], #1\n\tldr %[t0], [%[tab], %[t0], lsl #2]\n\t" \
  "ldr %[t1], [%[tab], %[t1], lsl #2]\n\tstrd %[t0], %[t1], [%[g]], #8\n\t"
  asm volatile("1:\n\t" ALE_GATHER_PAIR ALE_GATHER_PAIR ALE_GATHER_PAIR ALE_GATHER_PAIR
               "cmp %[p], %[end]\n\tbne 1b\n\t"
               : [p] "+r"(p), [g] "+r"(g), [t0] "=&r"(t0), [t1] "=&r"(t1)
               : [tab] "r"(table), [end] "r"(p_end)
               : "cc", "memory");
#undef ALE_GATHER_PAIR
#else
  for (; p != p_end; p += 8, g += 8) {
    std::uint32_t a, b;
    std::memcpy(&a, p, 4);
    std::memcpy(&b, p + 4, 4);
    g[0] = table[a & 0xFFu];
    g[1] = table[(a >> 8) & 0xFFu];
    g[2] = table[(a >> 16) & 0xFFu];
    g[3] = table[a >> 24];
    g[4] = table[b & 0xFFu];
    g[5] = table[(b >> 8) & 0xFFu];
    g[6] = table[(b >> 16) & 0xFFu];
    g[7] = table[b >> 24];
  }
#endif
}

}  // namespace

// The reference's LUT build (build_tile_luts) four bins at a time: clip with the excess summed
// in lanes; then per four bins a prefix sum (two shifted adds plus the carry) to which the
// redistribution is added in closed form, and the same multiply-by-reciprocal division with its
// one correction; saturating narrows do the clamp to 255. The reference adds one to the residual
// bins 0, step, 2*step, ... (residual of them, all below 256), so up to bin i it added
// min(residual, i / step + 1), with i / step = (i * ceil(2^16 / step)) >> 16, exact for i < 256.
void ClaheContext::build_tile_luts_neon(GrayView src) {
  const int tiles = params_.tiles_x * params_.tiles_y;
  const auto clip = static_cast<std::uint32_t>(clip_);
  const auto area = static_cast<std::uint32_t>(area_);
  const uint32x2_t recip = vdup_n_u32(area_recip_);
  const uint32x4_t area_v = vdupq_n_u32(area);
  const uint32x4_t half_area = vdupq_n_u32(area / 2u);
  const uint32x4_t k255 = vdupq_n_u32(255u);
  const uint32x4_t zero = vdupq_n_u32(0);
  const uint32x4_t one = vdupq_n_u32(1);
  const uint32x4_t four = vdupq_n_u32(4);
  static const std::uint32_t kLanes[4] = {0, 1, 2, 3};
  const uint32x4_t lanes = vld1q_u32(kLanes);
  if (counted_ != src.data || counted_stride_ != src.stride) count_tiles(src, kernels(KernelPath::kNeon).tile_histograms);
  counted_ = nullptr;  // the tables below clip the histograms in place
  for (int t = 0; t < tiles; ++t) {
    std::uint32_t* const h = tile_hist_.data() + static_cast<std::size_t>(t) * 256u;
    std::uint32_t batch = 0, residual = 0, step_recip = 0;
    if (clip > 0) {
      const uint32x4_t clip_v = vdupq_n_u32(clip);
      uint32x4_t excess = zero;
      for (std::uint32_t* p = h; p != h + 256; p += 8) {
        const uint32x4_t a = vld1q_u32(p);
        const uint32x4_t b = vld1q_u32(p + 4);
        excess = vaddq_u32(excess, vaddq_u32(vqsubq_u32(a, clip_v), vqsubq_u32(b, clip_v)));
        vst1q_u32(p, vminq_u32(a, clip_v));
        vst1q_u32(p + 4, vminq_u32(b, clip_v));
      }
      const uint32x2_t e2 = vadd_u32(vget_low_u32(excess), vget_high_u32(excess));
      const std::uint32_t clipped = vget_lane_u32(vpadd_u32(e2, e2), 0);  // <= area < 2^24
      batch = clipped / 256u;
      residual = clipped % 256u;
      if (residual != 0) {
        const std::uint32_t step = std::max(256u / residual, 1u);
        step_recip = (65536u + step - 1u) / step;
      }
    }
    const uint32x4_t batch_v = vdupq_n_u32(batch);
    const uint32x4_t residual_v = vdupq_n_u32(residual);
    const uint32x4_t step_recip_v = vdupq_n_u32(step_recip);
    uint32x4_t carry = zero;
    uint32x4_t bin = lanes;
    const auto scaled = [&](const std::uint32_t* p) {
      uint32x4_t c = vld1q_u32(p);
      c = vaddq_u32(c, vextq_u32(zero, c, 3));
      c = vaddq_u32(c, vextq_u32(zero, c, 2));
      c = vaddq_u32(c, carry);
      carry = vdupq_lane_u32(vget_high_u32(c), 1);
      // + (bin + 1) * batch + min(residual, bin / step + 1)
      const uint32x4_t spread = vminq_u32(vaddq_u32(vshrq_n_u32(vmulq_u32(bin, step_recip_v), 16), one), residual_v);
      c = vaddq_u32(c, vmlaq_u32(vaddq_u32(spread, batch_v), bin, batch_v));
      bin = vaddq_u32(bin, four);
      const uint32x4_t n = vmlaq_u32(half_area, c, k255);
      // The high words of the 64-bit products n * recip.
      uint32x4_t q = vuzpq_u32(vreinterpretq_u32_u64(vmull_u32(vget_low_u32(n), recip)),
                               vreinterpretq_u32_u64(vmull_u32(vget_high_u32(n), recip)))
                         .val[1];
      // q is low by at most one: add one where the remainder still reaches the area.
      q = vsubq_u32(q, vcgeq_u32(vmlsq_u32(n, q, area_v), area_v));
      return vqmovn_u32(q);
    };
    std::uint8_t* lut = luts_.data() + static_cast<std::size_t>(t) * 256u;
    for (const std::uint32_t* p = h; p != h + 256; p += 8, lut += 8)
      vst1_u8(lut, vqmovn_u16(vcombine_u16(scaled(p), scaled(p + 4))));
  }
}

void ClaheContext::apply_neon(GrayView src, MutableGrayView dst) {
  build_tile_luts_neon(src);
  quad_band_ = -1;
  if (width_ < 8) {  // no full vector: the reference blend
    for (int y = 0; y < height_; ++y) {
      const int band = row_plan_[static_cast<std::size_t>(y)].band;
      if (band != quad_band_) fill_band_quads(band);
      interpolate_row_ref(src.row(y), dst.row(y), y, 0, width_);
    }
    return;
  }
  const int32x4_t shift = vdupq_n_s32(-shift_);
  // The last vector overlaps the one before when the width is not a multiple of 8 (same values
  // written twice), so every pixel is blended here.
  const int last = width_ - 8;
  std::uint32_t* const gathered = row_quads_.data();
  const ColumnRun* const runs_begin = col_runs_.data();
  const ColumnRun* const runs_end = runs_begin + col_runs_.size();
  const std::uint32_t* const quads = quads_.data();
  for (int y = 0; y < height_; ++y) {
    const RowPlan rp = row_plan_[static_cast<std::size_t>(y)];
    if (rp.band != quad_band_) fill_band_quads(rp.band);
    const std::uint8_t* const s = src.row(y);
    std::uint8_t* const d = dst.row(y);
    // Gather the row's quads in runs of columns that share a tile pair (one table each), eight
    // pixels per step; a run's last step may run into the next run's columns, which that run
    // then overwrites (ColumnRun::vec_end).
    for (const ColumnRun* run = runs_begin; run != runs_end; ++run) {
      const std::uint32_t* const table = quads + run->offset;
      const std::uint8_t* p = s + run->x_begin;
      std::uint32_t* g = gathered + run->x_begin;
      const std::uint8_t* const p_vec_end = s + run->vec_end;
      if (p != p_vec_end) gather8(table, p, p_vec_end, g);
      for (const std::uint8_t* const p_end = s + run->x_end; p < p_end; ++p, ++g) *g = table[*p];
    }
    // Locals, not members: the stores to d could alias them, which made the compiler reload the
    // weight pointers and re-insert the row weights in every iteration.
    const std::uint8_t* w = w_lr_.data();
    const std::uint8_t* q = reinterpret_cast<const std::uint8_t*>(gathered);
    const uint16x4_t w_top = vdup_n_u16(rp.w_top);
    const uint16x4_t w_bottom = vdup_n_u16(rp.w_bottom);
    const auto blend8 = [&](const std::uint8_t* qp, const std::uint8_t* wp, std::uint8_t* out) {
      const uint8x8x4_t l = vld4_u8(qp);
      const uint8x8x2_t lr = vld2_u8(wp);
      const uint16x8_t h_top = vmlal_u8(vmull_u8(l.val[0], lr.val[0]), l.val[1], lr.val[1]);
      const uint16x8_t h_bot = vmlal_u8(vmull_u8(l.val[2], lr.val[0]), l.val[3], lr.val[1]);
      uint32x4_t lo = vmull_u16(vget_low_u16(h_top), w_top);
      uint32x4_t hi = vmull_u16(vget_high_u16(h_top), w_top);
      lo = vmlal_u16(lo, vget_low_u16(h_bot), w_bottom);
      hi = vmlal_u16(hi, vget_high_u16(h_bot), w_bottom);
      // After the shift every lane is at most 256: its low half is the value, and one unzip
      // gathers the eight low halves.
      const uint16x8x2_t z = vuzpq_u16(vreinterpretq_u16_u32(vrshlq_u32(lo, shift)),
                                       vreinterpretq_u16_u32(vrshlq_u32(hi, shift)));
      vst1_u8(out, vqmovn_u16(z.val[0]));
    };
    std::uint8_t* o = d;
#if defined(__arm__)
    if (width_ >= 16) {
      std::uint8_t* const o_end = d + (width_ & ~15);
      const uint16x4_t wt = w_top, wb = w_bottom;
      const int32x4_t sh = shift;
      // blend8 twice per step in inline assembly (GCC 12 adds register copies): 30 instructions
      // per 16 pixels with the loads, the store and the loop test.
#define ALE_BLEND_HALF(a, b, c, dd, wl, wr, out)                                                       \
  "vmull.u8 q0, " a ", " wl "\n\tvmlal.u8 q0, " b ", " wr "\n\tvmull.u8 q1, " c ", " wl "\n\t"          \
  "vmlal.u8 q1, " dd ", " wr "\n\tvmull.u16 q2, d0, %P[wt]\n\tvmull.u16 q3, d1, %P[wt]\n\t"           \
  "vmlal.u16 q2, d2, %P[wb]\n\tvmlal.u16 q3, d3, %P[wb]\n\tvrshl.u32 q2, q2, %q[sh]\n\t"               \
  "vrshl.u32 q3, q3, %q[sh]\n\tvuzp.16 q2, q3\n\tvqmovn.u16 " out ", q2\n\t"
      asm volatile("1:\n\t"
                   "vld4.8 {d16-d19}, [%[q]]!\n\t"
                   "vld4.8 {d20-d23}, [%[q]]!\n\t"
                   "vld2.8 {d24-d27}, [%[w]]!\n\t"  // q12 left weights, q13 right weights
                   ALE_BLEND_HALF("d16", "d17", "d18", "d19", "d24", "d26", "d28")
                       ALE_BLEND_HALF("d20", "d21", "d22", "d23", "d25", "d27", "d29")
                   "vst1.8 {d28-d29}, [%[o]]!\n\t"
                   "cmp %[o], %[o_end]\n\t"
                   "bne 1b\n\t"
                   : [q] "+r"(q), [w] "+r"(w), [o] "+r"(o)
                   : [o_end] "r"(o_end), [wt] "w"(wt), [wb] "w"(wb), [sh] "w"(sh)
                   : "d0", "d1", "d2", "d3", "d4", "d5", "d6", "d7", "d16", "d17", "d18", "d19", "d20", "d21",
                     "d22", "d23", "d24", "d25", "d26", "d27", "d28", "d29", "cc", "memory");
#undef ALE_BLEND_HALF
    }
#endif
    for (std::uint8_t* const o_end = d + (width_ & ~7); o != o_end; o += 8, q += 32, w += 16) blend8(q, w, o);
    if (o != d + width_) {
      const auto x = static_cast<std::size_t>(last);
      blend8(reinterpret_cast<const std::uint8_t*>(gathered + x), w_lr_.data() + 2 * x, d + x);
    }
  }
}

}  // namespace ale::enhance

#endif  // __ARM_NEON
