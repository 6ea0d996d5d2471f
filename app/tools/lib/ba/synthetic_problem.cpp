#include "app/tools/lib/ba/synthetic_problem.h"

#include <algorithm>
#include <cmath>

#include "core/base/rng.h"

namespace ale::optim {

using geometry::SE3;
using geometry::SO3;
using geometry::Vec2;
using geometry::Vec3;

namespace {

Vec3 gaussian3(SplitMix64* rng) { return Vec3(rng->gaussian(), rng->gaussian(), rng->gaussian()); }

// A far outlier: 20-100 px from the true pixel in a random direction.
Vec2 outlier_pixel(const Vec2& uv_true, SplitMix64* rng) {
  const double a = 2.0 * M_PI * rng->uniform_double();
  return uv_true + (20.0 + 80.0 * rng->uniform_double()) * Vec2(std::cos(a), std::sin(a));
}

geometry::CameraIntrinsics vga_camera() {
  geometry::CameraIntrinsics k;
  k.model = geometry::CameraModel::kPinholeRadTan;
  k.fx = 458.0;
  k.fy = 457.0;
  k.cx = 320.0;
  k.cy = 240.0;
  k.distortion = {-0.28, 0.07, 0.0002, 0.00002, 0.0};  // EuRoC-like radtan
  k.width = 640;
  k.height = 480;
  return k;
}

}  // namespace

SyntheticPoseScene make_synthetic_pose_scene(int matches, double outlier_ratio, std::uint64_t seed) {
  SyntheticPoseScene s;
  s.intrinsics = vga_camera();
  const geometry::Camera camera = geometry::Camera::create(s.intrinsics).value();
  SplitMix64 rng(seed);
  s.T_cw_true = SE3(SO3::exp(Vec3(0.05, -0.3, 0.02)), Vec3(0.4, -0.1, 0.2));
  const geometry::Vec6 err = (geometry::Vec6() << 0.06 * gaussian3(&rng), 0.02 * gaussian3(&rng)).finished();
  s.T_cw_init = SE3::exp(err) * s.T_cw_true;
  const SE3 T_wc = s.T_cw_true.inverse();
  while (static_cast<int>(s.points_w.size()) < matches) {
    const Vec2 uv(10.0 + 620.0 * rng.uniform_double(), 10.0 + 460.0 * rng.uniform_double());
    Vec3 ray;
    if (!camera.unproject(uv, &ray)) continue;
    const Vec3 p_w = T_wc * (ray * (1.5 + 6.5 * rng.uniform_double()));
    const int level = static_cast<int>(rng.below(8));
    const bool out = rng.uniform_double() < outlier_ratio;
    s.points_w.push_back(p_w);
    s.levels.push_back(level);
    s.outlier.push_back(out);
    s.uv_px.push_back(out ? outlier_pixel(uv, &rng)
                          : Vec2(uv + std::pow(s.scale_factor, level) * Vec2(rng.gaussian(), rng.gaussian())));
  }
  return s;
}

SyntheticScene make_synthetic_scene(const SyntheticOptions& o) {
  SyntheticScene s;
  s.intrinsics = vga_camera();
  const geometry::Camera camera = geometry::Camera::create(s.intrinsics).value();
  SplitMix64 rng(o.seed);

  for (int i = 0; i < o.keyframes; ++i) {
    const Vec3 centre(0.15 * i, 0.02 * std::sin(0.7 * i), 0.05 * std::cos(0.5 * i));
    const SO3 r_wc = SO3::exp(Vec3(0.02 * std::sin(0.3 * i), 0.05 * i - 0.2, 0.01 * i));
    const SE3 T_cw = SE3(r_wc, centre).inverse();
    s.T_cw_true.push_back(T_cw);
    const bool fixed = i < o.fixed;
    s.pose_fixed.push_back(fixed);
    s.T_cw_init.push_back(fixed ? T_cw
                                : SE3::exp((geometry::Vec6() << o.pose_noise_m * gaussian3(&rng),
                                            o.pose_noise_rad * gaussian3(&rng))
                                               .finished()) *
                                      T_cw);
  }
  const int window = std::min(o.views_per_point, o.keyframes);
  while (static_cast<int>(s.points_true.size()) < o.points) {
    const int first = static_cast<int>(rng.below(static_cast<std::uint32_t>(o.keyframes - window + 1)));
    // a pixel and depth in the middle keyframe of the window, back to the world
    const int mid = first + window / 2;
    const Vec2 uv(20.0 + 600.0 * rng.uniform_double(), 20.0 + 440.0 * rng.uniform_double());
    Vec3 ray;
    if (!camera.unproject(uv, &ray)) continue;
    const Vec3 p_w = s.T_cw_true[mid].inverse() * (ray * (2.0 + 6.0 * rng.uniform_double()));
    bool visible = true;
    Vec2 tmp;
    for (int i = first; i < first + window && visible; ++i) {
      visible = camera.project(s.T_cw_true[i] * p_w, &tmp) && tmp.x() >= 0.0 && tmp.x() < 640.0 &&
                tmp.y() >= 0.0 && tmp.y() < 480.0;
    }
    if (!visible) continue;
    const int j = static_cast<int>(s.points_true.size());
    s.points_true.push_back(p_w);
    s.points_init.push_back(p_w + o.point_noise_m * gaussian3(&rng));
    for (int i = first; i < first + window; ++i) {
      SyntheticObservation ob;
      ob.pose = i;
      ob.point = j;
      ob.level = static_cast<int>(rng.below(static_cast<std::uint32_t>(std::max(1, o.levels))));
      ob.outlier = rng.uniform_double() < o.outlier_ratio;
      camera.project(s.T_cw_true[i] * p_w, &ob.uv_px);
      if (ob.outlier) {
        ob.uv_px = outlier_pixel(ob.uv_px, &rng);
      } else {
        const double sigma = o.noise_px * std::pow(s.scale_factor, ob.level);
        ob.uv_px += sigma * Vec2(rng.gaussian(), rng.gaussian());
      }
      s.observations.push_back(ob);
    }
  }
  return s;
}

}  // namespace ale::optim
