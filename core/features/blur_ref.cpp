// Scalar 7x7 Gaussian: the specification blur_neon.cpp reproduces (definition in blur.h), and the
// drivers that pick the rectangles to blur.
#include "core/features/blur.h"

#include <algorithm>

#include "core/features/kernels.h"

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

}  // namespace

void gaussian7_interior(GrayView src, MutableGrayView dst, std::vector<std::uint8_t>& scratch, KernelPath path) {
  if (src.width < 2 * kBlurRadius + 1 || src.height < 2 * kBlurRadius + 1) return;
  if (scratch.size() < blur_scratch_bytes(src.width)) scratch.resize(blur_scratch_bytes(src.width));
  kernels(path).blur_rect(src, dst,
                          {kBlurRadius, kBlurRadius, src.width - 2 * kBlurRadius, src.height - 2 * kBlurRadius},
                          scratch.data());
}

void gaussian7_patches(GrayView src, MutableGrayView dst, const std::vector<FastCorner>& centres, int radius,
                       BlurScratch& scratch, KernelPath path) {
  if (src.width < 2 * kBlurRadius + 1 || src.height < 2 * kBlurRadius + 1 || centres.empty()) return;
  const int x_end = src.width - kBlurRadius;
  const int y_end = src.height - kBlurRadius;
  const int blocks = (x_end - kBlurRadius + kBlurBlockPx - 1) / kBlurBlockPx;
  const int groups = (y_end - kBlurRadius + kBlurGroupRows - 1) / kBlurGroupRows;
  const std::size_t cells = static_cast<std::size_t>(blocks) * static_cast<std::size_t>(groups);
  if (scratch.rows.size() < blur_scratch_bytes(src.width)) scratch.rows.resize(blur_scratch_bytes(src.width));
  if (scratch.marks.size() < cells) scratch.marks.resize(cells);
  std::fill(scratch.marks.begin(), scratch.marks.begin() + static_cast<std::ptrdiff_t>(cells), std::uint16_t{0});
  // Per cell, the columns some centre needs (bit i: column i of the cell): a run of marked cells is
  // blurred from the first needed column of its first cell to the last of its last cell (about
  // 10 % fewer pixels than whole cells for a normal frame; trimming the rows as well would save
  // 2 % more but cost a read-modify-write per cell instead of a store for most of them).
  static_assert(kBlurBlockPx == 16, "one 16-bit mask per cell");
  std::uint16_t* marks = scratch.marks.data();
  for (const FastCorner& c : centres) {
    const int x0 = std::max(c.x - radius, kBlurRadius), x1 = std::min(c.x + radius + 1, x_end);
    const int y0 = std::max(c.y - radius, kBlurRadius), y1 = std::min(c.y + radius + 1, y_end);
    if (x0 >= x1 || y0 >= y1) continue;
    // Offsets from the interior's corner, unsigned so that / and % are shifts.
    const unsigned u0 = static_cast<unsigned>(x0 - kBlurRadius), u1 = static_cast<unsigned>(x1 - 1 - kBlurRadius);
    const unsigned b0 = u0 / kBlurBlockPx, b1 = u1 / kBlurBlockPx;
    const unsigned g0 = static_cast<unsigned>(y0 - kBlurRadius) / kBlurGroupRows;
    const unsigned g1 = static_cast<unsigned>(y1 - 1 - kBlurRadius) / kBlurGroupRows;
    std::uint16_t first_cols = static_cast<std::uint16_t>(0xFFFFu << (u0 % kBlurBlockPx));
    std::uint16_t last_cols = static_cast<std::uint16_t>(0xFFFFu >> (kBlurBlockPx - 1 - u1 % kBlurBlockPx));
    // One cell wide: both ends are that cell (OR-ing it twice does no harm).
    if (b0 == b1) first_cols = last_cols = first_cols & last_cols;
    const unsigned inner = b1 - b0;  // cells after the first
    std::uint16_t* row = marks + g0 * static_cast<unsigned>(blocks) + b0;
    for (unsigned g = g0; g <= g1; ++g, row += blocks) {
      row[0] |= first_cols;
      // Cells in between need every column: a store. Patches of radius 15 span 2 or 3 cells:
      // straight-line code for those (GCC vectorises the general loop, whose set-up cost more).
      if (inner == 2) {
        row[1] = 0xFFFFu;
      } else {
        for (unsigned k = 1; k < inner; ++k) row[k] = 0xFFFFu;
      }
      row[inner] |= last_cols;
    }
  }
  const auto blur_rect = kernels(path).blur_rect;
  for (int g = 0; g < groups; ++g) {
    const std::uint16_t* row = marks + static_cast<std::ptrdiff_t>(g) * blocks;
    for (int b = 0; b < blocks;) {
      if (!row[b]) {
        ++b;
        continue;
      }
      const int first = b;
      while (b < blocks && row[b]) ++b;
      // First needed column of the first cell, last of the last.
      int x0 = kBlurRadius + first * kBlurBlockPx + __builtin_ctz(row[first]);
      int x1 = kBlurRadius + (b - 1) * kBlurBlockPx + 32 - __builtin_clz(row[b - 1]);
      // At least a vector wide where the interior allows (the NEON kernel's scalar fallback is slow).
      if (x1 - x0 < 16) {
        x1 = std::min(x0 + 16, x_end);
        x0 = std::max(kBlurRadius, x1 - 16);
      }
      const int y0 = kBlurRadius + g * kBlurGroupRows;
      const int y1 = std::min(y0 + kBlurGroupRows, y_end);
      blur_rect(src, dst, {x0, y0, x1 - x0, y1 - y0}, scratch.rows.data());
    }
  }
}

}  // namespace ale::features
