// Synthetic two-view scenes for the two-view tests: a pinhole camera, a known motion, points in
// general position or on a plane, Gaussian pixel noise and a share of outliers, all seeded.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "core/base/rng.h"
#include "core/geometry/camera.h"
#include "core/geometry/lie.h"
#include "tests/host/core/geometry/pose_error.h"

namespace ale::test {

using geometry::Mat3;
using geometry::Vec2;
using geometry::Vec3;

struct SceneSpec {
  bool planar = false;
  int points = 300;
  double noise_px = 1.0;       // sigma of the Gaussian added to both pixels
  double outlier_ratio = 0.3;  // share of matches whose second pixel is replaced by a random one
  double min_depth_m = 2.0, max_depth_m = 8.0;  // general scenes: depth in camera 1
  // Planar scenes: n^T p_1 = d, an oblique plane (like a floor seen by a forward camera, 2 to
  // 12 m deep over the image).
  Vec3 plane_normal_1 = Vec3(0.0, 0.8, 0.6);
  double plane_distance_m = 2.0;
  Mat3 R_21 = Eigen::AngleAxisd(6.0 * M_PI / 180.0, Vec3(0.2, 1.0, -0.1).normalized()).toRotationMatrix();
  Vec3 t_21 = Vec3(-0.5, 0.08, 0.12);
  std::uint64_t seed = 1;
};

struct Scene {
  geometry::CameraIntrinsics camera;  // ideal pinhole, 640x480
  Mat3 R_21;
  Vec3 t_21;
  std::vector<Vec2> x1, x2;         // observed (noisy, with outliers)
  std::vector<Vec3> p_1;            // true points in camera 1
  std::vector<std::uint8_t> inlier;  // 1 where x2 comes from p_1
};

inline geometry::CameraIntrinsics test_pinhole() {
  geometry::CameraIntrinsics k;
  k.fx = 450.0;
  k.fy = 452.0;
  k.cx = 322.0;
  k.cy = 241.0;
  k.width = 640;
  k.height = 480;
  return k;
}

inline Vec2 project_pinhole(const geometry::CameraIntrinsics& k, const Vec3& p) {
  return Vec2(k.fx * p.x() / p.z() + k.cx, k.fy * p.y() / p.z() + k.cy);
}

inline bool in_image(const geometry::CameraIntrinsics& k, const Vec2& uv) {
  return uv.x() >= 0.0 && uv.y() >= 0.0 && uv.x() < k.width && uv.y() < k.height;
}

inline Scene make_scene(const SceneSpec& spec) {
  Scene s;
  s.camera = test_pinhole();
  s.R_21 = spec.R_21;
  s.t_21 = spec.t_21;
  const geometry::CameraIntrinsics& k = s.camera;
  SplitMix64 rng(spec.seed);
  // Points: a pixel of image 1 and a depth (or the plane's), kept when camera 2 sees them.
  int guard = 0;
  while (static_cast<int>(s.p_1.size()) < spec.points && ++guard < 100 * spec.points) {
    // One draw per statement: the order in which a constructor's arguments are evaluated differs
    // between compilers (host and ARM would see different scenes).
    const double u = rng.uniform_double() * k.width;
    const double v = rng.uniform_double() * k.height;
    const Vec2 uv(u, v);
    const Vec3 ray((uv.x() - k.cx) / k.fx, (uv.y() - k.cy) / k.fy, 1.0);
    double depth = spec.min_depth_m + rng.uniform_double() * (spec.max_depth_m - spec.min_depth_m);
    if (spec.planar) depth = spec.plane_distance_m / spec.plane_normal_1.dot(ray);
    if (!(depth > 0.0)) continue;
    const Vec3 p1 = depth * ray;
    const Vec3 p2 = s.R_21 * p1 + s.t_21;
    if (p2.z() <= 0.1 || !in_image(k, project_pinhole(k, p2))) continue;
    s.p_1.push_back(p1);
  }
  const int n = static_cast<int>(s.p_1.size());
  s.inlier.assign(static_cast<std::size_t>(n), 1);
  // Exactly round(ratio * n) outliers, chosen by a seeded shuffle.
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  for (int i = n - 1; i > 0; --i)
    std::swap(order[static_cast<std::size_t>(i)], order[rng.below(static_cast<std::uint32_t>(i + 1))]);
  const int outliers = static_cast<int>(std::lround(spec.outlier_ratio * n));
  for (int i = 0; i < outliers; ++i) s.inlier[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])] = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3& p1 = s.p_1[static_cast<std::size_t>(i)];
    const auto gaussian2 = [&rng] {
      const double gx = rng.gaussian();
      const double gy = rng.gaussian();
      return Vec2(gx, gy);
    };
    const Vec2 n1 = gaussian2();
    const Vec2 n2 = gaussian2();
    s.x1.push_back(project_pinhole(k, p1) + spec.noise_px * n1);
    if (s.inlier[static_cast<std::size_t>(i)]) {
      s.x2.push_back(project_pinhole(k, s.R_21 * p1 + s.t_21) + spec.noise_px * n2);
    } else {
      const double u = rng.uniform_double() * k.width;
      const double v = rng.uniform_double() * k.height;
      s.x2.push_back(Vec2(u, v));
    }
  }
  return s;
}

inline Mat3 K_of(const geometry::CameraIntrinsics& k) {
  Mat3 K = Mat3::Identity();
  K(0, 0) = k.fx;
  K(1, 1) = k.fy;
  K(0, 2) = k.cx;
  K(1, 2) = k.cy;
  return K;
}

inline Mat3 true_fundamental(const Scene& s) {
  const Mat3 K_inv = K_of(s.camera).inverse();
  return K_inv.transpose() * geometry::hat(s.t_21) * s.R_21 * K_inv;
}

// The homography x2 ~ H x1 of the scene's plane (planar scenes).
inline Mat3 true_homography(const Scene& s, const SceneSpec& spec) {
  const Mat3 K = K_of(s.camera);
  const Mat3 A = s.R_21 + s.t_21 * spec.plane_normal_1.transpose() / spec.plane_distance_m;
  return K * A * K.inverse();
}

}  // namespace ale::test
