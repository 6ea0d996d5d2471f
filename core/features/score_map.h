// The FAST-9 score map the extractor detects from: one pass per pyramid level computes the score
// (fast.h) of every candidate pixel at the lowest threshold any cell may need, and every later
// question (corners at t_high, at t_low, non-maximum suppression) is answered from the map, because
// a pixel is a corner at t exactly when its score is >= t.
//
// Both kernels compute the score of 16 neighbouring pixels at once, with saturating differences
// (the score is the largest, over the 16 arcs of 9 circle pixels and both polarities, of the
// arc's smallest difference, minus one; see fast.h) and a sliding minimum by doubling (2, 4, 8,
// then 8 + 1), after a compass test that rejects the 16 pixels when none can be a corner. Only the
// polarity whose compass test passed in some lane is scored: a pixel cannot have a brighter and a
// darker arc of 9 on a circle of 16. The scalar reference (score_map_ref.cpp: fast9_row_ref, compass
// test, 9-arc bit test, fast9_score per corner) is the specification; the NEON kernel (score_map_neon.cpp) is bit-exact
// with it, and so is the SSE2 kernel (score_map_sse2.cpp) on x86.
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
                     std::vector<FastCorner>& corners, FastPath path = FastPath::kAuto);

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

// Row segment [x_begin, x_end) of row y.
void score_row_ref(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                   std::vector<FastCorner>& corners);
void score_row_neon(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                    std::vector<FastCorner>& corners);
void score_row_sse2(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                    std::vector<FastCorner>& corners);
}  // namespace internal

}  // namespace ale::features
