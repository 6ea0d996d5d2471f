#include "core/enhance/noise.h"

#include "core/enhance/kernels.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <utility>

namespace ale::enhance {

double estimate_noise_sigma(GrayView image, int row_step) {
  if (image.width < 3 || image.height < 3 || row_step < 1) return 0.0;
  // |N| is at most 16 * 255; above 255 (edges) one bin is enough for a median of noise.
  std::array<std::uint32_t, 257> hist{};
  std::uint32_t n = 0;
  for (int y = 1; y + 1 < image.height; y += row_step) {
    const std::uint8_t* a = image.row(y - 1);
    const std::uint8_t* b = image.row(y);
    const std::uint8_t* c = image.row(y + 1);
    for (int x = 1; x + 1 < image.width; x += 2) {
      const int v = (a[x - 1] + a[x + 1] + c[x - 1] + c[x + 1]) - 2 * (a[x] + c[x] + b[x - 1] + b[x + 1]) + 4 * b[x];
      const int m = std::abs(v);
      ++hist[static_cast<std::size_t>(m > 256 ? 256 : m)];
      ++n;
    }
  }
  if (n == 0) return 0.0;
  const std::uint32_t half = (n + 1) / 2;
  std::uint32_t cum = 0;
  int median = 0;
  for (int m = 0; m <= 256; ++m) {
    cum += hist[static_cast<std::size_t>(m)];
    if (cum >= half) {
      median = m;
      break;
    }
  }
  return median / (0.6745 * 6.0);
}

namespace internal {

void binomial3_ref(MutableGrayView img, std::uint8_t* rows, std::uint16_t* sums) {
  const int w = img.width, h = img.height;
  const std::size_t n = static_cast<std::size_t>(w);
  std::uint8_t* above = rows;  // the original of the row above (rows are filtered in place)
  std::uint8_t* here = rows + n;
  std::copy(img.row(0), img.row(0) + w, above);
  for (int y = 1; y + 1 < h; ++y) {
    std::uint8_t* r = img.row(y);
    const std::uint8_t* below = img.row(y + 1);
    std::copy(r, r + w, here);
    for (std::size_t x = 0; x < n; ++x) sums[x] = static_cast<std::uint16_t>(above[x] + 2 * here[x] + below[x]);
    for (std::size_t x = 1; x + 1 < n; ++x)
      r[x] = static_cast<std::uint8_t>((sums[x - 1] + 2 * sums[x] + sums[x + 1] + 8) >> 4);
    std::swap(above, here);
  }
}

}  // namespace internal

void binomial3_in_place(MutableGrayView img, std::vector<std::uint8_t>& rows, std::vector<std::uint16_t>& sums,
                        KernelPath path) {
  if (img.width < 3 || img.height < 3) return;
  const std::size_t n = static_cast<std::size_t>(img.width);
  rows.resize(2 * n);
  sums.resize(n);
  kernels(path).binomial3(img, rows.data(), sums.data());
}

}  // namespace ale::enhance
