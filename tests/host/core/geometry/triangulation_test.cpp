// Linear triangulation: exact recovery on synthetic two-view scenes, and each check reporting
// its own status (NaN/inf input, rays at infinity, points behind either camera, reprojection
// gate, low parallax).
#include "core/geometry/triangulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/base/rng.h"
#include "tests/host/core/geometry/pnp_scene.h"

namespace ale::geometry {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Two cameras 0.5 m apart looking down +z at a scene 2..6 m away, the second rotated a little.
struct TwoViews {
  SE3 T_1w = SE3(SO3::exp(Vec3(0.02, -0.03, 0.01)), Vec3(0.1, -0.05, 0.2));
  SE3 T_2w = SE3(SO3::exp(Vec3(-0.05, 0.12, 0.03)), Vec3(-0.4, 0.1, 0.05));
};

Vec2 normalised(const SE3& T_cw, const Vec3& p_w) {
  const Vec3 p_c = T_cw * p_w;
  return p_c.head<2>() / p_c.z();
}

Camera pinhole() { return test::euroc_pinhole(); }

TEST(Triangulation, ExactDataRecoversThePoint) {
  const TwoViews v;
  SplitMix64 rng(7);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p_w = test::uniform3(rng, Vec3(-2.0, -1.5, 2.0), Vec3(2.0, 1.5, 6.0));
    const Triangulation t =
        triangulate_normalised(v.T_1w, v.T_2w, normalised(v.T_1w, p_w), normalised(v.T_2w, p_w), 1e-3, 1e-3);
    ASSERT_EQ(t.status, TriangulationStatus::kOk) << to_string(t.status) << " at point " << i;
    EXPECT_LT((t.p_w - p_w).norm(), 1e-9 * p_w.norm());
    EXPECT_NEAR(t.depth_1, (v.T_1w * p_w).z(), 1e-9);
    EXPECT_NEAR(t.depth_2, (v.T_2w * p_w).z(), 1e-9);
    EXPECT_LT(t.err2_1, 1e-20);
    EXPECT_LT(t.err2_2, 1e-20);
    // Parallax from the camera centres, independently of the rays.
    const Vec3 c1 = v.T_1w.inverse().translation(), c2 = v.T_2w.inverse().translation();
    const double cos_expected = (p_w - c1).normalized().dot((p_w - c2).normalized());
    EXPECT_NEAR(t.cos_parallax, cos_expected, 1e-12);
  }
}

TEST(Triangulation, PixelsThroughTheCameraModel) {
  const TwoViews v;
  const Camera cam = pinhole();
  const Vec3 p_w(0.3, -0.2, 3.5);
  Vec2 uv_1, uv_2;
  ASSERT_TRUE(cam.project(v.T_1w * p_w, &uv_1));
  ASSERT_TRUE(cam.project(v.T_2w * p_w, &uv_2));
  const Triangulation exact = triangulate_pixels(cam, v.T_1w, v.T_2w, uv_1, uv_2, 1.0, 1.0);
  ASSERT_EQ(exact.status, TriangulationStatus::kOk) << to_string(exact.status);
  EXPECT_LT((exact.p_w - p_w).norm(), 1e-9);

  // One pixel of error across the epipolar line (the baseline runs along x) in the second view
  // passes a 1 px sigma gate: the DLT spreads it over both views, about 0.5 px each. Four
  // pixels under a 0.3 px sigma (gate 0.54 px^2) do not.
  const Vec2 off(0.0, 1.0);
  const Triangulation loose = triangulate_pixels(cam, v.T_1w, v.T_2w, uv_1, uv_2 + off, 1.0, 1.0);
  EXPECT_EQ(loose.status, TriangulationStatus::kOk) << to_string(loose.status);
  EXPECT_GT(loose.err2_1 + loose.err2_2, 0.05);
  const Triangulation tight = triangulate_pixels(cam, v.T_1w, v.T_2w, uv_1, uv_2 + 4.0 * off, 0.3, 0.3);
  EXPECT_TRUE(tight.status == TriangulationStatus::kReprojectionFirst ||
              tight.status == TriangulationStatus::kReprojectionSecond)
      << to_string(tight.status);
}

