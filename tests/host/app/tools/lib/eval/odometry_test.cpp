#include "app/tools/lib/eval/odometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ale::eval {
namespace {

constexpr double kPi = 3.14159265358979323846;

replay::OdometryRow row(std::int64_t t_ns, double x, double y, double theta) {
  replay::OdometryRow r;
  r.timestamp_ns = t_ns;
  r.x_m = x;
  r.y_m = y;
  r.theta_rad = theta;
  return r;
}

// The camera 0.15 m ahead of the base and 0.09 m up, looking along the base's x (camera z forward,
// x right, y down).
replay::OdometryTrack track_with_camera() {
  replay::OdometryTrack t;
  t.list_file = "odometry0/data.csv";
  t.sensor_yaml = "odometry0/sensor.yaml";
  t.T_BC = std::array<double, 16>{0, 0, 1, 0.15, -1, 0, 0, 0, 0, -1, 0, 0.09, 0, 0, 0, 1};
  return t;
}

TEST(OdometryTrajectoryTest, CameraIsTheBasePoseTimesTbc) {
  replay::OdometryTrack t = track_with_camera();
  t.rows = {row(1000000000, 0.0, 0.0, 0.0), row(2000000000, 1.0, 2.0, kPi / 2)};
  Result<Trajectory> traj = odometry_camera_trajectory(t);
  ASSERT_TRUE(traj.ok()) << traj.status().message();
  ASSERT_EQ(traj->poses.size(), 2u);
  EXPECT_DOUBLE_EQ(traj->poses[0].t_s, 1.0);
  EXPECT_NEAR((traj->poses[0].p_wb - Eigen::Vector3d(0.15, 0.0, 0.09)).norm(), 0.0, 1e-12);
  // Facing +y: the camera 0.15 m further along y, its optical axis (z) along world +y.
  EXPECT_NEAR((traj->poses[1].p_wb - Eigen::Vector3d(1.0, 2.15, 0.09)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((traj->poses[1].R_wb.col(2) - Eigen::Vector3d(0, 1, 0)).norm(), 0.0, 1e-12);
}

TEST(OdometryTrajectoryTest, InterpolatesThetaAlongTheShorterArcAndSkipsTimesOutside) {
  replay::OdometryTrack t = track_with_camera();
  t.rows = {row(0, 0.0, 0.0, kPi - 0.1), row(100, 1.0, 0.0, -kPi + 0.1)};
  Result<Trajectory> traj = odometry_camera_trajectory(t, {-10, 50, 200});
  ASSERT_TRUE(traj.ok()) << traj.status().message();
  ASSERT_EQ(traj->poses.size(), 1u);  // -10 and 200 lie outside the rows
  // Halfway: x 0.5, heading pi (not 0, the long way round): the camera 0.15 m behind along -x.
  EXPECT_NEAR((traj->poses[0].p_wb - Eigen::Vector3d(0.35, 0.0, 0.09)).norm(), 0.0, 1e-12);
}

TEST(OdometryTrajectoryTest, RefusesWhatCannotBeTurnedIntoPoses) {
  replay::OdometryTrack t = track_with_camera();
  t.rows = {row(0, 0.0, 0.0, 0.0), row(100, std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0)};
  Result<Trajectory> nan = odometry_camera_trajectory(t);
  ASSERT_FALSE(nan.ok());
  EXPECT_NE(nan.status().message().find("odometry0/data.csv: row 2"), std::string::npos) << nan.status().message();

  t.rows = {row(0, 0.0, 0.0, 0.0)};
  Result<Trajectory> outside = odometry_camera_trajectory(t, {50});
  ASSERT_FALSE(outside.ok());
  EXPECT_NE(outside.status().message().find("no odometry row"), std::string::npos);

  t.T_BC->at(0) = 2.0;  // a scaled rotation
  Result<Trajectory> scaled = odometry_camera_trajectory(t);
  ASSERT_FALSE(scaled.ok());
  EXPECT_NE(scaled.status().message().find("sensor.yaml: T_BC is not a rigid transform"), std::string::npos);

  t.T_BC.reset();
  Result<Trajectory> none = odometry_camera_trajectory(t);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.status().message().find("sensor.yaml: no T_BC"), std::string::npos);
}

}  // namespace
}  // namespace ale::eval
