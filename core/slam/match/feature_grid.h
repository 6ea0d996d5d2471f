// A grid over a frame's undistorted keypoints, for the matchers' radius and epipolar-band
// queries (ORB-SLAM's 64x48 cell grid). Built once per frame into reused buffers.
#pragma once

#include <cstdint>
#include <vector>

#include "core/map/map_store.h"

namespace ale::slam {

// The scale pyramid the keypoints came from: scale[l] = scale_factor^l.
struct ScalePyramid {
  static constexpr int kMaxLevels = 16;
  int levels = 8;
  float scale_factor = 1.2f;
  float log_scale_factor = 0.0f;
  float scale[kMaxLevels] = {};
  float inv_scale[kMaxLevels] = {};
  float sigma2[kMaxLevels] = {};      // scale^2: keypoint position variance at each level
  float inv_sigma2[kMaxLevels] = {};

  // levels in 1..kMaxLevels, scale_factor > 1 (clamped otherwise).
  static ScalePyramid make(int levels, float scale_factor);
  // The level a landmark at `distance` projects at, from its maximum distance (ORB-SLAM's
  // PredictScale), clamped to [0, levels - 1].
  int predict_level(float distance, float max_distance) const;
};

// Bounds of the undistorted image (the grid covers them).
struct ImageBounds {
  float min_u = 0.0f, min_v = 0.0f, max_u = 0.0f, max_v = 0.0f;
  bool contains(float u, float v) const { return u >= min_u && u < max_u && v >= min_v && v < max_v; }
};

// floor(x) clamped to [lo, hi] (NaN: lo), for the first (lo = 0, hi = cells) and last (lo = -1,
// hi = cells - 1) cell a range of coordinates touches: the same cells as max(0, floor(x)) and
// min(cells - 1, floor(x)) whenever those are representable, an empty range staying empty. Without
// libm: ARMv7 has no rounding instruction, so std::floor is a call (about 30 instructions).
inline int floor_clamped(double x, int lo, int hi) {
  if (!(x > lo)) return lo;
  if (x >= hi) return hi;
  const int i = static_cast<int>(x);  // x in (lo, hi): truncated towards zero
  return static_cast<double>(i) > x ? i - 1 : i;
}

class FeatureGrid {
 public:
  static constexpr int kCols = 64;
  static constexpr int kRows = 48;

  // Assigns every feature to its cell; features outside `bounds` are left out of the grid.
  void build(const map::KeyframeFeature* features, int count, const ImageBounds& bounds);

  // Indices (ascending) of features within an axis-aligned square of half-size r around (u, v)
  // whose level is in [min_level, max_level] (max_level < 0: any), appended to out.
  void query(float u, float v, float r, int min_level, int max_level, std::vector<int>& out) const;

  // The cell of a point; false outside the bounds.
  bool cell_of(float u, float v, int* col, int* row) const;
  // Features of one cell (indices into the feature array), for walks along a line. The cells of
  // a row are stored in column order, so cell_begin(c0, row) to cell_end(c1, row) (c0 <= c1)
  // lists the features of cells c0..c1 of that row, cell by cell.
  const int* cell_begin(int col, int row) const { return index_.data() + start_[cell(col, row)]; }
  const int* cell_end(int col, int row) const { return index_.data() + start_[cell(col, row) + 1]; }
  const ImageBounds& bounds() const { return bounds_; }
  float cell_width() const { return 1.0f / inv_cell_w_; }
  float cell_height() const { return 1.0f / inv_cell_h_; }

 private:
  static int cell(int col, int row) { return row * kCols + col; }
  const map::KeyframeFeature* features_ = nullptr;
  ImageBounds bounds_;
  float inv_cell_w_ = 1.0f, inv_cell_h_ = 1.0f;
  std::vector<int> start_;  // kCols * kRows + 1 offsets into index_ (counting sort)
  std::vector<int> index_;
  std::vector<int> cell_of_feature_;
  std::vector<int> fill_;
};

}  // namespace ale::slam
