#include "core/features/cell_clahe.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/enhance/gamma.h"
#include "core/enhance/level_clahe.h"
#include "core/features/fast.h"

#if defined(__ARM_NEON)
#include <arm_neon.h>
#endif

namespace ale::features {

Status CellClahe::apply(const enhance::LevelClaheParams& p, double scale, GrayView src, MutableGrayView dst) {
  ALE_RETURN_IF_ERROR(check_view(dst, "cell clahe destination"));
  if (dst.width != src.width || dst.height != src.height)
    return invalid_argument("cell clahe: destination size differs from the source");
  ALE_RETURN_IF_ERROR(plan(p, scale, src));
  if (!single_) return enhance::contrast_guided_clahe(general_, p, scale, src, dst);
  map(src, dst);
  return {};
}

Status CellClahe::plan(const enhance::LevelClaheParams& p, double scale, GrayView src) {
  ALE_RETURN_IF_ERROR(check_view(src, "cell clahe source"));
  return plan(p, scale, src, moments(src));
}

Status CellClahe::plan(const enhance::LevelClaheParams& p, double scale, GrayView src,
                       const enhance::Moments& moments) {
  ALE_RETURN_IF_ERROR(check_view(src, "cell clahe source"));
  single_ = false;
  const int w = src.width;
  const int h = src.height;
  const std::uint32_t area = static_cast<std::uint32_t>(w) * static_cast<std::uint32_t>(h);
  // 255 * area must fit 32 bits below (and core/enhance caps a tile at 2^24 pixels).
  if (area >= (1u << 22)) return {};
  // hist_ is all zero between calls: only the cell's grey range [lo, hi] is ever written, and it
  // is cleared again before returning.
  std::uint32_t* hist = hist_.data();  // a plain pointer lets the compiler index it by register
  for (int y = 0; y < h; ++y) enhance::count_row(src.row(y), 0, w, hist, hist);
  // Retried cells are low-contrast, so the range is narrow and the work below is on it alone.
  std::uint32_t lo = static_cast<std::uint32_t>(std::clamp(moments.min, 0, 255)), hi = 255;
  while (hist_[lo] == 0) ++lo;
  while (hist_[hi] == 0) --hi;
  build_table(p, scale, w, h, moments.sigma, lo, hi);
  std::fill(hist_.begin() + lo, hist_.begin() + hi + 1, 0u);
  return {};
}

void CellClahe::build_table(const enhance::LevelClaheParams& p, double scale, int w, int h, double sigma,
                            std::uint32_t lo, std::uint32_t hi) {
  const std::uint32_t area = static_cast<std::uint32_t>(w) * static_cast<std::uint32_t>(h);
  int median = static_cast<int>(lo);
  for (std::uint32_t cum = 0; median < 256; ++median) {
    cum += hist_[static_cast<std::size_t>(median)];
    if (2 * cum >= area) break;
  }
  const double dn = static_cast<double>(area);
  const enhance::LevelClaheSettings s = enhance::level_clahe_settings(p, scale, w, h, sigma, median);
  if (s.clahe.tiles_x != 1 || s.clahe.tiles_y != 1) return;
  single_ = true;
  lo_ = static_cast<int>(lo);
  hi_ = static_cast<int>(hi);
  // One tile of w x h: clipping and the LUT exactly as ClaheContext (clahe_ref.cpp), which adds
  // `batch` to every bin and one more to `residual` bins 0, step, 2 step, ...; here those additions
  // are counted into the running sum instead of written, since only [lo, hi] of the table is read.
  std::uint32_t batch = 0, residual = 0, step = 256, clip = area;
  if (s.clahe.clip_limit > 0.0) {
    const double limit = s.clahe.clip_limit * dn / 256.0;
    clip = limit >= dn ? area : static_cast<std::uint32_t>(std::max(static_cast<int>(limit), 1));
    std::uint32_t clipped = 0;
    for (std::uint32_t v = lo; v <= hi; ++v) {  // clip >= 1 leaves the empty bins alone
      std::uint32_t& c = hist_[v];
      if (c > clip) {
        clipped += c - clip;
        c = clip;
      }
    }
    batch = clipped / 256u;
    residual = clipped % 256u;
    if (residual != 0) step = std::max(256u / residual, 1u);
  }
  area_ = area;
  bin_max_ = clip + batch + 1u;  // what a bin of the clipped, spread histogram holds at most
  // The interpolation of a single tile blends four equal values: (lut * Dx * W + round) >> K with
  // the horizontal denominator Dx, the vertical weight total W and shift K of ClaheContext.
  const enhance::BlendScale blend = enhance::blend_scale(w);
  const auto dx = static_cast<std::uint32_t>(blend.dx);
  const int shift = blend.shift;
  const auto w_total = static_cast<std::uint32_t>(blend.w_total);
  const std::uint32_t round = 1u << (shift - 1);
  // floor(n / area) by a multiply with floor((2^32-1) / area) and one correction (as ClaheContext).
  const std::uint32_t recip = 0xFFFFFFFFu / area;
  // Residual bins below lo, then the next residual bin at or above lo.
  std::uint32_t extra = residual == 0 ? 0 : std::min(residual, (lo + step - 1) / step);
  std::uint32_t next_extra = extra * step;
  std::uint32_t cum = batch * lo + extra;
  for (std::uint32_t i = lo; i <= hi; ++i) {
    cum += hist_[i] + batch;
    if (extra < residual && i == next_extra) {
      ++cum;
      ++extra;
      next_extra += step;
    }
    const std::uint32_t n = cum * 255u + area / 2u;
    std::uint32_t q0 = static_cast<std::uint32_t>((std::uint64_t{n} * recip) >> 32);
    if (n - q0 * area >= area) ++q0;
    const std::uint32_t lut = q0 > 255u ? 255u : q0;
    const std::uint32_t out = (lut * dx * w_total + round) >> shift;
    lut_[i] = static_cast<std::uint8_t>(out > 255u ? 255u : out);
  }
  // min_raw_gap() reads whole vectors past hi (the table stays monotonic).
#if defined(__ARM_NEON)
  vst1q_u8(lut_.data() + hi + 1, vdupq_n_u8(lut_[hi]));
#endif
}

namespace {

// The score bound of a single-tile table with this clip limit: after clipping and spreading a
// bin holds at most clip + area / 256 + 1 pixels, so d grey levels rise the table by at most
// ceil(255 d H / area), plus one for its final rescaling (which keeps values within 0.01).
// Rising by more than threshold needs 255 d H > (threshold - 1) area. A larger clip limit gives
// a smaller bound.
int needed_for_clip(double clip_limit, std::uint32_t area, int threshold) {
  if (clip_limit <= 0.0) return 0;
  const double dn = static_cast<double>(area);
  const double limit = clip_limit * dn / 256.0;
  const std::uint32_t clip = limit >= dn ? area : static_cast<std::uint32_t>(std::max(static_cast<int>(limit), 1));
  // 32-bit arithmetic (a 64-bit division is a library call on ARM): area < 2^22 and threshold < 256
  // keep (threshold - 1) * area below 2^30, and bin_max <= area + area / 256 + 1 keeps 255 * bin_max
  // below 2^31.
  const std::uint32_t bin_max = std::min(clip, area) + area / 256u + 1u;
  const std::uint32_t needed = static_cast<std::uint32_t>(threshold - 1) * area / (255u * bin_max);
  return static_cast<int>(std::min<std::uint32_t>(needed, 255u));
}

// Whether the cell's grid is one tile and the bounds apply at all (tiles as plan() allows; a clip
// limit falling with contrast would turn the bounds around).
bool bounds_apply(const enhance::LevelClaheParams& p, double scale, int w, int h, int threshold) {
  const std::uint32_t area = static_cast<std::uint32_t>(w) * static_cast<std::uint32_t>(h);
  if (w < 1 || h < 1 || area >= (1u << 22) || p.clip_contrast < 0.0 || threshold < 1) return false;
  const enhance::LevelClaheSettings grid = enhance::level_clahe_settings(p, scale, w, h, 0.0, 1);
  return grid.clahe.tiles_x == 1 && grid.clahe.tiles_y == 1;
}

}  // namespace

int CellClahe::param_needed_score(const enhance::LevelClaheParams& p, double scale, int w, int h, int threshold) {
  if (!bounds_apply(p, scale, w, h, threshold)) return 0;
  // The clip limit is at most clip_max whatever the cell.
  return needed_for_clip(std::max(p.clip_max, p.clip_min),
                         static_cast<std::uint32_t>(w) * static_cast<std::uint32_t>(h), threshold);
}

int CellClahe::quick_needed_score(const enhance::LevelClaheParams& p, double scale, GrayView src, int threshold) {
  if (!bounds_apply(p, scale, src.width, src.height, threshold)) return 0;
  return quick_needed_score(p, scale, src.width, src.height, moments(src), threshold);
}

int CellClahe::quick_needed_score(const enhance::LevelClaheParams& p, double scale, int w, int h,
                                  const enhance::Moments& mo, int threshold) {
  if (!bounds_apply(p, scale, w, h, threshold)) return 0;
  const std::uint32_t area = static_cast<std::uint32_t>(w) * static_cast<std::uint32_t>(h);
  // As plan(): the same sigma. The median is at least the minimum and at least mean - sigma (a
  // median lies within one standard deviation of the mean), so the contrast and with it the clip
  // limit are at most these.
  const int median_at_least = std::max(mo.min, static_cast<int>(std::floor(mo.mean - mo.sigma)));
  return needed_for_clip(enhance::level_clahe_settings(p, scale, w, h, mo.sigma, median_at_least).clahe.clip_limit,
                         area, threshold);
}

#if defined(__ARM_NEON)
namespace {

// Sums of a cell's pixels and their squares in 32-bit lanes, and its minimum.
struct CellSums {
  uint32x4_t sum = vdupq_n_u32(0);
  uint32x4_t sum_sq = vdupq_n_u32(0);
  uint8x16_t low = vdupq_n_u8(255);
};

#if defined(__arm__)
// Rows of two full steps and a tail (cells 33-47 pixels wide, most of them) in inline assembly:
// loads that step to the next row by themselves and no inner loop, 25 instructions a row where
// GCC 12 gives 30 (copies of the loop-carried vectors).
void add_rows_2_tail(GrayView src, uint8x16_t keep, CellSums& c) {
  const std::uint8_t* p = src.data;
  const int to_tail = src.width - 32;             // after the second step
  const int to_next = src.stride - src.width + 16;  // after the tail
  int rows = src.height;
  uint8x16_t a, b, t;
  uint16x8_t s16, sq;
  asm volatile(
      "1:\n\t"
      "vld1.8 {%q[a]}, [%[p]]!\n\t"
      "vld1.8 {%q[b]}, [%[p]], %[to_tail]\n\t"
      "vld1.8 {%q[t]}, [%[p]], %[to_next]\n\t"
      "vmin.u8 %q[low], %q[low], %q[a]\n\t"
      "vmin.u8 %q[low], %q[low], %q[b]\n\t"
      "vmin.u8 %q[low], %q[low], %q[t]\n\t"
      "vand %q[t], %q[t], %q[keep]\n\t"
      "vpaddl.u8 %q[s16], %q[a]\n\t"
      "vpadal.u8 %q[s16], %q[b]\n\t"
      "vpadal.u8 %q[s16], %q[t]\n\t"
      "vmull.u8 %q[sq], %e[a], %e[a]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vmull.u8 %q[sq], %f[a], %f[a]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vmull.u8 %q[sq], %e[b], %e[b]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vmull.u8 %q[sq], %f[b], %f[b]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vmull.u8 %q[sq], %e[t], %e[t]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vmull.u8 %q[sq], %f[t], %f[t]\n\t"
      "vpadal.u16 %q[q32], %q[sq]\n\t"
      "vpadal.u16 %q[s32], %q[s16]\n\t"
      "subs %[rows], %[rows], #1\n\t"
      "bne 1b\n\t"
      : [p] "+r"(p), [rows] "+r"(rows), [low] "+w"(c.low), [s32] "+w"(c.sum), [q32] "+w"(c.sum_sq), [a] "=&w"(a),
        [b] "=&w"(b), [t] "=&w"(t), [s16] "=&w"(s16), [sq] "=&w"(sq)
      : [to_tail] "r"(to_tail), [to_next] "r"(to_next), [keep] "w"(keep)
      : "cc", "memory");
}
#endif

// `full` 16-pixel steps a row and, with `tail`, a last step on the row's final 16 pixels, `keep`
// masking out of the sums the lanes the full steps saw.
void add_rows(GrayView src, int full, bool tail, uint8x16_t keep, CellSums& c) {
  const int w = src.width;
  for (int y = 0; y < src.height; ++y) {
    const std::uint8_t* p = src.row(y);
    uint16x8_t s16 = vdupq_n_u16(0);  // at most 2 * 255 a step, 128 steps a row
    for (int k = 0; k < full; ++k) {
      const uint8x16_t v = vld1q_u8(p + 16 * k);
      c.low = vminq_u8(c.low, v);
      s16 = vpadalq_u8(s16, v);
      c.sum_sq = vpadalq_u16(c.sum_sq, vmull_u8(vget_low_u8(v), vget_low_u8(v)));
      c.sum_sq = vpadalq_u16(c.sum_sq, vmull_u8(vget_high_u8(v), vget_high_u8(v)));
    }
    if (tail) {
      uint8x16_t v = vld1q_u8(p + w - 16);
      c.low = vminq_u8(c.low, v);  // the masked lanes were seen already
      v = vandq_u8(v, keep);
      s16 = vpadalq_u8(s16, v);
      c.sum_sq = vpadalq_u16(c.sum_sq, vmull_u8(vget_low_u8(v), vget_low_u8(v)));
      c.sum_sq = vpadalq_u16(c.sum_sq, vmull_u8(vget_high_u8(v), vget_high_u8(v)));
    }
    c.sum = vpadalq_u16(c.sum, s16);
  }
}

std::uint32_t lane_total(uint32x4_t v) {
  const uint32x2_t t = vpadd_u32(vget_low_u32(v), vget_high_u32(v));
  return vget_lane_u32(vpadd_u32(t, t), 0);
}

}  // namespace
#endif

enhance::Moments CellClahe::moments(GrayView src) {
#if defined(__ARM_NEON)
  // enhance::compute_moments() for images of any size pays per row for the folds that keep its
  // sums exact; a cell of at most 66,051 pixels (255^2 each) keeps every sum of squares below
  // 2^32, so all sums stay in 32-bit lanes to the end (and convert to double in one instruction),
  // and rows of at most 128 steps let the byte sums move from 16- to 32-bit lanes once a row:
  // about half the instructions on a 37 x 38 cell.
  const int w = src.width, h = src.height;
  if (w >= 16 && w <= 2048 && h >= 1 && std::int64_t{w} * h <= 66051) {
    static const std::uint8_t kLane[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
    const int tail = w % 16;
    const uint8x16_t keep =
        vcgeq_u8(vld1q_u8(kLane), vdupq_n_u8(static_cast<std::uint8_t>(tail == 0 ? 0 : 16 - tail)));
    const int full = w / 16;
    CellSums c;
#if defined(__arm__)
    if (full == 2 && tail != 0)
      add_rows_2_tail(src, keep, c);
    else
#endif
      add_rows(src, full, tail != 0, keep, c);
    uint8x8_t m = vpmin_u8(vget_low_u8(c.low), vget_high_u8(c.low));
    m = vpmin_u8(m, m);
    m = vpmin_u8(m, m);
    m = vpmin_u8(m, m);
    enhance::Moments mo = enhance::moments_from_sums(static_cast<std::uint32_t>(w * h), lane_total(c.sum),
                                                     lane_total(c.sum_sq));
    mo.min = vget_lane_u8(m, 0);
    return mo;
  }
#endif
  return enhance::compute_moments(src);
}

int CellClahe::min_raw_gap(int threshold) const {
#if defined(__ARM_NEON)
  // By increasing gap d, the largest rise lut[v + d] - lut[v] over the range, 16 v at a time. The
  // last vector reads up to hi_ + 15, where build_table() repeats lut_[hi_]: there a "pair" is
  // (v, hi_) with a gap below d, or rises by 0, and a rise of more than `threshold` at a gap below
  // d would have ended an earlier d. The search starts at the gap the clip allows (as
  // needed_for_clip(), with the cell's own bin bound: 255 d bin_max_ > (threshold - 1) area_), so
  // a typical cell (range 76, gap 14) takes a few gaps of about 5 vectors.
  if (threshold >= 1 && threshold < 255) {
    const std::uint8_t* const lut = lut_.data();
    const int first = static_cast<int>(static_cast<std::uint32_t>(threshold - 1) * area_ / (255u * bin_max_)) + 1;
    for (int d = first; d <= hi_ - lo_; ++d) {
      const std::uint8_t* p = lut + lo_;
      const std::uint8_t* const end = lut + hi_ - d;  // the last v of a real pair
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
#endif
  return min_raw_gap_ref(threshold);
}

int CellClahe::min_raw_gap_ref(int threshold) const {
  // Two pointers over the monotonic table: for each v the first u with lut[u] - lut[v] > threshold.
  int best = 256;
  int u = lo_;
  for (int v = lo_; v <= hi_; ++v) {
    if (u < v) u = v;
    while (u <= hi_ && lut_[static_cast<std::size_t>(u)] - lut_[static_cast<std::size_t>(v)] <= threshold) ++u;
    if (u > hi_) break;  // later v only have smaller rises left
    best = std::min(best, u - v);
  }
  return best;
}

int CellClahe::mapped_score(GrayView src, int x, int y) const {
  constexpr int kEdge = 2 * kFastRadius + 1;
  std::uint8_t patch[kEdge * kEdge];
  for (int dy = 0; dy < kEdge; ++dy) {
    const std::uint8_t* row = src.row(y - kFastRadius + dy) + x - kFastRadius;
    for (int dx = 0; dx < kEdge; ++dx) patch[dy * kEdge + dx] = lut_[row[dx]];
  }
  return fast9_score(patch + kFastRadius * kEdge + kFastRadius, kEdge);
}

void CellClahe::map(GrayView src, MutableGrayView dst) const {
  for (int y = 0; y < src.height; ++y) enhance::lut_row(src.row(y), dst.row(y), src.width, lut_.data());
}

}  // namespace ale::features
