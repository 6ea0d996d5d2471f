// The sweeper's simulated wheel odometry: without noise it is the base's truth; with the named
// noise levels the errors have the sizes their figures give; the same seed gives the same output.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "app/tools/lib/render/odometry.h"
#include "render_fixture.h"

namespace ale::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr std::int64_t kStartNs = 1700000000000000000LL;

// Truth at `rate_hz` from a function of seconds giving (x, y, yaw) of the base.
template <typename F>
std::vector<BaseTruth> truth_of(F pose, double duration_s, double rate_hz = 50.0) {
  std::vector<BaseTruth> out;
  const int n = static_cast<int>(std::lround(duration_s * rate_hz)) + 1;
  for (int i = 0; i < n; ++i) {
    const double t = i / rate_hz;
    BaseTruth b = pose(t);
    b.t_ns = kStartNs + std::llround(i * 1e9 / rate_hz);
    out.push_back(b);
  }
  return out;
}

BaseTruth planar(double x, double y, double yaw) {
  BaseTruth b;
  b.x_m = x;
  b.y_m = y;
  b.yaw_rad = yaw;
  return b;
}

std::vector<OdometrySample> run(const std::vector<BaseTruth>& truth, OdometryNoise noise, std::uint64_t seed = 1) {
  OdometrySettings s;
  s.noise = noise;
  s.seed = seed;
  const double duration_s = 1e-9 * static_cast<double>(truth.back().t_ns - truth.front().t_ns);
  Result<std::vector<OdometrySample>> odo = simulate_odometry(truth, s, odometry_errors(s, duration_s));
  EXPECT_TRUE(odo.ok()) << odo.status().to_string();
  return odo.ok() ? *odo : std::vector<OdometrySample>{};
}

// Frames at 30 fps on a continuous drive, as ale-render records them.
std::vector<FrameTime> frames_at_30fps(double duration_s) {
  std::vector<FrameTime> f;
  for (int k = 0; k * (1.0 / 30.0) <= duration_s + 1e-9; ++k) f.push_back({kStartNs + std::llround(k * 1e9 / 30.0), k / 30.0});
  return f;
}

void expect_truth(const std::vector<BaseTruth>& truth, const std::vector<OdometrySample>& odo, double tol) {
  ASSERT_EQ(odo.size(), truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const BaseTruth want = in_frame_of(truth.front(), truth[i]);
    ASSERT_EQ(odo[i].t_ns, truth[i].t_ns);
    ASSERT_NEAR(odo[i].x_m, want.x_m, tol) << "sample " << i;
    ASSERT_NEAR(odo[i].y_m, want.y_m, tol) << "sample " << i;
    ASSERT_NEAR(std::remainder(odo[i].theta_rad - want.yaw_rad, 2.0 * kPi), 0.0, tol) << "sample " << i;
    ASSERT_GT(odo[i].theta_rad, -kPi);
    ASSERT_LE(odo[i].theta_rad, kPi);
  }
}

// The routes' base truth computed here from the body (the camera's optical centre with the base's
// axes, camera_ahead_m ahead of the turning axis), not through T_BC.
std::vector<BaseTruth> route_truth_by_hand(const Trajectory& traj, const DriveOptions& drive, double duration_s) {
  return truth_of([&](double t) {
    const Pose p = traj.at(t);
    const Eigen::Vector3d forward = p.q_wb * Eigen::Vector3d::UnitX();
    return planar(p.p_wb.x() - drive.camera_ahead_m * forward.x(), p.p_wb.y() - drive.camera_ahead_m * forward.y(),
                  std::atan2(forward.y(), forward.x()));
  }, duration_s);
}

