#include "core/features/cell_clahe.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/enhance/level_clahe.h"

namespace ale::features {

Status CellClahe::apply(const enhance::LevelClaheParams& p, double scale, GrayView src, MutableGrayView dst) {
  ALE_RETURN_IF_ERROR(check_view(src, "cell clahe source"));
  ALE_RETURN_IF_ERROR(check_view(dst, "cell clahe destination"));
  const int w = src.width;
  const int h = src.height;
  const std::uint32_t area = static_cast<std::uint32_t>(w) * static_cast<std::uint32_t>(h);
  // 255 * area must fit 32 bits below (and core/enhance caps a tile at 2^24 pixels).
  if (dst.width != w || dst.height != h || area >= (1u << 22)) {
    single_ = false;
    return enhance::contrast_guided_clahe(general_, p, scale, src, dst);
  }
  // Statistics as enhance::compute_stats: the sums fit 32 bits for cells, and convert to the same
  // doubles as its 64-bit ones.
  hist_.fill(0);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* row = src.row(y);
    int x = 0;
    // Four pixels per word load: fewer instructions on the Cortex-A7 than byte loads.
    for (; x + 4 <= w; x += 4) {
      std::uint32_t q;
      std::memcpy(&q, row + x, 4);
      ++hist_[q & 0xFFu];
      ++hist_[(q >> 8) & 0xFFu];
      ++hist_[(q >> 16) & 0xFFu];
      ++hist_[q >> 24];
    }
    for (; x < w; ++x) ++hist_[row[x]];
  }
  // The grey range [lo, hi] the cell occupies (retried cells are low-contrast, so it is narrow):
  // bins outside it are 0 until the clip redistribution, and LUT entries outside it are never read.
  std::uint32_t lo = 0, hi = 255;
  while (hist_[lo] == 0) ++lo;
  while (hist_[hi] == 0) --hi;
  std::uint32_t sum = 0, sum_sq = 0;
  for (std::uint32_t v = lo; v <= hi; ++v) {
    sum += hist_[v] * v;
    sum_sq += hist_[v] * v * v;
  }
  int median = static_cast<int>(lo);
  for (std::uint32_t cum = 0; median < 256; ++median) {
    cum += hist_[static_cast<std::size_t>(median)];
    if (2 * cum >= area) break;
  }
  const double dn = static_cast<double>(area);
  const double mean = static_cast<double>(sum) / dn;
  const double sigma = std::sqrt(std::max(0.0, static_cast<double>(sum_sq) / dn - mean * mean));
  const enhance::LevelClaheSettings s = enhance::level_clahe_settings(p, scale, w, h, sigma, median);
  if (s.clahe.tiles_x != 1 || s.clahe.tiles_y != 1) {
    single_ = false;
    return enhance::contrast_guided_clahe(general_, p, scale, src, dst);
  }
  single_ = true;
  // One tile of w x h: clipping and the LUT exactly as ClaheContext (clahe_ref.cpp).
  if (s.clahe.clip_limit > 0.0) {
    const double limit = s.clahe.clip_limit * dn / 256.0;
    const std::uint32_t clip =
        limit >= dn ? area : static_cast<std::uint32_t>(std::max(static_cast<int>(limit), 1));
    std::uint32_t clipped = 0;
    for (std::uint32_t v = lo; v <= hi; ++v) {  // clip >= 1 leaves the empty bins alone
      std::uint32_t& c = hist_[v];
      if (c > clip) {
        clipped += c - clip;
        c = clip;
      }
    }
    const std::uint32_t batch = clipped / 256u;
    std::uint32_t residual = clipped % 256u;
    if (batch != 0)
      for (std::uint32_t& c : hist_) c += batch;
    if (residual != 0) {
      const std::uint32_t step = std::max(256u / residual, 1u);
      for (std::uint32_t i = 0; i < 256u && residual > 0; i += step, --residual) ++hist_[i];
    }
  }
  // The interpolation of a single tile blends four equal values: (lut * Dx * W + round) >> K with
  // the horizontal denominator Dx, the vertical weight total W and shift K of ClaheContext.
  const enhance::BlendScale blend = enhance::blend_scale(w);
  const auto dx = static_cast<std::uint32_t>(blend.dx);
  const int shift = blend.shift;
  const auto w_total = static_cast<std::uint32_t>(blend.w_total);
  const std::uint32_t round = 1u << (shift - 1);
  // floor(n / area) by a multiply with floor((2^32-1) / area) and one correction (as ClaheContext).
  const std::uint32_t recip = 0xFFFFFFFFu / area;
  std::uint32_t cum = 0;
  for (std::size_t i = 0; i < lo; ++i) cum += hist_[i];
  for (std::size_t i = lo; i <= hi; ++i) {
    cum += hist_[i];
    const std::uint32_t n = cum * 255u + area / 2u;
    std::uint32_t q0 = static_cast<std::uint32_t>((std::uint64_t{n} * recip) >> 32);
    if (n - q0 * area >= area) ++q0;
    const std::uint32_t lut = q0 > 255u ? 255u : q0;
    const std::uint32_t out = (lut * dx * w_total + round) >> shift;
    lut_[i] = static_cast<std::uint8_t>(out > 255u ? 255u : out);
  }
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* in = src.row(y);
    std::uint8_t* out = dst.row(y);
    int x = 0;
    for (; x + 4 <= w; x += 4) {
      std::uint32_t q;
      std::memcpy(&q, in + x, 4);
      const std::uint32_t r = std::uint32_t{lut_[q & 0xFFu]} | std::uint32_t{lut_[(q >> 8) & 0xFFu]} << 8 |
                              std::uint32_t{lut_[(q >> 16) & 0xFFu]} << 16 | std::uint32_t{lut_[q >> 24]} << 24;
      std::memcpy(out + x, &r, 4);
    }
    for (; x < w; ++x) out[x] = lut_[in[x]];
  }
  return {};
}

}  // namespace ale::features
