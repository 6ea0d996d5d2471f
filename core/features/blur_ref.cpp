// Scalar 7x7 Gaussian: the specification blur_neon.cpp reproduces (definition in blur.h), and the
// drivers that pick the rectangles to blur.
#include "core/features/blur.h"

#include <algorithm>

namespace ale::features {

namespace internal {

namespace {

void vertical_row(GrayView src, int y, int x0, int x1, std::uint8_t* vrow) {
  const std::uint8_t* r[7];
  for (int k = 0; k < 7; ++k) r[k] = src.row(y + k - kBlurRadius);
  for (int x = x0; x < x1; ++x) {
    unsigned s = 128;
    for (int k = 0; k < 7; ++k) s += static_cast<unsigned>(kBlurTaps[k]) * r[k][x];
    vrow[x] = static_cast<std::uint8_t>(s >> 8);
  }
}

void horizontal_row(const std::uint8_t* vrow, int x0, int x1, std::uint8_t* out) {
  for (int x = x0; x < x1; ++x) {
    unsigned s = 128;
    for (int k = 0; k < 7; ++k) s += static_cast<unsigned>(kBlurTaps[k]) * vrow[x + k - kBlurRadius];
    out[x] = static_cast<std::uint8_t>(s >> 8);
  }
}

}  // namespace

void blur_rect_ref(GrayView src, MutableGrayView dst, PixelRect rect, std::uint8_t* scratch) {
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    vertical_row(src, y, rect.x - kBlurRadius, rect.x + rect.width + kBlurRadius, scratch);
    horizontal_row(scratch, rect.x, rect.x + rect.width, dst.row(y));
  }
}

}  // namespace internal

namespace {

std::size_t blur_scratch_bytes(int width) { return 2u * (static_cast<std::size_t>(width) + 32u); }

void blur_rect(GrayView src, MutableGrayView dst, PixelRect rect, std::uint8_t* scratch, bool neon) {
  if (neon)
    internal::blur_rect_neon(src, dst, rect, scratch);
  else
    internal::blur_rect_ref(src, dst, rect, scratch);
}

bool use_neon(FastPath path) {
  if (path == FastPath::kAuto) path = fast_auto_path();
  return path == FastPath::kNeon && fast_neon_compiled();
}

}  // namespace

void gaussian7_interior(GrayView src, MutableGrayView dst, std::vector<std::uint8_t>& scratch, FastPath path) {
  if (src.width < 2 * kBlurRadius + 1 || src.height < 2 * kBlurRadius + 1) return;
  if (scratch.size() < blur_scratch_bytes(src.width)) scratch.resize(blur_scratch_bytes(src.width));
  blur_rect(src, dst, {kBlurRadius, kBlurRadius, src.width - 2 * kBlurRadius, src.height - 2 * kBlurRadius},
            scratch.data(), use_neon(path));
}

void gaussian7_patches(GrayView src, MutableGrayView dst, const std::vector<FastCorner>& centres, int radius,
                       BlurScratch& scratch, FastPath path) {
  if (src.width < 2 * kBlurRadius + 1 || src.height < 2 * kBlurRadius + 1 || centres.empty()) return;
  const int x_end = src.width - kBlurRadius;
  const int y_end = src.height - kBlurRadius;
  const int blocks = (x_end - kBlurRadius + kBlurBlockPx - 1) / kBlurBlockPx;
  const int groups = (y_end - kBlurRadius + kBlurGroupRows - 1) / kBlurGroupRows;
  const std::size_t cells = static_cast<std::size_t>(blocks) * static_cast<std::size_t>(groups);
  if (scratch.rows.size() < blur_scratch_bytes(src.width)) scratch.rows.resize(blur_scratch_bytes(src.width));
  if (scratch.marks.size() < cells) scratch.marks.resize(cells);
  std::fill(scratch.marks.begin(), scratch.marks.begin() + static_cast<std::ptrdiff_t>(cells), std::uint8_t{0});
  std::uint8_t* marks = scratch.marks.data();
  for (const FastCorner& c : centres) {
    const int x0 = std::max(c.x - radius, kBlurRadius), x1 = std::min(c.x + radius + 1, x_end);
    const int y0 = std::max(c.y - radius, kBlurRadius), y1 = std::min(c.y + radius + 1, y_end);
    if (x0 >= x1 || y0 >= y1) continue;
    const int b0 = (x0 - kBlurRadius) / kBlurBlockPx, b1 = (x1 - 1 - kBlurRadius) / kBlurBlockPx;
    const int g0 = (y0 - kBlurRadius) / kBlurGroupRows, g1 = (y1 - 1 - kBlurRadius) / kBlurGroupRows;
    for (int g = g0; g <= g1; ++g) {
      std::uint8_t* row = marks + static_cast<std::ptrdiff_t>(g) * blocks;
      for (int b = b0; b <= b1; ++b) row[b] = 1;
    }
  }
  const bool neon = use_neon(path);
  for (int g = 0; g < groups; ++g) {
    const std::uint8_t* row = marks + static_cast<std::ptrdiff_t>(g) * blocks;
    const int y0 = kBlurRadius + g * kBlurGroupRows;
    const int rows = std::min(kBlurGroupRows, y_end - y0);
    for (int b = 0; b < blocks;) {
      if (!row[b]) {
        ++b;
        continue;
      }
      const int first = b;
      while (b < blocks && row[b]) ++b;
      const int x0 = kBlurRadius + first * kBlurBlockPx;
      const int x1 = std::min(kBlurRadius + b * kBlurBlockPx, x_end);
      blur_rect(src, dst, {x0, y0, x1 - x0, rows}, scratch.rows.data(), neon);
    }
  }
}

}  // namespace ale::features
