#include "core/slam/floor_plane.h"

#include <algorithm>
#include <cmath>

namespace ale::slam {

using geometry::Vec3;

namespace {

constexpr std::size_t kMaxSearchPoints = 1500;

struct Score {
  int support = 0, below = 0;
};

Score score(const FloorPlane& f, double band, const std::vector<Vec3>& points) {
  Score s;
  const double limit = band * f.height;
  for (const Vec3& x : points) {
    const double h = f.height_of(x);
    if (std::abs(h) < limit) {
      ++s.support;
    } else if (h < -limit) {
      ++s.below;
    }
  }
  return s;
}


// The densest band [x (1 - b), x (1 + b)] of the sorted depths below the camera: its centre and
// count, scored by count / x (points per unit of thickness: the floor is thin and crowded, a
// band far below gathers points in a wide slab).
struct Band {
  double depth = 0.0, density = 0.0;
  int count = 0;
};
Band densest_band(const std::vector<double>& sorted, double b, int min_count) {
  Band best;
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const double x = sorted[i];
    if (!(x > 0.0)) continue;
    while (sorted[lo] < x * (1.0 - b)) ++lo;
    if (hi < i) hi = i;
    while (hi + 1 < sorted.size() && sorted[hi + 1] <= x * (1.0 + b)) ++hi;
    const int count = static_cast<int>(hi + 1 - lo);
    const double density = count / x;
    if (count >= min_count && density > best.density) best = {x, density, count};
  }
  return best;
}

Vec3 tilted_up(double pitch_rad, double roll_rad) {
  // the camera's up (-y) turned about x by pitch (toward +z) and about z by roll
  const Vec3 n(std::sin(roll_rad) * std::cos(pitch_rad), -std::cos(roll_rad) * std::cos(pitch_rad), std::sin(pitch_rad));
  return n.normalized();
}

}  // namespace

std::optional<FloorPlane> find_floor(const std::vector<FloorSample>& keyframes, const FloorParams& params) {
  if (!params.enabled || static_cast<int>(keyframes.size()) < std::max(1, params.min_keyframes)) return std::nullopt;
  std::vector<Vec3> all;
  for (const FloorSample& k : keyframes)
    for (const Vec3& x : k.points_c)
      if (x.allFinite() && x.y() > 0.0) all.push_back(x);  // the floor is below the optical axis
  if (static_cast<int>(all.size()) < params.min_support) return std::nullopt;
  std::vector<Vec3> points;
  const std::size_t stride = (all.size() + kMaxSearchPoints - 1) / kMaxSearchPoints;
  for (std::size_t i = 0; i < all.size(); i += stride) points.push_back(all[i]);
  const int min_count = std::max(3, static_cast<int>(params.min_support / static_cast<double>(stride)));

  // a coarse grid of normals around the camera's up axis, then a finer one around the best
  std::vector<double> depth;
  auto evaluate = [&](double pitch, double roll) {
    const Vec3 n = tilted_up(pitch, roll);
    depth.clear();
    for (const Vec3& x : points) depth.push_back(-n.dot(x));
    std::sort(depth.begin(), depth.end());
    return densest_band(depth, params.band, min_count);
  };
  const double deg = M_PI / 180.0;
  double best_pitch = 0.0, best_roll = 0.0;
  Band best;
  for (int pass = 0; pass < 2; ++pass) {
    const double step = (pass == 0 ? params.search_step_deg : params.search_step_deg / 5.0) * deg;
    const double pitch_span = pass == 0 ? params.max_tilt_deg * deg : params.search_step_deg * deg;
    const double roll_span = pass == 0 ? params.max_roll_deg * deg : params.search_step_deg * deg;
    const double p0 = pass == 0 ? 0.0 : best_pitch, r0 = pass == 0 ? 0.0 : best_roll;
    const int np = static_cast<int>(std::floor(pitch_span / step + 1e-9)), nr = static_cast<int>(std::floor(roll_span / step + 1e-9));
    for (int i = -np; i <= np; ++i) {
      for (int j = -nr; j <= nr; ++j) {
        const Band b = evaluate(p0 + i * step, r0 + j * step);
        if (b.density > best.density) {
          best = b;
          best_pitch = p0 + i * step;
          best_roll = r0 + j * step;
        }
      }
    }
  }
  if (best.count < min_count) return std::nullopt;
  FloorPlane floor;
  floor.n_c = tilted_up(best_pitch, best_roll);
  floor.height = best.depth;
  // over every point and per keyframe
  const Score s = score(floor, params.band, all);
  if (s.support < params.min_support || s.below > params.max_below_share * s.support) return std::nullopt;
  int seeing = 0;
  for (const FloorSample& k : keyframes) seeing += score(floor, params.band, k.points_c).support >= params.min_keyframe_support;
  if (seeing < params.min_keyframe_share * static_cast<double>(keyframes.size())) return std::nullopt;
  floor.support = s.support;
  return floor;
}

}  // namespace ale::slam
