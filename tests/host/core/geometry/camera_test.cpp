// Camera models with the parameters of the datasets we replay (EuRoC cam0 radtan, TUM fr1
// radtan with k3, TUM-VI equidistant fisheye, ideal pinhole): projection Jacobians against
// central differences, project/unproject round trips over the whole image, failure on
// non-finite input, points behind the camera, non-convergence, and create()'s validation.
// On the host, projection and undistortion are also checked against OpenCV calib3d.
#include "core/geometry/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "core/base/rng.h"
#include "tests/host/support/euroc_cam0.h"

#ifdef ALE_HAVE_CALIB3D
#include <opencv2/calib3d.hpp>
#endif

namespace ale::geometry {
namespace {

struct NamedIntrinsics {
  std::string name;
  CameraIntrinsics k;
};

CameraIntrinsics radtan(double fx, double fy, double cx, double cy, std::array<double, 5> d, int w, int h) {
  CameraIntrinsics k;
  k.model = CameraModel::kPinholeRadTan;
  k.fx = fx, k.fy = fy, k.cx = cx, k.cy = cy;
  k.distortion = d;
  k.width = w, k.height = h;
  return k;
}

CameraIntrinsics euroc_cam0() { return ale::test::euroc_cam0_intrinsics(); }

CameraIntrinsics tum_fisheye() {
  // TUM-VI cam0, Kalibr's equidistant calibration
  CameraIntrinsics k;
  k.model = CameraModel::kEquidistant;
  k.fx = 190.97847715128717, k.fy = 190.9733070521226, k.cx = 254.93170605935475, k.cy = 256.8974428996504;
  k.distortion = {0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182, 0.0};
  k.width = 512, k.height = 512;
  return k;
}

std::vector<NamedIntrinsics> typical_cameras() {
  return {
      {"euroc_cam0", euroc_cam0()},
      // TUM RGB-D freiburg1, OpenCV's order (k1 k2 p1 p2 k3)
      {"tum_fr1", radtan(517.306408, 516.469215, 318.643040, 255.313989, {0.262383, -0.953104, -0.005358, 0.002628, 1.163314},
                         640, 480)},
      {"pinhole", radtan(525.0, 525.0, 319.5, 239.5, {0.0, 0.0, 0.0, 0.0, 0.0}, 640, 480)},
      {"tum_vi_fisheye", tum_fisheye()},
      // a strong fisheye (OpenCV-style calibration of a 180 deg lens)
      {"strong_fisheye",
       [] {
         CameraIntrinsics k = tum_fisheye();
         k.distortion = {-0.05, 0.012, -0.004, 0.0005, 0.0};
         return k;
       }()},
  };
}

// A point uniform in [-half_x, half_x] x [-half_y, half_y] x [z_min, z_max], one draw per
// statement (constructor arguments are evaluated in an unspecified, platform-dependent order).
Vec3 draw_point(SplitMix64& rng, double half_x, double half_y, double z_min, double z_max) {
  const double x = half_x * (2.0 * rng.uniform_double() - 1.0);
  const double y = half_y * (2.0 * rng.uniform_double() - 1.0);
  const double z = z_min + (z_max - z_min) * rng.uniform_double();
  return Vec3(x, y, z);
}

Camera make(const CameraIntrinsics& k) {
  Result<Camera> c = Camera::create(k);
  EXPECT_TRUE(c.ok()) << c.status().to_string();
  return c.ok() ? *c : Camera();
}

// Pixels on a grid covering the image including its border rows and columns. A fisheye's
// image corners see rays beyond 90 deg, which a ray (x, y, 1) cannot hold: for the equidistant
// model the grid keeps the pixels with theta_d below 1.2 rad (about 70 deg).
std::vector<Vec2> pixel_grid(const CameraIntrinsics& k, int steps) {
  std::vector<Vec2> out;
  for (int j = 0; j <= steps; ++j)
    for (int i = 0; i <= steps; ++i) {
      const Vec2 uv((k.width - 1) * static_cast<double>(i) / steps, (k.height - 1) * static_cast<double>(j) / steps);
      const double theta_d = Vec2((uv.x() - k.cx) / k.fx, (uv.y() - k.cy) / k.fy).norm();
      if (k.model == CameraModel::kEquidistant && theta_d > 1.2) continue;
      out.push_back(uv);
    }
  return out;
}

// Central differences of the pixel with step h; false when a shifted point does not project.
bool numeric_d_uv_d_p(const Camera& cam, const Vec3& p, double h, Mat23* num) {
  for (int c = 0; c < 3; ++c) {
    Vec3 dp = Vec3::Zero();
    dp[c] = h;
    Vec2 plus, minus;
    if (!cam.project(p + dp, &plus) || !cam.project(p - dp, &minus)) return false;
    num->col(c) = (plus - minus) / (2.0 * h);
  }
  return true;
}

TEST(Camera, ProjectJacobianMatchesCentralDifferences) {
  SplitMix64 rng(31);
  for (const auto& [name, k] : typical_cameras()) {
    const Camera cam = make(k);
    const std::vector<Vec2> grid = pixel_grid(k, 12);
    EXPECT_GT(grid.size(), 13u * 13u / 2u) << name;
    for (const Vec2& uv : grid) {
      Vec3 ray;
      ASSERT_TRUE(cam.unproject(uv, &ray)) << name << " " << uv.transpose();
      const Vec3 p = ray * (0.5 + 5.0 * rng.uniform_double());
      Vec2 pix;
      Mat23 j;
      ASSERT_TRUE(cam.project(p, &pix, &j));
      Mat23 num;
      ASSERT_TRUE(numeric_d_uv_d_p(cam, p, 1e-6 * p.norm(), &num));
      // relative to the Jacobian's size (fx / z): central differences are good to ~1e-9 here
      EXPECT_LT((j - num).norm(), 1e-7 * j.norm()) << name << " at " << uv.transpose() << "\n" << j << "\n" << num;
      // the Jacobian does not change the pixel
      Vec2 pix2;
      ASSERT_TRUE(cam.project(p, &pix2));
      EXPECT_EQ(pix, pix2);
    }
  }
}

TEST(Camera, JacobianNearTheOpticalAxis) {
  // The equidistant model switches to a series below r = 1e-4 (normalised): check both sides.
  for (const auto& [name, k] : typical_cameras()) {
    const Camera cam = make(k);
    for (double r : {0.0, 1e-9, 1e-5, 9.9e-5, 1.01e-4, 1e-3}) {
      const Vec3 p(2.0 * r * 0.6, -2.0 * r * 0.8, 2.0);  // normalised radius r
      Vec2 pix;
      Mat23 j;
      ASSERT_TRUE(cam.project(p, &pix, &j));
      Mat23 num;
      ASSERT_TRUE(numeric_d_uv_d_p(cam, p, 1e-5, &num));
      EXPECT_LT((j - num).norm(), 1e-7 * j.norm()) << name << " r " << r;
    }
  }
}

TEST(Camera, UnprojectProjectRoundTripOverTheImage) {
  for (const auto& [name, k] : typical_cameras()) {
    const Camera cam = make(k);
    double worst_px = 0.0;
    for (const Vec2& uv : pixel_grid(k, 40)) {
      Vec3 ray;
      ASSERT_TRUE(cam.unproject(uv, &ray)) << name << " " << uv.transpose();
      EXPECT_EQ(ray.z(), 1.0);
      Vec2 back;
      ASSERT_TRUE(cam.project(ray * 3.0, &back));
      worst_px = std::max(worst_px, (back - uv).norm());
    }
    // Newton stops below 1e-10 normalised (~5e-8 px) and takes one more step: rounding is left
    EXPECT_LT(worst_px, 1e-9) << name;
  }
}

TEST(Camera, ProjectUnprojectRoundTripForPoints) {
  SplitMix64 rng(37);
  for (const auto& [name, k] : typical_cameras()) {
    const Camera cam = make(k);
    int inside = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 p = draw_point(rng, 2.0, 2.0, 0.2, 4.2);
      Vec2 uv;
      if (!cam.project(p, &uv)) continue;
      if (uv.x() < 0.0 || uv.y() < 0.0 || uv.x() > k.width - 1 || uv.y() > k.height - 1) continue;
      ++inside;
      Vec3 ray;
      ASSERT_TRUE(cam.unproject(uv, &ray)) << name;
      EXPECT_LT((ray * p.z() - p).norm(), 1e-9 * p.norm()) << name << " " << p.transpose();
    }
    EXPECT_GT(inside, 100) << name;
  }
}

TEST(Camera, UndistortPixelIsUnprojectThenIdealPinhole) {
  for (const auto& [name, k] : typical_cameras()) {
    const Camera cam = make(k);
    const Camera ideal = cam.undistorted();
    EXPECT_FALSE(ideal.has_distortion());
    EXPECT_EQ(ideal.intrinsics().fx, k.fx);
    EXPECT_EQ(ideal.intrinsics().cy, k.cy);
    for (const Vec2& uv : pixel_grid(k, 10)) {
      Vec2 u;
      ASSERT_TRUE(cam.undistort_pixel(uv, &u));
      Vec3 ray;
      ASSERT_TRUE(cam.unproject(uv, &ray));
      Vec2 expected;
      ASSERT_TRUE(ideal.project(ray, &expected));
      EXPECT_LT((u - expected).norm(), 1e-9);
      // and distorting the ideal pixel again gives the input back
      Vec3 ideal_ray;
      ASSERT_TRUE(ideal.unproject(u, &ideal_ray));
      Vec2 again;
      ASSERT_TRUE(cam.project(ideal_ray, &again));
      EXPECT_LT((again - uv).norm(), 1e-9) << name;
    }
  }
  // no distortion: the identity
  const Camera pin = make(typical_cameras()[2].k);
  Vec2 u;
  ASSERT_TRUE(pin.undistort_pixel(Vec2(12.25, 400.5), &u));
  EXPECT_LT((u - Vec2(12.25, 400.5)).norm(), 1e-12);
}

TEST(Camera, HasDistortion) {
  EXPECT_TRUE(make(euroc_cam0()).has_distortion());
  EXPECT_FALSE(make(typical_cameras()[2].k).has_distortion());
  CameraIntrinsics k = tum_fisheye();
  k.distortion = {};
  EXPECT_TRUE(make(k).has_distortion());  // atan(r) still bends the rays
}

TEST(Camera, RejectsPointsBehindAndNonFinite) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [name, k] : typical_cameras()) {
    const Camera cam = make(k);
    const Vec2 sentinel(-7.0, -7.0);
    for (const Vec3& p : {Vec3(0.1, 0.2, -1.0), Vec3(0.1, 0.2, 0.0), Vec3(1.0, 0.0, 1e-12), Vec3(nan, 0.0, 1.0),
                          Vec3(0.0, inf, 1.0), Vec3(0.0, 0.0, inf), Vec3(0.0, 0.0, nan)}) {
      Vec2 uv = sentinel;
      Mat23 j;
      EXPECT_FALSE(cam.project(p, &uv, &j)) << name << " " << p.transpose();
      EXPECT_EQ(uv, sentinel);  // untouched
    }
    for (const Vec2& uv : {Vec2(nan, 10.0), Vec2(10.0, inf), Vec2(-inf, -inf)}) {
      Vec3 ray(5.0, 5.0, 5.0);
      EXPECT_FALSE(cam.unproject(uv, &ray)) << name;
      Vec2 ideal;
      EXPECT_FALSE(cam.undistort_pixel(uv, &ideal)) << name;
    }
  }
  // a default-constructed camera is invalid and says so instead of dividing by zero
  const Camera invalid;
  Vec2 uv;
  Vec3 ray;
  EXPECT_FALSE(invalid.project(Vec3(0.0, 0.0, 1.0), &uv));
  EXPECT_FALSE(invalid.unproject(Vec2(1.0, 1.0), &ray));
}

