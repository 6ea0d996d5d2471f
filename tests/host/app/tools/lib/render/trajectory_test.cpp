// The sweeper's loops close and stay on the floor at camera height, clear of the furniture; a
// real EuRoC flight is fitted inside the room, keeping its shape.
#include <gtest/gtest.h>

#include <cmath>

#include "app/tools/lib/render/trajectory.h"
#include "render_fixture.h"
#include "tests/host/support/test_data.h"

namespace ale::render {
namespace {

using test::small_scene;

TEST(RenderTrajectory, LoopClosesAtConstantSpeedAndHeight) {
  DriveOptions d;
  const Trajectory t = make_loop(small_scene(), d, 60.0);
  // One lap of the 3 x 2 m ellipse is ~7.93 m: 26.4 s at 0.3 m/s.
  double length = 0.0;
  double lap_end = -1.0;
  const auto& s = t.samples();
  for (std::size_t i = 1; i < s.size(); ++i) {
    const double step = (s[i].pose.p_wb - s[i - 1].pose.p_wb).norm();
    EXPECT_NEAR(step / (s[i].t_s - s[i - 1].t_s), d.speed_mps, 0.01);
    length += step;
    if (lap_end < 0 && length >= 7.93) lap_end = s[i].t_s;
    EXPECT_DOUBLE_EQ(s[i].pose.p_wb.z(), 0.09);
    EXPECT_FALSE(small_scene().inside_box(s[i].pose.p_wb.cast<float>(), 0.3f)) << s[i].pose.p_wb.transpose();
  }
  ASSERT_GT(lap_end, 0.0);
  EXPECT_NEAR(lap_end, 26.4, 0.2);
  // After a lap the pose is the start pose again (a closed loop).
  const double lap = 7.9327 / d.speed_mps;
  EXPECT_LT((t.at(lap).p_wb - t.at(0.0).p_wb).norm(), 0.01);
  EXPECT_LT(t.at(lap).q_wb.angularDistance(t.at(0.0).q_wb), 0.01);
}

TEST(RenderTrajectory, SquareTurnsInPlaceAndCloses) {
  DriveOptions d;
  const Trajectory t = make_square(small_scene(), d, 40.0);
  // Legs: 8 s straight, 1.5 s turn, 5.33 s straight, 1.5 s turn, ... lap 32.67 s.
  const double lap = 2.0 * (2.4 + 1.6) / d.speed_mps + 4.0 * 1.5;
  // Within one 5 ms trajectory sample of motion (1.5 mm): the lap end falls between samples.
  EXPECT_LT((t.at(lap).p_wb - t.at(0.0).p_wb).norm(), 0.002);
  // Mid-turn at the first corner: heading 45 degrees, the camera 15 cm from the corner.
  const Pose mid = t.at(8.0 + 0.75);
  const Eigen::Vector3d heading = mid.q_wb * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(heading.y(), heading.x()), 0.25 * 3.14159265358979, 1e-3);
  EXPECT_NEAR((mid.p_wb.head<2>() - Eigen::Vector2d(4.2, 1.7)).norm(), 0.15, 1e-6);
  for (const TimedPose& s : t.samples())
    EXPECT_FALSE(small_scene().inside_box(s.pose.p_wb.cast<float>(), 0.3f)) << s.pose.p_wb.transpose();
}

TEST(RenderTrajectory, FitsAFlightIntoTheRoom) {
  // A synthetic 8 x 3 x 2 m flight, longest along x like the room (so not turned).
  std::vector<TimedPose> rec;
  for (int i = 0; i <= 100; ++i) {
    TimedPose p;
    p.t_s = 100.0 + i * 0.1;
    p.pose.p_wb = Eigen::Vector3d(-4.0 + 0.08 * i, 1.5 * std::sin(i * 0.1), 1.0 + std::cos(i * 0.2));
    rec.push_back(p);
  }
  FitReport rep;
  Result<Trajectory> t = fit_into_room(rec, small_scene(), euroc_cam0_rig(), 0.5, &rep);
  ASSERT_TRUE(t.ok()) << t.status().to_string();
  EXPECT_DOUBLE_EQ(rep.yaw_deg, 0.0);
  EXPECT_NEAR(rep.scale, 5.0 / 8.0, 1e-9);  // (6 - 2 * 0.5) / 8
  EXPECT_DOUBLE_EQ(t->samples().front().t_s, 0.0);
  EXPECT_NEAR(t->duration_s(), 10.0, 1e-9);
  for (const TimedPose& s : t->samples()) {
    EXPECT_GE(s.pose.p_wb.x(), 0.5 - 1e-9);
    EXPECT_LE(s.pose.p_wb.x(), 5.5 + 1e-9);
    EXPECT_GE(s.pose.p_wb.z(), 0.09 - 1e-9);
    EXPECT_LE(s.pose.p_wb.z(), 2.0 + 1e-9);
  }
  // Distances shrink by the scale, shapes stay.
  const double d_in = (rec[10].pose.p_wb - rec[60].pose.p_wb).norm();
  const double d_out = (t->samples()[10].pose.p_wb - t->samples()[60].pose.p_wb).norm();
  EXPECT_NEAR(d_out, rep.scale * d_in, 1e-9);

  rec[5].t_s = rec[4].t_s;  // not increasing
  EXPECT_FALSE(fit_into_room(rec, small_scene(), euroc_cam0_rig(), 0.5, nullptr).ok());
}

}  // namespace
}  // namespace ale::render
