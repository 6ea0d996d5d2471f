// Scalar FAST-9 score map: the specification score_map_neon.cpp reproduces (see score_map.h):
// FAST's reference row (compass test, 9-arc bit test, then fast9_score()), whose output is this map.

#include "core/features/score_map.h"

#include "core/features/kernels.h"

namespace ale::features {

namespace internal {

void score_rect_ref(GrayView image, PixelRect rect, int threshold, MutableGrayView scores,
                    std::vector<FastCorner>& corners) {
  // FAST's reference computes exactly this (scores of the corners at the threshold, 0 elsewhere).
  for (int y = rect.y; y < rect.y + rect.height; ++y)
    fast9_row_ref(image, y, rect.x, rect.x + rect.width, threshold, scores.row(y), corners);
}

}  // namespace internal

void fast9_score_map(GrayView image, PixelRect rect, int threshold, MutableGrayView scores,
                     std::vector<FastCorner>& corners, KernelPath path) {
  if (rect.width <= 0 || rect.height <= 0) return;
  kernels(path).score_rect(image, rect, threshold, scores, corners);
}

void fast9_nonmax_at(GrayView scores, const std::vector<FastCorner>& in, int threshold, std::vector<FastCorner>& out) {
  for (const FastCorner& c : in) {
    const int v = c.score;
    if (v < threshold) continue;
    const std::uint8_t* s = scores.row(c.y) + c.x;
    const std::uint8_t* up = s - scores.stride;
    const std::uint8_t* down = s + scores.stride;
    if (v > up[-1] && v > up[0] && v > up[1] && v > s[-1] && v > s[1] && v > down[-1] && v > down[0] &&
        v > down[1])
      out.push_back(c);
  }
}

}  // namespace ale::features