TEST(Camera, UnprojectFailsWhereTheDistortionCannotBeInverted) {
  // A strong barrel distortion x_d = x (1 - 0.45 r^2) folds at r = sqrt(1 / 1.35): distorted
  // radii beyond the fold's maximum have no preimage, and Newton must say so instead of
  // returning a wrong ray. (EuRoC's k1 = -0.28, k2 = 0.074 never folds.)
  CameraIntrinsics k = euroc_cam0();
  k.distortion = {-0.45, 0.0, 0.0, 0.0, 0.0};
  const Camera barrel = make(k);
  const double r_fold = std::sqrt(1.0 / 1.35);
  const double r_d_max = r_fold * (1.0 - 0.45 * r_fold * r_fold);
  Vec3 ray;
  for (double angle : {0.0, 0.7, 2.0, 4.0}) {
    const Vec2 dir(std::cos(angle), std::sin(angle));
    const auto pixel = [&](double r_d) { return Vec2(k.cx + k.fx * r_d * dir.x(), k.cy + k.fy * r_d * dir.y()); };
    EXPECT_FALSE(barrel.unproject(pixel(r_d_max * 1.02), &ray)) << angle;
    EXPECT_FALSE(barrel.unproject(pixel(50.0), &ray)) << angle;
    ASSERT_TRUE(barrel.unproject(pixel(r_d_max * 0.95), &ray)) << angle;
    // the root found is the one before the fold
    EXPECT_LT(ray.head<2>().norm(), r_fold) << angle;
  }

  // Equidistant: theta_d beyond what theta < pi/2 reaches (here theta_d(pi/2) ~ 1.57).
  const Camera fish = make(tum_fisheye());
  const double ffx = fish.intrinsics().fx, fcx = fish.intrinsics().cx, fcy = fish.intrinsics().cy;
  EXPECT_FALSE(fish.unproject(Vec2(fcx + ffx * 1.7, fcy), &ray));
  EXPECT_TRUE(fish.unproject(Vec2(fcx + ffx * 1.4, fcy), &ray));
  // the TUM-VI image corner (1.9 rad off axis) is such a pixel
  EXPECT_FALSE(fish.unproject(Vec2(0.0, 0.0), &ray));
}

