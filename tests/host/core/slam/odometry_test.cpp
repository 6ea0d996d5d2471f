// The odometry buffer: interpolation at camera times, the camera's motion through its mounting,
// and every kind of bad sample refused and counted without disturbing what is kept.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/slam/odometry.h"

namespace ale::slam {
namespace {

constexpr double kPi = 3.14159265358979323846;

OdometrySample at(std::int64_t t_ms, double x, double y, double theta, std::uint32_t seq = 0) {
  OdometrySample s;
  s.t_ns = t_ms * 1000000;
  s.sequence = seq;
  s.x_m = x;
  s.y_m = y;
  s.theta_rad = theta;
  return s;
}

TEST(OdometryBuffer, InterpolatesBetweenSamplesAndAcrossTheAngleWrap) {
  OdometryBuffer buffer(OdometryParams{});
  ASSERT_TRUE(buffer.add(at(0, 0.0, 0.0, kPi - 0.05, 1)).ok());
  ASSERT_TRUE(buffer.add(at(20, 0.004, 0.002, -kPi + 0.05, 2)).ok());
  const auto mid = buffer.at(10 * 1000000);
  ASSERT_TRUE(mid.has_value());
  EXPECT_NEAR(mid->x_m, 0.002, 1e-12);
  EXPECT_NEAR(mid->y_m, 0.001, 1e-12);
  // Half way from pi - 0.05 to -pi + 0.05 the short way is pi, not 0.
  EXPECT_NEAR(std::abs(std::remainder(mid->theta_rad, 2 * kPi)), kPi, 1e-9);
  EXPECT_FALSE(buffer.at(-1).has_value());                     // before the first sample
  EXPECT_TRUE(buffer.at(60 * 1000000).has_value());            // 40 ms past the last: extrapolated
  EXPECT_FALSE(buffer.at(200 * 1000000).has_value());          // 180 ms past it: unknown
}

TEST(OdometryBuffer, ClockOffsetShiftsTheCameraTime) {
  OdometryParams p;
  p.clock_offset_ns = 5 * 1000000;  // the camera's clock is 5 ms ahead of the MCU's
  OdometryBuffer buffer(p);
  ASSERT_TRUE(buffer.add(at(0, 0.0, 0.0, 0.0)).ok());
  ASSERT_TRUE(buffer.add(at(10, 0.01, 0.0, 0.0, 1)).ok());
  EXPECT_NEAR(buffer.at(10 * 1000000)->x_m, 0.005, 1e-12);
}

TEST(OdometryBuffer, CameraMotionFollowsTheMountingOnATurnOnTheSpot) {
  OdometryParams p;
  // A camera looking forward (z along the base's x), 15 cm ahead of the axis and 9 cm up.
  geometry::Mat3 R_bc;
  R_bc << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  p.T_bc = geometry::SE3(geometry::SO3::from_matrix(R_bc), geometry::Vec3(0.15, 0.0, 0.09));
  OdometryBuffer buffer(p);
  ASSERT_TRUE(buffer.add(at(0, 1.0, 2.0, 0.3)).ok());
  ASSERT_TRUE(buffer.add(at(200, 1.0, 2.0, 0.3 + kPi / 2, 1)).ok());  // 90 degrees on the spot
  const auto T_c2c1 = buffer.camera_motion(0, 200 * 1000000);
  ASSERT_TRUE(T_c2c1.has_value());
  // The camera centre swings on its 15 cm arm: from (0.15, 0) to (0, 0.15) in the first base frame,
  // sqrt(2) * 0.15 apart; the camera turns 90 degrees about its own -y (the base's z).
  const geometry::SE3 T_c1c2 = T_c2c1->inverse();
  EXPECT_NEAR(T_c1c2.translation().norm(), std::sqrt(2.0) * 0.15, 1e-9);
  EXPECT_NEAR(T_c1c2.so3().log().norm(), kPi / 2, 1e-9);
  EXPECT_NEAR(T_c1c2.so3().log().y(), -kPi / 2, 1e-9);
  // In the first camera's frame the second centre is 15 cm to the left (-x) and 15 cm back (-z).
  EXPECT_NEAR(T_c1c2.translation().x(), -0.15, 1e-9);
  EXPECT_NEAR(T_c1c2.translation().z(), -0.15, 1e-9);
}

TEST(OdometryBuffer, RefusesAndCountsBadSamplesWithoutChangingWhatItKeeps) {
  OdometryBuffer buffer(OdometryParams{});
  ASSERT_TRUE(buffer.add(at(0, 0.0, 0.0, 0.0, 1)).ok());
  ASSERT_TRUE(buffer.add(at(20, 0.006, 0.0, 0.0, 2)).ok());
  OdometrySample nan = at(40, std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0, 3);
  const Status s_nan = buffer.add(nan);
  EXPECT_EQ(s_nan.code(), StatusCode::kFrameRejected);
  EXPECT_NE(s_nan.message().find("not finite"), std::string::npos);
  EXPECT_EQ(buffer.add(at(20, 0.006, 0.0, 0.0, 3)).code(), StatusCode::kFrameRejected);  // same time
  EXPECT_EQ(buffer.add(at(10, 0.003, 0.0, 0.0, 3)).code(), StatusCode::kFrameRejected);  // backwards
  EXPECT_EQ(buffer.add(at(40, 5.0, 0.0, 0.0, 3)).code(), StatusCode::kFrameRejected);    // 5 m in 20 ms
  EXPECT_EQ(buffer.add(at(40, 0.012, 0.0, 2.0, 3)).code(), StatusCode::kFrameRejected);  // 2 rad in 20 ms
  EXPECT_EQ(buffer.counters().not_finite, 1u);
  EXPECT_EQ(buffer.counters().not_increasing, 2u);
  EXPECT_EQ(buffer.counters().jumps, 2u);
  EXPECT_EQ(buffer.size(), 2u);
  EXPECT_NEAR(buffer.at(10 * 1000000)->x_m, 0.003, 1e-12);
  // A good sample after the refusals is taken, and the next ones are judged from it.
  ASSERT_TRUE(buffer.add(at(40, 0.012, 0.0, 0.0, 4)).ok());
  EXPECT_EQ(buffer.size(), 3u);
}

TEST(OdometryBuffer, AStreamThatStaysAtItsNewPlaceHasRestarted) {
  OdometryParams p;
  p.jump_restart = 3;
  OdometryBuffer buffer(p);
  ASSERT_TRUE(buffer.add(at(0, 0.0, 0.0, 0.0, 1)).ok());
  ASSERT_TRUE(buffer.add(at(20, 0.006, 0.0, 0.0, 2)).ok());
  // The MCU reset its odometry frame: every sample from now on is 3 m away from the last kept.
  EXPECT_FALSE(buffer.add(at(40, 3.0, 0.0, 0.0, 3)).ok());
  EXPECT_FALSE(buffer.add(at(60, 3.006, 0.0, 0.0, 4)).ok());
  EXPECT_TRUE(buffer.add(at(80, 3.012, 0.0, 0.0, 5)).ok());
  EXPECT_EQ(buffer.counters().restarts, 1u);
  EXPECT_EQ(buffer.size(), 1u);
  EXPECT_FALSE(buffer.at(20 * 1000000).has_value());  // nothing before the restart is kept
}

TEST(OdometryBuffer, DoesNotInterpolateAcrossAGapAndCountsLostReports) {
  OdometryBuffer buffer(OdometryParams{});
  ASSERT_TRUE(buffer.add(at(0, 0.0, 0.0, 0.0, 1)).ok());
  ASSERT_TRUE(buffer.add(at(500, 0.1, 0.0, 0.0, 9)).ok());  // 0.5 s later, 7 reports lost
  EXPECT_EQ(buffer.counters().gaps, 1u);
  EXPECT_EQ(buffer.counters().lost_reports, 7u);
  EXPECT_FALSE(buffer.at(250 * 1000000).has_value());
  EXPECT_TRUE(buffer.at(500 * 1000000).has_value());
}

TEST(OdometryBuffer, KeepsOnlyItsCapacity) {
  OdometryParams p;
  p.capacity = 4;
  OdometryBuffer buffer(p);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(buffer.add(at(i * 20, 0.005 * i, 0.0, 0.0, i)).ok());
  EXPECT_EQ(buffer.size(), 4u);
  EXPECT_FALSE(buffer.at(100 * 1000000).has_value());
  EXPECT_NEAR(buffer.at(150 * 1000000)->x_m, 0.0375, 1e-12);
}

TEST(OdometryParams, ValidateNamesTheField) {
  OdometryParams p;
  p.max_gap_s = 0.0;
  const Status s = validate(p);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("max_gap_s"), std::string::npos);
  EXPECT_TRUE(validate(OdometryParams{}).ok());
}


// The gyro's bias against the camera's heading: frames at 15 fps, the camera's turn with a
// deterministic noise of +-0.05 deg a frame (about what tracking gives), the odometry's the true
// turn plus bias x dt. 0.2 deg/s (`harsh`) is found to within 10 % once evident; no bias gives 0
// (the mean within three standard errors); frames that turn, or that few inliers tracked, or z 0,
// leave it at 0.
TEST(GyroBias, FindsAnEvidentBiasOnStraightFramesOnly) {
  constexpr double kDt = 1.0 / 15.0, kDeg = 3.14159265358979323846 / 180.0;
  auto run = [&](const OdometryParams& params, double bias_dps, double turn_dps, int inliers, int frames) {
    GyroBias g(params);
    for (int i = 0; i < frames; ++i) {
      const double noise = 0.05 * kDeg * std::sin(1.7 * i) * ((i % 3) - 1.0);
      const double truth = turn_dps * kDeg * kDt;
      g.add(truth + bias_dps * kDeg * kDt, truth + noise, kDt, inliers);
    }
    return g.rate_rps() / kDeg;
  };
  const OdometryParams params;
  EXPECT_NEAR(run(params, 0.2, 0.0, 200, 900), 0.2, 0.02);
  EXPECT_NEAR(run(params, -0.2, 0.0, 200, 900), -0.2, 0.02);
  EXPECT_EQ(run(params, 0.0, 0.0, 200, 900), 0.0);
  EXPECT_EQ(run(params, 0.2, 0.0, 200, GyroBias::kMinFrames - 1), 0.0) << "too few frames yet";
  EXPECT_EQ(run(params, 0.2, 30.0, 200, 900), 0.0) << "turning: the gyro's scale error is in it";
  EXPECT_EQ(run(params, 0.2, 0.0, GyroBias::kMinInliers - 1, 900), 0.0) << "the camera's heading too uncertain";
  OdometryParams off = params;
  off.gyro_bias_z = 0.0;
  EXPECT_EQ(run(off, 0.2, 0.0, 200, 900), 0.0);
  OdometryParams bad = params;
  bad.gyro_bias_window_s = 0.0;
  EXPECT_FALSE(validate(bad).ok());
}

}  // namespace
}  // namespace ale::slam