TEST(Odometry, WithoutNoiseItIsTheBaseTruthOnEveryRoute) {
  const DriveOptions drive;
  const Rig rig = sweeper_rig(12.0);
  const Eigen::Isometry3d T_BC = sweeper_T_BC(rig, drive);
  constexpr double kDuration = 40.0;
  const Trajectory routes[] = {make_loop(test::small_scene(), drive, kDuration),
                               make_square(test::small_scene(), drive, kDuration),
                               make_lanes(test::small_scene(), drive, LaneOptions{}, kDuration)};
  for (const Trajectory& traj : routes) {
    Result<std::vector<BaseTruth>> truth = sample_base_truth(traj, rig, T_BC, frames_at_30fps(kDuration), 50.0);
    ASSERT_TRUE(truth.ok()) << truth.status().to_string();
    // The samples' times are whole nanoseconds after frames at whole nanoseconds: up to 1 ns off
    // the exact time, 0.3 m/s and 60 deg/s make that < 1e-9 m and rad.
    const std::vector<BaseTruth> by_hand = route_truth_by_hand(traj, drive, kDuration);
    ASSERT_EQ(truth->size(), by_hand.size());
    for (std::size_t i = 0; i < by_hand.size(); ++i) {
      ASSERT_EQ((*truth)[i].t_ns, by_hand[i].t_ns);
      ASSERT_NEAR((*truth)[i].x_m, by_hand[i].x_m, 1e-9);
      ASSERT_NEAR((*truth)[i].y_m, by_hand[i].y_m, 1e-9);
      ASSERT_NEAR(std::remainder((*truth)[i].yaw_rad - by_hand[i].yaw_rad, 2.0 * kPi), 0.0, 1e-9);
      ASSERT_FALSE((*truth)[i].carried);
    }
    const std::vector<OdometrySample> odo = run(*truth, OdometryNoise::kNone);
    expect_truth(*truth, odo, 1e-9);
    // The wheels and the gyro agree with the motion: a turn in place has opposite wheel speeds.
    for (const OdometrySample& o : odo) {
      EXPECT_NEAR(o.v_right_mps - o.v_left_mps, o.gyro_z_rps * 0.23, 1e-6);
      EXPECT_LE(std::abs(0.5 * (o.v_left_mps + o.v_right_mps)), drive.speed_mps + 1e-3);
    }
  }
}

TEST(Odometry, TCameraInBaseIsTheRigOnTheFloor) {
  const DriveOptions drive;
  const Rig rig = sweeper_rig(12.0);
  const Eigen::Isometry3d T_BC = sweeper_T_BC(rig, drive);
  EXPECT_TRUE(T_BC.translation().isApprox(Eigen::Vector3d(0.15, 0.0, 0.09)));
  // The optical axis looks forward and 12 degrees up.
  const Eigen::Vector3d axis = T_BC.linear() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(axis.x(), std::cos(12.0 * kDeg), 1e-12);
  EXPECT_NEAR(axis.z(), std::sin(12.0 * kDeg), 1e-12);
  // The camera of a base at (1, 2, 90 deg) stands 0.15 m along +y from it, 0.09 m up.
  Eigen::Isometry3d T_w_base = Eigen::Isometry3d::Identity();
  T_w_base.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_w_base.translation() = Eigen::Vector3d(1.0, 2.0, 0.0);
  const Eigen::Isometry3d T_wc = T_w_base * T_BC;
  EXPECT_TRUE(T_wc.translation().isApprox(Eigen::Vector3d(1.0, 2.15, 0.09)));
  const BaseTruth back = base_under_camera(T_wc, T_BC);
  EXPECT_NEAR(back.x_m, 1.0, 1e-12);
  EXPECT_NEAR(back.y_m, 2.0, 1e-12);
  EXPECT_NEAR(back.yaw_rad, kPi / 2, 1e-12);
}

TEST(Odometry, NormalStraightDriveIsShortBySlipAndRadiusError) {
  // 3 m along x at 0.3 m/s.
  const std::vector<BaseTruth> truth = truth_of([](double t) { return planar(0.3 * t, 0.0, 0.0); }, 10.0);
  const std::vector<OdometrySample> odo = run(truth, OdometryNoise::kNormal);
  const OdometrySample& end = odo.back();
  const double error = std::hypot(end.x_m - 3.0, end.y_m);
  // 1 % slip, the mean radius error +0.1 %, the gyro's bias turning the drive by ~0.25 deg on average.
  EXPECT_GT(error, 0.005 * 3.0);
  EXPECT_LT(error, 0.02 * 3.0);
  EXPECT_NEAR(end.x_m, 3.0 * 0.99 * 1.001, 0.002);
  EXPECT_GT(end.y_m, 0.0);  // the positive bias turns it left
}

TEST(Odometry, HarshGyroBiasDriftsTheHeading) {
  constexpr double kDuration = 60.0;
  const std::vector<BaseTruth> truth = truth_of([](double t) { return planar(0.3 * t, 0.0, 0.0); }, kDuration);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const std::vector<OdometrySample> odo = run(truth, OdometryNoise::kHarsh, seed);
    // 0.2 deg/s x 60 s = 12 deg; the white noise (0.03 deg/s/sqrt(Hz)) walks ~0.23 deg in 60 s.
    EXPECT_NEAR(std::abs(odo.back().theta_rad) / kDeg, 0.2 * kDuration, 1.0) << "seed " << seed;
    const std::vector<OdometrySample> normal = run(truth, OdometryNoise::kNormal, seed);
    EXPECT_NEAR(normal.back().theta_rad / kDeg, 0.05 * kDuration, 0.5) << "seed " << seed;
  }
}

