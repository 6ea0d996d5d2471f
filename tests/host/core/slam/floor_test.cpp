// The floor as a scale cue: the mounting's floor geometry, and the floor's distance found among a
// camera's points (the densest group of distances below the camera, walls and noise around it).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/slam/floor.h"

namespace ale::slam {
namespace {

using geometry::SE3;
using geometry::SO3;
using geometry::Vec3;

// A sweeper's mounting: camera axes (x right, y down, z forward) in the base (x forward, y left,
// z up), tilted up by 12 degrees, 9 cm above the floor and 15 cm ahead of the axle.
SE3 sweeper_mounting(double height_m = 0.09) {
  const double t = 12.0 * M_PI / 180.0;
  geometry::Mat3 R;
  R.col(0) = Vec3(0, -1, 0);
  R.col(1) = Vec3(std::sin(t), 0, -std::cos(t));
  R.col(2) = Vec3(std::cos(t), 0, std::sin(t));
  return SE3(SO3(Eigen::Quaterniond(R)), Vec3(0.15, 0.0, height_m));
}

TEST(FloorGeometry, TheMountingGivesTheFloorInTheCameraFrame) {
  const SE3 T_bc = sweeper_mounting();
  const std::optional<FloorGeometry> g = floor_geometry(FloorParams{}, T_bc);
  ASSERT_TRUE(g.has_value());
  EXPECT_NEAR(g->camera_height_m, 0.09, 1e-12);
  // a point on the floor 1 m ahead of the base, in the camera frame, lies on the plane
  const Vec3 p_c = T_bc.inverse() * Vec3(1.0, 0.3, 0.0);
  EXPECT_NEAR(g->up_c.dot(p_c) + g->camera_height_m, 0.0, 1e-12);
  EXPECT_NEAR(g->up_c.norm(), 1.0, 1e-12);
  // no cue: off, an unset mounting (the identity), a camera on the floor
  FloorParams off;
  off.enabled = false;
  EXPECT_FALSE(floor_geometry(off, T_bc).has_value());
  EXPECT_FALSE(floor_geometry(FloorParams{}, SE3()).has_value());
  EXPECT_FALSE(floor_geometry(FloorParams{}, sweeper_mounting(0.01)).has_value());
}

// The points of a view at map scale `scale` (map units per metre): floor points 0.3-4 m ahead
// with 1.5 % depth noise, wall points from the floor to 2.5 m, some points above the camera.
std::vector<Vec3> view_points(const SE3& T_bc, double scale, int floor_points, int wall_points, std::mt19937& rng) {
  std::uniform_real_distribution<double> ahead(0.3, 4.0), side(-2.0, 2.0), up(0.0, 2.5);
  std::normal_distribution<double> noise(0.0, 0.015);
  std::vector<Vec3> pts;
  const SE3 T_cb = T_bc.inverse();
  for (int i = 0; i < floor_points; ++i) pts.push_back(scale * (1.0 + noise(rng)) * (T_cb * Vec3(ahead(rng), side(rng), 0.0)));
  for (int i = 0; i < wall_points; ++i) pts.push_back(scale * (T_cb * Vec3(4.0, side(rng), up(rng))));
  return pts;
}

TEST(FloorDistance, FindsTheFloorAmongWallsAtAnyScale) {
  const SE3 T_bc = sweeper_mounting();
  const FloorGeometry g = *floor_geometry(FloorParams{}, T_bc);
  std::mt19937 rng(3);
  std::vector<double> scratch;
  for (double scale : {0.37, 1.0, 4.2}) {
    const std::vector<Vec3> pts = view_points(T_bc, scale, 60, 200, rng);
    const std::optional<FloorFit> fit = floor_distance(FloorParams{}, g.up_c, pts, scratch);
    ASSERT_TRUE(fit.has_value()) << scale;
    EXPECT_NEAR(fit->distance / (scale * 0.09), 1.0, 0.01) << scale;
    EXPECT_GE(fit->points, 50);
  }
  // too few floor points: no fit (the walls below the camera spread out, no group of 20)
  const std::vector<Vec3> few = view_points(T_bc, 1.0, 10, 200, rng);
  EXPECT_FALSE(floor_distance(FloorParams{}, g.up_c, few, scratch).has_value());
  // nothing below the camera
  EXPECT_FALSE(floor_distance(FloorParams{}, g.up_c, {}, scratch).has_value());
}

TEST(FloorDistance, OfTwoEquallyDenseGroupsTheFartherIsTheFloor) {
  const Vec3 up(0, -1, 0);  // camera looking ahead, y down
  std::vector<Vec3> pts;
  for (int i = 0; i < 30; ++i) pts.push_back(Vec3(0.01 * i, 0.05, 1.0 + 0.1 * i));  // a table top 5 cm below
  for (int i = 0; i < 30; ++i) pts.push_back(Vec3(0.01 * i, 0.09, 1.0 + 0.1 * i));  // the floor 9 cm below
  std::vector<double> scratch;
  const std::optional<FloorFit> fit = floor_distance(FloorParams{}, up, pts, scratch);
  ASSERT_TRUE(fit.has_value());
  EXPECT_NEAR(fit->distance, 0.09, 1e-12);
  EXPECT_EQ(fit->points, 30);
}

}  // namespace
}  // namespace ale::slam