TEST(Camera, CreateRejectsBadIntrinsics) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto expect_rejected = [](CameraIntrinsics k, const char* what) {
    const Result<Camera> c = Camera::create(k);
    ASSERT_FALSE(c.ok()) << what;
    EXPECT_EQ(c.status().code(), StatusCode::kInvalidArgument) << what;
    EXPECT_FALSE(c.status().message().empty());
  };
  CameraIntrinsics k = euroc_cam0();
  ASSERT_TRUE(Camera::create(k).ok());
  k.fx = 0.0;
  expect_rejected(k, "fx 0");
  k = euroc_cam0(), k.fy = -458.0;
  expect_rejected(k, "fy < 0");
  k = euroc_cam0(), k.fx = nan;
  expect_rejected(k, "fx nan");
  k = euroc_cam0(), k.cx = inf;
  expect_rejected(k, "cx inf");
  k = euroc_cam0(), k.distortion[2] = nan;
  expect_rejected(k, "p1 nan");
  k = euroc_cam0(), k.width = -1;
  expect_rejected(k, "negative width");
  k = euroc_cam0(), k.model = static_cast<CameraModel>(7);
  expect_rejected(k, "unknown model");
  k = tum_fisheye(), k.distortion[4] = 0.1;
  expect_rejected(k, "equidistant fifth coefficient");
  k = euroc_cam0(), k.width = 0, k.height = 0;
  EXPECT_TRUE(Camera::create(k).ok()) << "unknown size is allowed";
}

