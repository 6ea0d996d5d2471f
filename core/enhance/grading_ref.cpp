// Moments of an image in C: the specification grading_neon.cpp reproduces (grading.h).
#include <algorithm>

#include "core/enhance/grading.h"

namespace ale::enhance::internal {

Moments moments_ref(GrayView image) {
  std::uint64_t sum = 0, sum_sq = 0;
  std::uint8_t low = 255;
  const int w = image.width > 0 ? image.width : 0;
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t* p = image.row(y);
    for (int x = 0; x < w; ++x) {
      const std::uint64_t v = p[x];
      sum += v;
      sum_sq += v * v;
      low = std::min(low, p[x]);
    }
  }
  return moments_with_min(static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(std::max(image.height, 0)), sum,
                          sum_sq, low);
}

}  // namespace ale::enhance::internal