TEST(Triangulation, DistortedPixelsThroughTheCameraModel) {
  // EuRoC cam0's radial-tangential coefficients: raw pixels are unprojected by the model and the
  // reprojection error is measured on distorted pixels.
  CameraIntrinsics k = test::euroc_pinhole().intrinsics();
  k.distortion = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0.0};
  const Camera cam = Camera::create(k).value();
  const TwoViews v;
  SplitMix64 rng(5);
  for (int i = 0; i < 50; ++i) {
    const Vec3 p_w = test::uniform3(rng, Vec3(-1.5, -1.0, 2.5), Vec3(1.5, 1.0, 6.0));
    Vec2 uv_1, uv_2;
    ASSERT_TRUE(cam.project(v.T_1w * p_w, &uv_1));
    ASSERT_TRUE(cam.project(v.T_2w * p_w, &uv_2));
    const Triangulation t = triangulate_pixels(cam, v.T_1w, v.T_2w, uv_1, uv_2, 1.0, 1.0);
    ASSERT_EQ(t.status, TriangulationStatus::kOk) << to_string(t.status) << " at point " << i;
    EXPECT_LT((t.p_w - p_w).norm(), 1e-8 * p_w.norm());
    EXPECT_LT(t.err2_1 + t.err2_2, 1e-12);
  }
}

TEST(Triangulation, ReprojectionGateUsesEachViewsSigma) {
  const TwoViews v;
  const Vec3 p_w(0.3, -0.2, 3.5);
  const Vec2 x1 = normalised(v.T_1w, p_w);
  // A large disparity error along the second view's y axis (epipolar lines here run mostly
  // along x, so the error cannot be absorbed by moving the point along them).
  const Vec2 x2 = normalised(v.T_2w, p_w) + Vec2(0.0, 0.01);
  const Triangulation t = triangulate_normalised(v.T_1w, v.T_2w, x1, x2, 1e-3, 1e-3);
  EXPECT_TRUE(t.status == TriangulationStatus::kReprojectionFirst ||
              t.status == TriangulationStatus::kReprojectionSecond)
      << to_string(t.status);
  // The residual left over both views is between half the squared offset (the optimal split)
  // and all of it; with a generous sigma in both views the point passes.
  const Triangulation generous = triangulate_normalised(v.T_1w, v.T_2w, x1, x2, 0.02, 0.02);
  EXPECT_EQ(generous.status, TriangulationStatus::kOk) << to_string(generous.status);
  const double total = generous.err2_1 + generous.err2_2;
  EXPECT_GT(total, 0.3 * 1e-4);
  EXPECT_LT(total, 1e-4 * 1.01);
}

TEST(Triangulation, NonFiniteInputsAreReported) {
  const TwoViews v;
  const Vec2 x(0.1, 0.2);
  EXPECT_EQ(triangulate_normalised(v.T_1w, v.T_2w, Vec2(kNaN, 0.0), x, 1e-3, 1e-3).status,
            TriangulationStatus::kNotFinite);
  EXPECT_EQ(triangulate_normalised(v.T_1w, v.T_2w, x, Vec2(0.0, kInf), 1e-3, 1e-3).status,
            TriangulationStatus::kNotFinite);
  EXPECT_EQ(triangulate_normalised(SE3(SO3(), Vec3(kNaN, 0, 0)), v.T_2w, x, x, 1e-3, 1e-3).status,
            TriangulationStatus::kNotFinite);
  EXPECT_EQ(triangulate_normalised(v.T_1w, v.T_2w, x, x, 0.0, 1e-3).status, TriangulationStatus::kNotFinite);
  EXPECT_EQ(triangulate_normalised(v.T_1w, v.T_2w, x, x, 1e-3, kNaN).status, TriangulationStatus::kNotFinite);
  EXPECT_EQ(triangulate_pixels(pinhole(), v.T_1w, v.T_2w, Vec2(kInf, 1.0), x, 1.0, 1.0).status,
            TriangulationStatus::kNotFinite);
}