// Half a second still, 90 degrees left at 60 deg/s, half a second still.
std::vector<BaseTruth> turn_on_the_spot() {
  return truth_of([](double t) {
    const double w = std::clamp((t - 0.5) / 1.5, 0.0, 1.0);
    return planar(1.0, 2.0, 0.3 + w * kPi / 2);
  }, 2.5);
}

TEST(Odometry, TurnOnTheSpotNormal) {
  const std::vector<OdometrySample> odo = run(turn_on_the_spot(), OdometryNoise::kNormal);
  // Gyro scale 0.2 % of 90 deg, bias 0.05 deg/s x 2.5 s, noise ~0.016 deg.
  EXPECT_NEAR(odo.back().theta_rad / kDeg, 90.0, 0.18 + 0.125 + 0.05);
  // The wheels' radius errors differ (+0.5 %, -0.3 %): 0.4 % of each wheel's 0.18 m.
  EXPECT_LT(std::hypot(odo.back().x_m, odo.back().y_m), 0.001);
}

TEST(Odometry, TurnOnTheSpotHarshShowsTheWheelSpin) {
  for (std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    OdometrySettings s;
    s.noise = OdometryNoise::kHarsh;
    s.seed = seed;
    const OdometryErrors e = odometry_errors(s, 2.5);
    ASSERT_TRUE(e.wheel_spin);
    EXPECT_GE(e.wheel_spin_start_s, 0.0);
    EXPECT_LE(e.wheel_spin_start_s + e.wheel_spin_s, 2.5);
    const std::vector<OdometrySample> odo = run(turn_on_the_spot(), OdometryNoise::kHarsh, seed);
    EXPECT_NEAR(odo.back().theta_rad / kDeg, 90.0, 0.18 + 0.2 * 2.5 + 0.15) << "seed " << seed;
    // One wheel's 0.2 m/s for 1 s is 0.1 m of mean travel; radius errors (<= 1 %) and slip (<= 3 %)
    // on the wheels' 0.18 m add at most ~7 mm.
    const double moved = std::hypot(odo.back().x_m, odo.back().y_m);
    EXPECT_GT(moved, 0.05) << "seed " << seed;
    EXPECT_LT(moved, 0.1 + 0.007) << "seed " << seed;
    // Only while the wheel spins does a wheel report more than the turn.
    int spinning = 0;
    for (const OdometrySample& o : odo) spinning += std::abs(o.v_left_mps + o.v_right_mps) > 0.1 ? 1 : 0;
    EXPECT_NEAR(spinning, 50, 1) << "seed " << seed;
  }
}

TEST(Odometry, SameSeedSameOutputOtherSeedOther) {
  const DriveOptions drive;
  const Trajectory traj = make_lanes(test::small_scene(), drive, LaneOptions{}, 30.0);
  const std::vector<BaseTruth> truth = route_truth_by_hand(traj, drive, 30.0);
  for (OdometryNoise noise : {OdometryNoise::kNormal, OdometryNoise::kHarsh}) {
    const std::string a = odometry_csv_text(run(truth, noise, 7));
    EXPECT_EQ(a, odometry_csv_text(run(truth, noise, 7)));
    EXPECT_NE(a, odometry_csv_text(run(truth, noise, 8)));
  }
}

TEST(Odometry, ACarriedStepIsNotSeen) {
  // 1 s along x, then lifted and put down 1 m to the left, 1 s along x again.
  std::vector<BaseTruth> truth = truth_of([](double t) { return planar(0.3 * t + (t > 1.0 ? -0.3 : 0.0), t > 1.0 ? 1.0 : 0.0, 0.0); }, 2.0);
  truth[51].carried = true;
  const std::vector<OdometrySample> odo = run(truth, OdometryNoise::kNone);
  EXPECT_NEAR(odo.back().x_m, 0.3 * 2.0 - 0.006, 1e-9);  // the carried step's 6 mm is lost too
  EXPECT_NEAR(odo.back().y_m, 0.0, 1e-9);
  EXPECT_EQ(odo[51].v_left_mps, 0.0);
}

