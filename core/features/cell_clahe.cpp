#include "core/features/cell_clahe.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/enhance/kernels.h"
#include "core/enhance/level_clahe.h"
#include "core/features/fast.h"
#include "core/features/kernels.h"

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
  enhance::kernels().histogram(src, hist, hist);
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
  // min_raw_gap()'s NEON kernel reads whole vectors past hi (the table stays monotonic).
  std::memset(lut_.data() + hi + 1, lut_[hi], kLutPad);
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

enhance::Moments CellClahe::moments(GrayView src) { return enhance::kernels().small_moments(src); }

int CellClahe::min_raw_gap(int threshold) const {
  if (threshold < 1 || threshold >= 255) return min_raw_gap_ref(threshold);
  // No gap below the one the clip allows can rise by more than threshold (as needed_for_clip(),
  // with the cell's own bin bound: 255 d bin_max_ > (threshold - 1) area_).
  const int first = static_cast<int>(static_cast<std::uint32_t>(threshold - 1) * area_ / (255u * bin_max_)) + 1;
  return enhance::kernels().min_gap(lut_.data(), lo_, hi_, first, threshold);
}

int CellClahe::min_raw_gap_ref(int threshold) const {
  return enhance::internal::min_gap_ref(lut_.data(), lo_, hi_, 1, threshold);
}

int CellClahe::mapped_score(GrayView src, int x, int y) const {
  constexpr int kEdge = 2 * kFastRadius + 1;
  std::uint8_t patch[kEdge * kEdge];
  for (int dy = 0; dy < kEdge; ++dy) {
    const std::uint8_t* row = src.row(y - kFastRadius + dy) + x - kFastRadius;
    for (int dx = 0; dx < kEdge; ++dx) patch[dy * kEdge + dx] = lut_[row[dx]];
  }
  return kernels().fast9_score(patch + kFastRadius * kEdge + kFastRadius, kEdge);
}

void CellClahe::map(GrayView src, MutableGrayView dst) const { enhance::kernels().apply_lut(src, dst, lut_.data()); }

}  // namespace ale::features