#ifdef ALE_HAVE_CALIB3D
// Ours against cv::projectPoints / cv::fisheye::projectPoints (identity pose) and against
// cv::undistortPoints run to convergence.
TEST(CameraVsOpenCv, ProjectionAndUndistortionAgree) {
  SplitMix64 rng(41);
  for (const auto& [name, k] : typical_cameras()) {
    const Camera cam = make(k);
    std::vector<cv::Point3d> points;
    std::vector<Vec2> ours;
    for (int i = 0; i < 500; ++i) {
      const Vec3 p = draw_point(rng, 2.0, 1.5, 0.5, 4.5);
      Vec2 uv;
      if (!cam.project(p, &uv)) continue;
      points.emplace_back(p.x(), p.y(), p.z());
      ours.push_back(uv);
    }
    ASSERT_GT(points.size(), 400u);
    const cv::Matx33d kmat(k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0);
    std::vector<cv::Point2d> theirs;
    const cv::Vec3d zero(0.0, 0.0, 0.0);
    if (k.model == CameraModel::kEquidistant) {
      const cv::Vec4d d(k.distortion[0], k.distortion[1], k.distortion[2], k.distortion[3]);
      cv::fisheye::projectPoints(points, theirs, zero, zero, kmat, d);
    } else {
      const std::vector<double> d(k.distortion.begin(), k.distortion.end());
      cv::projectPoints(points, zero, zero, kmat, d, theirs);
    }
    double worst = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i)
      worst = std::max(worst, (ours[i] - Vec2(theirs[i].x, theirs[i].y)).norm());
    EXPECT_LT(worst, 1e-8) << name << " projection";
    std::printf("%-16s vs OpenCV: projection max %.2e px", name.c_str(), worst);

    // undistortion over the image, both run to convergence (OpenCV until its step is below 1e-14)
    std::vector<cv::Point2d> distorted, undist;
    for (const Vec2& uv : pixel_grid(k, 20)) distorted.emplace_back(uv.x(), uv.y());
    const cv::TermCriteria crit(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 1000, 1e-14);
    if (k.model == CameraModel::kEquidistant) {
      const cv::Vec4d d(k.distortion[0], k.distortion[1], k.distortion[2], k.distortion[3]);
      cv::fisheye::undistortPoints(distorted, undist, kmat, d, cv::noArray(), kmat, crit);
    } else {
      const std::vector<double> d(k.distortion.begin(), k.distortion.end());
      cv::undistortPoints(distorted, undist, kmat, d, cv::noArray(), kmat, crit);
    }
    worst = 0.0;
    for (std::size_t i = 0; i < distorted.size(); ++i) {
      Vec2 u;
      ASSERT_TRUE(cam.undistort_pixel(Vec2(distorted[i].x, distorted[i].y), &u));
      worst = std::max(worst, (u - Vec2(undist[i].x, undist[i].y)).norm());
    }
    EXPECT_LT(worst, 1e-9) << name << " undistortion";
    std::printf(", undistortion max %.2e px\n", worst);
  }
}
#endif

}  // namespace
}  // namespace ale::geometry
