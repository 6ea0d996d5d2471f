// Synthetic PnP scenes shared by the PnP tests: points in front of a camera with EuRoC-like
// intrinsics, pixels with Gaussian noise scaled by a per-point pyramid sigma, and a share of
// outliers moved far off their true pixel.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/base/rng.h"
#include "core/geometry/camera.h"
#include "core/geometry/lie.h"
#include "core/geometry/pnp.h"
#include "tests/host/support/euroc_cam0.h"

namespace ale::geometry::test {

inline Camera euroc_pinhole() {
  CameraIntrinsics k = ale::test::euroc_cam0_intrinsics();
  k.distortion = {0.0, 0.0, 0.0, 0.0, 0.0};
  return Camera::create(k).value();
}

inline double gaussian(SplitMix64& rng) {
  // Box-Muller from two 53-bit uniforms: full tails, same stream on every machine.
  const double u1 = 1.0 - rng.uniform_double();
  const double u2 = rng.uniform_double();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

// Vectors of draws taken one after the other: the order in which a constructor's arguments are
// evaluated is unspecified (GCC differs between x86-64 and ARM), so Vec3(f(rng), f(rng), f(rng))
// would give other scenes on the board.
inline Vec3 gaussian3(SplitMix64& rng) {
  const double x = gaussian(rng);
  const double y = gaussian(rng);
  const double z = gaussian(rng);
  return Vec3(x, y, z);
}
inline Vec2 gaussian2(SplitMix64& rng) {
  const double x = gaussian(rng);
  const double y = gaussian(rng);
  return Vec2(x, y);
}
// Uniform in the box [lo, hi).
inline Vec3 uniform3(SplitMix64& rng, const Vec3& lo, const Vec3& hi) {
  Vec3 v;
  for (int i = 0; i < 3; ++i) v(i) = lo(i) + (hi(i) - lo(i)) * rng.uniform_double();
  return v;
}

inline SE3 random_pose(SplitMix64& rng, double angle_rad, double translation_m) {
  const Vec3 axis = gaussian3(rng);
  const Vec3 t = gaussian3(rng);
  return SE3(SO3::exp(axis.normalized() * angle_rad), t.normalized() * translation_m);
}

struct PnpScene {
  SE3 T_cw;
  std::vector<Vec3> points_w;
  std::vector<Vec2> pixels;
  std::vector<double> sigma_px;
  std::vector<std::uint8_t> is_outlier;

  PnpInput input() const {
    return PnpInput{points_w.data(), pixels.data(), sigma_px.data(), static_cast<int>(points_w.size())};
  }
};

// n points seen by `camera` at depths [2, 8] m (planar: all on the plane z_c = 4 m tilted by
// 0.3 rad), noise of sigma_px = 1.2^level (level 0..levels-1) times `noise_px`, and a share
// `outlier_ratio` of pixels replaced by uniform pixels at least 20 px from the truth.
inline PnpScene make_scene(const Camera& camera, std::uint64_t seed, int n, double noise_px, double outlier_ratio,
                           bool planar = false, int levels = 4) {
  SplitMix64 rng(seed);
  PnpScene s;
  s.T_cw = random_pose(rng, 0.5, 1.5);
  const SE3 T_wc = s.T_cw.inverse();
  const CameraIntrinsics& k = camera.intrinsics();
  const int n_out = static_cast<int>(std::lround(outlier_ratio * n));
  while (static_cast<int>(s.points_w.size()) < n) {
    const double u = 10.0 + (k.width - 20.0) * rng.uniform_double();
    const double v = 10.0 + (k.height - 20.0) * rng.uniform_double();
    Vec3 ray;
    if (!camera.unproject(Vec2(u, v), &ray)) continue;
    double depth = 2.0 + 6.0 * rng.uniform_double();
    if (planar) {
      // Plane n . p_c = 4 with n tilted about x.
      const Vec3 normal(0.0, std::sin(0.3), std::cos(0.3));
      depth = 4.0 / normal.dot(ray);
    }
    const Vec3 p_w = T_wc * (ray * depth);
    const int level = static_cast<int>(rng.below(static_cast<std::uint32_t>(levels)));
    const double sigma = std::pow(1.2, level);
    Vec2 uv;
    if (!camera.project(s.T_cw * p_w, &uv)) continue;
    const bool outlier = static_cast<int>(s.points_w.size()) < n_out;
    if (outlier) {
      Vec2 bad;
      do {
        const double bu = k.width * rng.uniform_double();
        bad = Vec2(bu, k.height * rng.uniform_double());
      } while ((bad - uv).norm() < 20.0);
      uv = bad;
    } else {
      uv += noise_px * sigma * gaussian2(rng);
    }
    s.points_w.push_back(p_w);
    s.pixels.push_back(uv);
    s.sigma_px.push_back(sigma);
    s.is_outlier.push_back(outlier ? 1 : 0);
  }
  return s;
}

inline double rotation_error_deg(const SE3& a, const SE3& b) {
  return (a.so3() * b.so3().inverse()).log().norm() * 180.0 / 3.14159265358979323846;
}

// Distance between the camera centres.
inline double centre_error_m(const SE3& a, const SE3& b) {
  return (a.inverse().translation() - b.inverse().translation()).norm();
}

// |A n B| / |A u B| of two masks.
inline double jaccard(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  int inter = 0, uni = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    inter += (a[i] && b[i]) ? 1 : 0;
    uni += (a[i] || b[i]) ? 1 : 0;
  }
  return uni > 0 ? static_cast<double>(inter) / uni : 1.0;
}

}  // namespace ale::geometry::test
