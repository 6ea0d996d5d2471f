// Motion-only pose optimisation with ORB-SLAM's outlier rounds: 300 matches with 20 % outliers
// recover the pose and flag the outliers; bad input is a status; nothing is allocated.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/optim/motion_only.h"
#include "core/optim/synthetic_problem.h"
#include "tests/host/core/optim/alloc_counter.h"

namespace ale::optim {
namespace {

using geometry::Camera;
using geometry::SE3;
using geometry::Vec3;

std::vector<PoseObservation> observations_of(const SyntheticPoseScene& s) {
  std::vector<PoseObservation> obs;
  for (std::size_t k = 0; k < s.points_w.size(); ++k) obs.push_back({s.points_w[k], s.uv_px[k], s.levels[k]});
  return obs;
}

TEST(MotionOnly, RecoversPoseAndFlagsOutliers) {
  for (std::uint64_t seed : {1u, 2u, 3u, 4u, 5u}) {
    const SyntheticPoseScene s = make_synthetic_pose_scene(300, 0.2, seed);
    const Camera cam = Camera::create(s.intrinsics).value();
    const std::vector<PoseObservation> obs = observations_of(s);
    std::vector<std::uint8_t> inlier(obs.size());
    const MotionOnlyResult r = optimize_pose(cam, s.T_cw_init, obs.data(), static_cast<int>(obs.size()), {}, inlier.data());
    ASSERT_TRUE(r.status.ok()) << r.status.to_string();
    const double rot_deg = (r.T_cw.so3() * s.T_cw_true.so3().inverse()).log().norm() * 180 / M_PI;
    const double centre_m = (r.T_cw.inverse().translation() - s.T_cw_true.inverse().translation()).norm();
    const double init_rot_deg = (s.T_cw_init.so3() * s.T_cw_true.so3().inverse()).log().norm() * 180 / M_PI;
    // 240 good matches at 1-3.6 px noise: the pose is good to a few hundredths of a degree and
    // a few millimetres (the start is ~2 deg, ~10 cm off)
    EXPECT_LT(rot_deg, 0.1) << "seed " << seed << " start " << init_rot_deg;
    EXPECT_LT(centre_m, 0.01) << "seed " << seed;
    int caught = 0, outliers = 0, good_flagged = 0, count = 0;
    for (std::size_t k = 0; k < obs.size(); ++k) {
      outliers += s.outlier[k];
      caught += s.outlier[k] && !inlier[k];
      good_flagged += !s.outlier[k] && !inlier[k];
      count += inlier[k];
    }
    EXPECT_EQ(caught, outliers) << "seed " << seed;           // every outlier is >= 20 px off
    EXPECT_LE(good_flagged, (300 - outliers) / 10) << "seed " << seed;  // the 95 % gate: ~5 %
    EXPECT_EQ(count, r.inliers);
    EXPECT_LE(r.iterations, 40);
  }
}

TEST(MotionOnly, BadInputAndTooFewInliers) {
  const SyntheticPoseScene s = make_synthetic_pose_scene(30, 0.0, 9);
  const Camera cam = Camera::create(s.intrinsics).value();
  const std::vector<PoseObservation> obs = observations_of(s);
  std::vector<std::uint8_t> inlier(obs.size());
  EXPECT_EQ(optimize_pose(cam, s.T_cw_init, obs.data(), 2, {}, inlier.data()).status.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(optimize_pose(Camera(), s.T_cw_init, obs.data(), 30, {}, inlier.data()).status.code(),
            StatusCode::kInvalidArgument);
  std::vector<PoseObservation> bad = obs;
  bad[3].uv_px.x() = NAN;
  EXPECT_EQ(optimize_pose(cam, s.T_cw_init, bad.data(), 30, {}, inlier.data()).status.code(), StatusCode::kInvalidArgument);
  // every match wrong: not enough inliers is a status, the pose stays finite
  const SyntheticPoseScene all_bad = make_synthetic_pose_scene(30, 1.0, 9);
  const std::vector<PoseObservation> wrong = observations_of(all_bad);
  const MotionOnlyResult r = optimize_pose(cam, all_bad.T_cw_init, wrong.data(), 30, {}, inlier.data());
  EXPECT_EQ(r.status.code(), StatusCode::kNotFound);
  EXPECT_TRUE(r.T_cw.translation().allFinite());
}

TEST(MotionOnly, NoAllocation) {
  const SyntheticPoseScene s = make_synthetic_pose_scene(300, 0.2, 3);
  const Camera cam = Camera::create(s.intrinsics).value();
  const std::vector<PoseObservation> obs = observations_of(s);
  std::vector<std::uint8_t> inlier(obs.size());
  test::AllocationCounter counter;
  const MotionOnlyResult r = optimize_pose(cam, s.T_cw_init, obs.data(), 300, {}, inlier.data());
  EXPECT_EQ(counter.count(), 0);
  EXPECT_TRUE(r.status.ok());
}

}  // namespace
}  // namespace ale::optim
