// The FAST-9 score map the extractor detects from: one pass per pyramid level computes the score
// (fast.h) of every candidate pixel at the lowest threshold any cell may need, and every later
// question (corners at t_high, at t_low, non-maximum suppression) is answered from the map, because
// a pixel is a corner at t exactly when its score is >= t.
//
// The vector kernels compute the score of 16 neighbouring pixels at once, after a compass test
// that rejects the 16 pixels when none can be a corner. NEON (score_map_neon.cpp): the largest
// (smallest) arc minimum (maximum) of the grey values by suffix/prefix extremes of the circle's
// two halves, then one saturating difference with the centre; one pass per vector, the darker
// candidates flipped (255 - v) when both polarities occur, two passes when a lane may be either.
// SSE2 (score_map_sse2.cpp): saturating differences and a sliding minimum by doubling (2, 4, 8,
// then 8 + 1) for the polarities whose compass test passed. Either way a pixel's score is
// max(brighter, darker) - 1 and it is a corner when that is >= t. The scalar reference
// (score_map_ref.cpp: fast9_row_ref, compass test, 9-arc bit test, fast9_score per corner) is the
// specification; both vector kernels are bit-exact with it.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "core/features/fast.h"

namespace ale::features {

// For every pixel p of `rect`: scores[p] = score(p) when score(p) >= threshold, else 0; the
// pixels with a non-zero score are appended to `corners` in row-major order. `rect` must keep
// kFastRadius pixels inside `image`, `scores` has the size of `image` (only `rect` is written),
// threshold is 1..254. No checks: the extractor's own geometry guarantees these.
void fast9_score_map(GrayView image, PixelRect rect, int threshold, MutableGrayView scores,
                     std::vector<FastCorner>& corners, KernelPath path = KernelPath::kAuto);

// Appends the corners of `in` with score >= threshold that are strict maxima of their 8
// neighbours in `scores` to `out` (fast9_nonmax with a threshold).
void fast9_nonmax_at(GrayView scores, const std::vector<FastCorner>& in, int threshold, std::vector<FastCorner>& out);

namespace internal {
// Appends the corner of each set bit i of `mask`: lane i of the 16-pixel vector at (x, y), whose
// scores are `lanes`. Shared by the vector paths.
inline void append_lane_corners(unsigned mask, const std::uint8_t* lanes, int x, int y,
                                std::vector<FastCorner>& corners) {
  while (mask != 0) {
    const int i = __builtin_ctz(mask);
    mask &= mask - 1;
    corners.push_back({static_cast<std::int16_t>(x + i), static_cast<std::int16_t>(y), lanes[i]});
  }
}

// The score map of `rect` (fast9_score_map's contract), one kernel per path. The vector kernels
// take the whole rectangle so that their setup (and the narrow-segment geometry) is paid once per
// cell, not once per row: the extractor calls them for about a thousand small cells per frame.
void score_rect_ref(GrayView image, PixelRect rect, int threshold, MutableGrayView scores,
                    std::vector<FastCorner>& corners);
void score_rect_neon(GrayView image, PixelRect rect, int threshold, MutableGrayView scores,
                     std::vector<FastCorner>& corners);
void score_rect_sse2(GrayView image, PixelRect rect, int threshold, MutableGrayView scores,
                     std::vector<FastCorner>& corners);
}  // namespace internal

}  // namespace ale::features