TEST(Odometry, AKidnapInTheFramesMarksTheStepCarried) {
  const DriveOptions drive;
  const Rig rig = sweeper_rig(12.0);
  const Trajectory traj = make_loop(test::small_scene(), drive, 10.0);
  // Frames at 10 fps: to 1.0 s on the trajectory, then (after a 0.5 s gap) from 5.0 s on.
  std::vector<FrameTime> frames;
  for (int k = 0; k <= 10; ++k) frames.push_back({kStartNs + k * 100000000LL, k * 0.1});
  for (int k = 0; k <= 10; ++k) frames.push_back({kStartNs + 1600000000LL + k * 100000000LL, 5.0 + k * 0.1});
  Result<std::vector<BaseTruth>> truth = sample_base_truth(traj, rig, sweeper_T_BC(rig, drive), frames, 50.0);
  ASSERT_TRUE(truth.ok()) << truth.status().to_string();
  ASSERT_EQ(truth->size(), 131u);  // 2.6 s at 50 Hz
  int carried = 0;
  for (std::size_t i = 0; i < truth->size(); ++i)
    if ((*truth)[i].carried) {
      ++carried;
      EXPECT_EQ(i, 80u);  // the first sample at the frame after the gap
    }
  EXPECT_EQ(carried, 1);
  // Held still at the last frame before the kidnap.
  EXPECT_EQ((*truth)[79].x_m, (*truth)[50].x_m);
}

TEST(Odometry, ClockOffsetShiftsTheTimestamps) {
  const std::vector<BaseTruth> truth = truth_of([](double t) { return planar(0.3 * t, 0.0, 0.0); }, 1.0);
  OdometrySettings s;
  s.noise = OdometryNoise::kNone;
  s.clock_offset_ms = -12.5;
  Result<std::vector<OdometrySample>> odo = simulate_odometry(truth, s, odometry_errors(s, 1.0));
  ASSERT_TRUE(odo.ok());
  EXPECT_EQ((*odo)[3].t_ns, truth[3].t_ns - 12500000);
}

TEST(Odometry, FilesTexts) {
  const std::vector<BaseTruth> truth = truth_of([](double t) { return planar(0.3 * t, 0.0, 0.0); }, 0.04);
  const std::string csv = odometry_csv_text(run(truth, OdometryNoise::kNone));
  EXPECT_EQ(csv,
            "#timestamp [ns],x [m],y [m],theta [rad],gyro_z [rad/s],v_left [m/s],v_right [m/s]\n"
            "1700000000000000000,0,0,0,0,0,0\n"
            "1700000000020000000,0.006,0,0,0,0.3,0.3\n"
            "1700000000040000000,0.012,0,0,0,0.3,0.3\n");
  OdometrySettings s;
  s.noise = OdometryNoise::kHarsh;
  s.seed = 5;
  const std::string yaml = odometry_yaml_text(s, odometry_errors(s, 10.0), sweeper_T_BC(sweeper_rig(0.0), DriveOptions{}), "c");
  EXPECT_EQ(yaml.rfind("sensor_type: odometry\ncomment: c\nrate_hz: 50\nT_BC:\n  cols: 4\n  rows: 4\n"
                       "  data: [0, 0, 1, 0.15, -1, 0, 0, 0, 0, -1, 0, 0.09, 0, 0, 0, 1]\nnoise: harsh\nseed: 5\n", 0),
            0u)
      << yaml;
  EXPECT_NE(yaml.find("gyro_bias_dps: "), std::string::npos);
  EXPECT_NE(yaml.find("wheel_spin: "), std::string::npos);
}

TEST(Odometry, BadInputIsRefused) {
  Result<OdometryNoise> n = parse_odometry_noise("loud");
  ASSERT_FALSE(n.ok());
  EXPECT_NE(n.status().message().find("'loud' is not none, normal or harsh"), std::string::npos);
  EXPECT_TRUE(parse_odometry_noise("harsh").ok());
  OdometrySettings s;
  std::vector<BaseTruth> one(1);
  EXPECT_FALSE(simulate_odometry(one, s, OdometryErrors{}).ok());
  std::vector<BaseTruth> backwards(2);
  backwards[1].t_ns = -5;
  Result<std::vector<OdometrySample>> r = simulate_odometry(backwards, s, OdometryErrors{});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("do not increase"), std::string::npos);
  const Trajectory traj = make_loop(test::small_scene(), DriveOptions{}, 1.0);
  const Rig rig = sweeper_rig(12.0);
  EXPECT_FALSE(sample_base_truth(traj, rig, sweeper_T_BC(rig, DriveOptions{}), frames_at_30fps(1.0), 0.0).ok());
  EXPECT_FALSE(sample_base_truth(traj, rig, sweeper_T_BC(rig, DriveOptions{}), {}, 50.0).ok());
}

}  // namespace
}  // namespace ale::render
