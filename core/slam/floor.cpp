#include "core/slam/floor.h"

#include <algorithm>
#include <cmath>

namespace ale::slam {
namespace {
constexpr ConfigField kFloorFields[] = {
    flag<&FloorParams::enabled>("enabled", "the camera's height above the floor as a scale cue (needs T_bc's height)"),
    number<&FloorParams::sigma_m>("sigma_m", 1e-5, 1, "local BA: a floor landmark's height prior, sigma in m"),
    number<&FloorParams::max_height_m>("max_height_m", 0, 1, "local BA: landmarks this close to the floor are held on it, m"),
    number<&FloorParams::min_camera_height_m>("min_camera_height_m", 0, 10,
                                              "a mounting lower than this gives no floor cue, m"),
    number<&FloorParams::distance_tolerance>("distance_tolerance", 0.001, 0.5,
                                             "finding the floor: its landmarks' distances agree within this share"),
    number<&FloorParams::min_points>("min_points", 3, 100000, "finding the floor: landmarks needed to scale the map by it"),
};
}  // namespace
extern constexpr ConfigTable kFloorConfig = table_of<FloorParams>(kFloorFields);

Status validate(const FloorParams& p) { return check_ranges(kFloorConfig, &p, "floor."); }

geometry::Vec3 floor_normal_in_camera(const geometry::SE3& T_bc) {
  return T_bc.rotation().transpose() * geometry::Vec3::UnitZ();
}

std::optional<FloorGeometry> floor_geometry(const FloorParams& params, const geometry::SE3& T_bc) {
  const double height = T_bc.translation().z();
  if (!params.enabled || !(height >= params.min_camera_height_m) || !(height > 0.0)) return std::nullopt;
  FloorGeometry g;
  g.up_c = floor_normal_in_camera(T_bc);
  g.camera_height_m = height;
  return g;
}

std::optional<FloorFit> floor_distance(const FloorParams& params, const geometry::Vec3& up_c,
                                       const std::vector<geometry::Vec3>& points_c, std::vector<double>& scratch) {
  scratch.clear();
  for (const geometry::Vec3& p : points_c) {
    const double d = -up_c.dot(p);
    if (d > 0.0 && std::isfinite(d)) scratch.push_back(std::log(d));
  }
  std::sort(scratch.begin(), scratch.end());
  const double width = 2.0 * std::log1p(params.distance_tolerance);
  const int n = static_cast<int>(scratch.size());
  int best_begin = 0, best_count = 0;
  for (int begin = 0, end = 0; begin < n; ++begin) {
    while (end < n && scratch[static_cast<std::size_t>(end)] - scratch[static_cast<std::size_t>(begin)] <= width) ++end;
    if (end - begin >= best_count) {  // >=: the farthest of equally dense groups
      best_count = end - begin;
      best_begin = begin;
    }
  }
  if (best_count < params.min_points) return std::nullopt;
  FloorFit fit;
  fit.points = best_count;
  fit.distance = std::exp(scratch[static_cast<std::size_t>(best_begin + best_count / 2)]);
  return fit;
}

}  // namespace ale::slam
