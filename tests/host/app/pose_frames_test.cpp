#include "app/daemon/pose_frames.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace ale::app {
namespace {

Eigen::Isometry3d iso(const std::array<double, 3>& p, const std::array<double, 4>& q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
  T.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
  return T;
}

std::array<double, 16> row_major(const Eigen::Isometry3d& T) {
  std::array<double, 16> m{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[static_cast<std::size_t>(4 * r + c)] = T.matrix()(r, c);
  return m;
}

hal::PoseEstimate tracked_pose(std::int64_t t_ns, const Eigen::Isometry3d& T_wc) {
  hal::PoseEstimate p;
  p.timestamp_ns = t_ns;
  p.state = TrackingState::kTracking;
  const Eigen::Quaterniond q(T_wc.linear());
  p.q_wc = {q.w(), q.x(), q.y(), q.z()};
  p.p_wc = {T_wc.translation().x(), T_wc.translation().y(), T_wc.translation().z()};
  return p;
}

TEST(PoseFramesTest, BodyPoseIsCameraPoseTimesInverseExtrinsics) {
  // EuRoC-like extrinsics: camera looking forward on a body, 5 cm ahead and 2 cm up.
  const Eigen::Isometry3d T_bc = iso({0.05, 0.0, 0.02}, {0.5, -0.5, 0.5, -0.5});
  const Eigen::Isometry3d T_wc =
      iso({1.0, 2.0, 0.3}, {0.9238795325112867, 0.0, 0.0, 0.3826834323650898}) * iso({0, 0, 0}, {0.5, -0.5, 0.5, -0.5});
  auto rigid = rigid_from_row_major(row_major(T_bc));
  ASSERT_TRUE(rigid.has_value());
  hal::PoseEstimate pose = tracked_pose(0, T_wc);
  apply_body_frame(rigid, pose);
  ASSERT_TRUE(pose.body_valid);
  const Eigen::Isometry3d want = T_wc * T_bc.inverse();
  const Eigen::Isometry3d got = iso(pose.p_wb, pose.q_wb);
  EXPECT_LT((got.matrix() - want.matrix()).norm(), 1e-12);
  EXPECT_LT((iso(pose.p_bc, pose.q_bc).matrix() - T_bc.matrix()).norm(), 1e-12);
}

TEST(PoseFramesTest, WithoutExtrinsicsTheBodyPoseIsTheCameraPose) {
  hal::PoseEstimate pose = tracked_pose(0, iso({1, 2, 3}, {0, 1, 0, 0}));
  apply_body_frame(std::nullopt, pose);
  EXPECT_FALSE(pose.body_valid);
  EXPECT_EQ(pose.p_wb, pose.p_wc);
  EXPECT_EQ(pose.q_wb, pose.q_wc);
}

TEST(PoseFramesTest, RejectsAMatrixThatIsNotRigid) {
  std::array<double, 16> m{2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // a scale
  EXPECT_FALSE(rigid_from_row_major(m).has_value());
  std::array<double, 16> mirror{-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_FALSE(rigid_from_row_major(mirror).has_value());
}

TEST(PoseFramesTest, VelocitiesFromTheLastTwoTrackedPoses) {
  const Eigen::Isometry3d T0 = iso({1, 0, 0}, {1, 0, 0, 0});
  Eigen::Isometry3d T1 = Eigen::Isometry3d::Identity();
  T1.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T1.translation() = Eigen::Vector3d(1.05, 0, -0.02);
  const hal::PoseEstimate p0 = tracked_pose(1000000000, T0);
  hal::PoseEstimate p1 = tracked_pose(1100000000, T1);  // 0.1 s later
  apply_motion(p0, p1);
  EXPECT_NEAR(p1.velocity_w_mps[0], 0.5, 1e-9);
  EXPECT_NEAR(p1.velocity_w_mps[2], -0.2, 1e-9);
  EXPECT_NEAR(p1.angular_velocity_w_radps[1], 0.1, 1e-9);
  EXPECT_NEAR(p1.angular_velocity_w_radps[0], 0.0, 1e-12);

  hal::PoseEstimate reset = p1;
  reset.map_id = 1;  // a new map: the old pose says nothing about this one
  apply_motion(p0, reset);
  EXPECT_EQ(reset.velocity_w_mps, (std::array<double, 3>{0, 0, 0}));
  hal::PoseEstimate lost = p0;
  lost.state = TrackingState::kLost;
  hal::PoseEstimate after_lost = p1;
  apply_motion(lost, after_lost);
  EXPECT_EQ(after_lost.angular_velocity_w_radps, (std::array<double, 3>{0, 0, 0}));
}

}  // namespace
}  // namespace ale::app