TEST(Triangulation, ParallelRaysAreAtInfinityOrLowParallax) {
  // Pure rotation about the same centre: every match is a point at infinity.
  const SE3 T_1w(SO3::exp(Vec3(0.0, 0.0, 0.0)), Vec3::Zero());
  const SE3 T_2w(SO3::exp(Vec3(0.0, 0.2, 0.0)), Vec3::Zero());
  const Vec3 dir_w = Vec3(0.1, -0.05, 1.0).normalized();
  const Triangulation t =
      triangulate_normalised(T_1w, T_2w, normalised(T_1w, dir_w), normalised(T_2w, dir_w), 1e-3, 1e-3);
  EXPECT_EQ(t.status, TriangulationStatus::kAtInfinity) << to_string(t.status);
  EXPECT_NEAR(t.cos_parallax, 1.0, 1e-12);

  // A far point with a short baseline: placed, but with too little parallax (1 cm at 50 m is
  // 0.011 deg, cos = 1 - 2e-8).
  const SE3 T_3w(SO3(), Vec3(-0.01, 0.0, 0.0));
  const Vec3 far_w(0.5, 0.2, 50.0);
  const Triangulation low =
      triangulate_normalised(T_1w, T_3w, normalised(T_1w, far_w), normalised(T_3w, far_w), 1e-3, 1e-3);
  EXPECT_EQ(low.status, TriangulationStatus::kLowParallax) << to_string(low.status);
  EXPECT_GT(low.cos_parallax, 0.99998);
  EXPECT_LT((low.p_w - far_w).norm(), 1e-6 * far_w.norm());
  // The same point passes with the bound moved above its cosine.
  TriangulationParams lenient;
  lenient.max_cos_parallax = 1.0 - 1e-9;
  EXPECT_EQ(
      triangulate_normalised(T_1w, T_3w, normalised(T_1w, far_w), normalised(T_3w, far_w), 1e-3, 1e-3, lenient).status,
      TriangulationStatus::kOk);
}

TEST(Triangulation, PointsBehindEitherCamera) {
  // Camera 2 sits 5 m in front of camera 1 looking the same way: a point 3 m in front of
  // camera 1 is behind camera 2.
  const SE3 T_1w(SO3(), Vec3::Zero());
  const SE3 T_2w(SO3(), Vec3(0.0, 0.0, -5.0));
  const Vec3 p_w(0.4, 0.3, 3.0);
  // Its projection into camera 2 (negative depth) still gives a normalised coordinate.
  const Vec3 p_2 = T_2w * p_w;
  ASSERT_LT(p_2.z(), 0.0);
  const Vec2 x2 = p_2.head<2>() / p_2.z();
  const Triangulation t = triangulate_normalised(T_1w, T_2w, normalised(T_1w, p_w), x2, 1e-3, 1e-3);
  EXPECT_EQ(t.status, TriangulationStatus::kBehindSecond) << to_string(t.status);
  EXPECT_LT((t.p_w - p_w).norm(), 1e-9);
  const Triangulation swapped = triangulate_normalised(T_2w, T_1w, x2, normalised(T_1w, p_w), 1e-3, 1e-3);
  EXPECT_EQ(swapped.status, TriangulationStatus::kBehindFirst) << to_string(swapped.status);
  // A point behind both cameras (mirror of a valid point through the first centre).
  const SE3 T_3w(SO3(), Vec3(-0.5, 0.0, 0.0));
  const Vec3 q_w(0.2, 0.1, -4.0);
  const Vec3 q_1 = T_1w * q_w, q_3 = T_3w * q_w;
  const Triangulation both =
      triangulate_normalised(T_1w, T_3w, q_1.head<2>() / q_1.z(), q_3.head<2>() / q_3.z(), 1e-3, 1e-3);
  EXPECT_EQ(both.status, TriangulationStatus::kBehindFirst) << to_string(both.status);
}

TEST(Triangulation, StatusNamesAreDistinct) {
  EXPECT_STREQ(to_string(TriangulationStatus::kOk), "ok");
  EXPECT_STRNE(to_string(TriangulationStatus::kBehindFirst), to_string(TriangulationStatus::kBehindSecond));
  EXPECT_STRNE(to_string(TriangulationStatus::kLowParallax), to_string(TriangulationStatus::kAtInfinity));
}

}  // namespace
}  // namespace ale::geometry
