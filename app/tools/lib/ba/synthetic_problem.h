// Seeded synthetic bundle-adjustment scenes (a camera moving past a textured room volume) for
// the optimiser's tests, benchmarks and ARM instruction counts: the same seed gives the same
// scene on every machine (core/base/rng.h).
#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry/camera.h"
#include "core/geometry/lie.h"

namespace ale::optim {

struct SyntheticObservation {
  int pose = 0, point = 0;
  geometry::Vec2 uv_px = geometry::Vec2::Zero();
  int level = 0;          // pyramid level: noise sigma = scale_factor^level pixels
  bool outlier = false;   // uv is a random pixel, not the point's projection
};

struct SyntheticScene {
  geometry::CameraIntrinsics intrinsics;
  double scale_factor = 1.2;
  std::vector<geometry::SE3> T_cw_true, T_cw_init;
  std::vector<bool> pose_fixed;
  std::vector<geometry::Vec3> points_true, points_init;
  std::vector<SyntheticObservation> observations;
};

struct SyntheticOptions {
  int keyframes = 10;
  int fixed = 2;          // the first `fixed` keyframes keep their true pose
  int points = 3000;
  int views_per_point = 5;  // observations = points * views_per_point
  double outlier_ratio = 0.05;
  double noise_px = 1.0;    // sigma at level 0
  int levels = 8;
  double pose_noise_rad = 0.005, pose_noise_m = 0.02, point_noise_m = 0.05;  // initial errors
  std::uint64_t seed = 1;
};

struct SyntheticPoseScene {
  geometry::CameraIntrinsics intrinsics;
  double scale_factor = 1.2;
  geometry::SE3 T_cw_true, T_cw_init;
  std::vector<geometry::Vec3> points_w;
  std::vector<geometry::Vec2> uv_px;
  std::vector<int> levels;
  std::vector<bool> outlier;
};

// One frame's matches for motion-only optimisation: `matches` points at 1.5-8 m seen by the
// camera of make_synthetic_scene, 1 px noise x 1.2^level, `outlier_ratio` of them moved 20-100 px;
// the initial pose is off by about 2 deg and 10 cm (a constant-velocity prediction's error).
SyntheticPoseScene make_synthetic_pose_scene(int matches, double outlier_ratio, std::uint64_t seed);

// A local-BA-shaped scene: keyframes 0.15 m apart along x with small rotations, points at
// 2-8 m depth, each seen by views_per_point consecutive keyframes inside the 640x480 image.
SyntheticScene make_synthetic_scene(const SyntheticOptions& options);

}  // namespace ale::optim
