#include "core/slam/match/feature_grid.h"

#include <algorithm>
#include <cmath>

namespace ale::slam {

ScalePyramid ScalePyramid::make(int levels, float scale_factor) {
  ScalePyramid p;
  p.levels = std::clamp(levels, 1, kMaxLevels);
  p.scale_factor = scale_factor > 1.0f ? scale_factor : 1.2f;
  p.log_scale_factor = std::log(p.scale_factor);
  float s = 1.0f;
  for (int l = 0; l < p.levels; ++l) {
    p.scale[l] = s;
    p.inv_scale[l] = 1.0f / s;
    p.sigma2[l] = s * s;
    p.inv_sigma2[l] = 1.0f / (s * s);
    s *= p.scale_factor;
  }
  return p;
}

int ScalePyramid::predict_level(float distance, float max_distance) const {
  if (!(distance > 0.0f) || !(max_distance > 0.0f)) return 0;
  const float ratio = max_distance / distance;
  const int level = static_cast<int>(std::ceil(std::log(ratio) / log_scale_factor));
  return std::clamp(level, 0, levels - 1);
}

void FeatureGrid::build(const map::KeyframeFeature* features, int count, const ImageBounds& bounds) {
  features_ = features;
  bounds_ = bounds;
  const float w = std::max(bounds.max_u - bounds.min_u, 1.0f);
  const float h = std::max(bounds.max_v - bounds.min_v, 1.0f);
  inv_cell_w_ = static_cast<float>(kCols) / w;
  inv_cell_h_ = static_cast<float>(kRows) / h;
  start_.assign(kCols * kRows + 1, 0);
  cell_of_feature_.resize(static_cast<std::size_t>(std::max(count, 0)));
  for (int i = 0; i < count; ++i) {
    int c = 0, r = 0;
    if (cell_of(features[i].u, features[i].v, &c, &r)) {
      cell_of_feature_[static_cast<std::size_t>(i)] = cell(c, r);
      ++start_[static_cast<std::size_t>(cell(c, r)) + 1];
    } else {
      cell_of_feature_[static_cast<std::size_t>(i)] = -1;
    }
  }
  for (std::size_t k = 1; k < start_.size(); ++k) start_[k] += start_[k - 1];
  index_.resize(static_cast<std::size_t>(start_.back()));
  // fill in feature order so each cell lists ascending indices
  fill_.assign(start_.begin(), start_.end() - 1);
  for (int i = 0; i < count; ++i) {
    const int c = cell_of_feature_[static_cast<std::size_t>(i)];
    if (c >= 0) index_[static_cast<std::size_t>(fill_[static_cast<std::size_t>(c)]++)] = i;
  }
}

bool FeatureGrid::cell_of(float u, float v, int* col, int* row) const {
  if (!bounds_.contains(u, v)) return false;
  const int c = static_cast<int>((u - bounds_.min_u) * inv_cell_w_);
  const int r = static_cast<int>((v - bounds_.min_v) * inv_cell_h_);
  if (c < 0 || c >= kCols || r < 0 || r >= kRows) return false;
  *col = c;
  *row = r;
  return true;
}

void FeatureGrid::query(float u, float v, float r, int min_level, int max_level, std::vector<int>& out) const {
  if (!features_ || start_.empty()) return;
  const int c0 = floor_clamped((u - r - bounds_.min_u) * inv_cell_w_, 0, kCols);
  const int c1 = floor_clamped((u + r - bounds_.min_u) * inv_cell_w_, -1, kCols - 1);
  const int r0 = floor_clamped((v - r - bounds_.min_v) * inv_cell_h_, 0, kRows);
  const int r1 = floor_clamped((v + r - bounds_.min_v) * inv_cell_h_, -1, kRows - 1);
  if (c0 > c1 || r0 > r1) return;
  const std::size_t first = out.size();
  for (int row = r0; row <= r1; ++row) {
    // cells c0..c1 of the row in one pass (cell_begin)
    for (const int* p = cell_begin(c0, row), *end = cell_end(c1, row); p != end; ++p) {
      const map::KeyframeFeature& f = features_[*p];
      if (f.level < min_level || (max_level >= 0 && f.level > max_level)) continue;
      if (std::fabs(f.u - u) > r || std::fabs(f.v - v) > r) continue;
      out.push_back(*p);
    }
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
}

}  // namespace ale::slam
