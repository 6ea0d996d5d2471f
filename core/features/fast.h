// FAST-9 corner detection (Rosten & Drummond): a portable scalar reference (fast_ref.cpp, the
// specification) and an ARM NEON path (fast_neon.cpp) that finds the identical corner set with the
// identical scores, chosen through the feature kernels' table (kernels.h).
//
// Definitions, for a pixel p with grey value I_p and the 16 pixels c_0..c_15 of the Bresenham
// circle of radius 3 around it (clockwise from the pixel 3 rows above), d_k = I(c_k) - I_p:
// - p is a corner at threshold t (1..254) when some arc of 9 contiguous circle pixels (indices taken
//   modulo 16) has d_k > t for all of them (brighter arc) or d_k < -t for all of them (darker arc).
// - score(p) = the largest t at which p is still a corner
//            = max over the 16 arcs A of max(min_{k in A} d_k, min_{k in A} -d_k) - 1,
//   which is the score ORB-SLAM and OpenCV's FAST use. So p is a corner at t exactly when
//   score(p) >= t, and a detection at T_low carries every detection at T_high >= T_low.
// - Non-maximum suppression (fast9_nonmax) keeps a corner when its score is strictly greater than
//   the scores of its 8 neighbours, non-corners counting as 0 (OpenCV's rule). Because of the
//   property above, the corners kept at threshold t are the strict local maxima of the score map
//   that have score >= t, whatever threshold the neighbours were detected at.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "core/base/kernel_path.h"
#include "core/base/status.h"

namespace ale::features {

constexpr int kFastRadius = 3;  // pixels a detection needs on every side of a candidate

struct FastCorner {
  std::int16_t x = 0;  // image coordinates
  std::int16_t y = 0;
  std::uint8_t score = 0;  // see above; >= the detection threshold
};

// A rectangle [x, x + width) x [y, y + height) of candidate pixels.
struct PixelRect {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
};

// The score of the pixel at `p` in an image with row stride `stride` (kFastRadius pixels must exist
// on every side). Defined for every pixel; corners at threshold t are those with score >= t.
// NEON builds compute it with one vector per polarity (fast_neon.cpp); equal to
// internal::fast9_score_ref() for every circle.
int fast9_score(const std::uint8_t* p, int stride, KernelPath path = KernelPath::kAuto);

// Appends the corners at `threshold` among the pixels of `rect` to `corners`, in row-major order,
// and writes each pixel's score into `scores` (score where it is a corner, 0 elsewhere; `scores`
// has the size of `image` and only the pixels of `rect` are written). `rect` must keep kFastRadius
// pixels inside `image`; `threshold` is 1..254.
Status fast9_detect(GrayView image, PixelRect rect, int threshold, MutableGrayView scores,
                    std::vector<FastCorner>& corners, KernelPath path = KernelPath::kAuto);

// Keeps the corners of `in` whose score beats their 8 neighbours in `scores` (strictly), appending
// them to `out`. Each corner needs its 8 neighbours inside `scores`.
void fast9_nonmax(GrayView scores, const std::vector<FastCorner>& in, std::vector<FastCorner>& out);

namespace internal {
// One row segment [x_begin, x_end) of row y; the two kernels behind fast9_detect (no checks).
void fast9_row_ref(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                   std::vector<FastCorner>& corners);
void fast9_row_neon(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                    std::vector<FastCorner>& corners);
// The SSE2 score map's row (score_map_sse2.cpp).
void fast9_row_sse2(GrayView image, int y, int x_begin, int x_end, int threshold, std::uint8_t* score_row,
                    std::vector<FastCorner>& corners);
// The circle c_0..c_15: c_k = (x + kCircleDx[k], y + kCircleDy[k]).
inline constexpr int kCircleDx[16] = {0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3, -3, -3, -2, -1};
inline constexpr int kCircleDy[16] = {-3, -3, -2, -1, 0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3};
// The scalar definition of fast9_score(), which the NEON version is tested against.
int fast9_score_ref(const std::uint8_t* p, int stride);
int fast9_score_neon(const std::uint8_t* p, int stride);
// Circle offsets c_0..c_15 for a row stride.
void fast9_offsets(int stride, int offsets[16]);
}  // namespace internal

}  // namespace ale::features
