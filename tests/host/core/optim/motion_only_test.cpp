// Motion-only pose optimisation with ORB-SLAM's outlier rounds: 300 matches with 20 % outliers
// recover the pose and flag the outliers; bad input is a status; nothing is allocated.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/optim/motion_only.h"
#include "app/tools/lib/ba/synthetic_problem.h"
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
    // The oracle: the true inliers only, no kernel, converged. Its distance from the truth is the
    // noise's (0.02-0.06 deg on these seeds); ours must be close to the oracle.
    std::vector<PoseObservation> good;
    for (std::size_t k = 0; k < obs.size(); ++k) {
      if (!s.outlier[k]) good.push_back(obs[k]);
    }
    std::vector<std::uint8_t> good_inlier(good.size());
    MotionOnlyOptions oracle_options;
    oracle_options.robust_rounds = 0;
    oracle_options.chi2_gate = 1e30;
    oracle_options.iterations = 100;
    oracle_options.lm.function_tolerance = 1e-14;
    const MotionOnlyResult oracle = optimize_pose(cam, s.T_cw_true, good.data(), static_cast<int>(good.size()),
                                                  oracle_options, good_inlier.data());
    ASSERT_TRUE(oracle.status.ok());
    const double from_oracle_deg = (r.T_cw.so3() * oracle.T_cw.so3().inverse()).log().norm() * 180 / M_PI;
    const double from_oracle_m = (r.T_cw.inverse().translation() - oracle.T_cw.inverse().translation()).norm();
    std::printf("seed %d: rotation error %.4f deg, centre %.4f m; from the oracle %.4f deg, %.4f m\n",
                static_cast<int>(seed), rot_deg, centre_m, from_oracle_deg, from_oracle_m);
    // The start is ~2 deg and ~10 cm off. The oracle's own spread is up to 0.063 deg here; ours
    // differs from it by dropping the ~5 % of good matches beyond the gate (up to 0.054 deg).
    EXPECT_LT(rot_deg, 0.15) << "seed " << seed;
    EXPECT_LT(centre_m, 0.01) << "seed " << seed;
    EXPECT_LT(from_oracle_deg, 0.08) << "seed " << seed;
    EXPECT_LT(from_oracle_m, 0.006) << "seed " << seed;
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
