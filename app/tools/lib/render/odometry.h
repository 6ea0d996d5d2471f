// Simulated wheel odometry of a rendered sweeper route, as the sweeper's MCU reports it: the base's
// floor pose (x, y, theta) in the MCU's odometry frame, the gyro's z rate and the wheel speeds.
// Heading is integrated from the gyro (as sweeper MCUs do), position from the wheels' mean travel
// along that heading; both with the error figures of a named noise level (docs/rendering.md).
//
// The base frame sits on the floor under the turning axis: x forward, y left, z up. T_BC is the
// camera in it (p_base = T_BC * p_camera).
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "app/tools/lib/render/trajectory.h"

namespace ale::render {

enum class OdometryNoise { kNone, kNormal, kHarsh };
const char* to_string(OdometryNoise noise);
// "none", "normal" or "harsh"; kInvalidArgument naming the word otherwise.
Result<OdometryNoise> parse_odometry_noise(const std::string& name);

// What ale-render's --odometry-* options set.
struct OdometrySettings {
  OdometryNoise noise = OdometryNoise::kNormal;
  std::uint64_t seed = 1;
  double rate_hz = 50.0;         // 15..200
  double clock_offset_ms = 0.0;  // MCU clock = camera clock + this
  double wheel_base_m = 0.23;    // between the wheels' contact points
};

// The error figures of a run, drawn once from the noise level and the seed.
struct OdometryErrors {
  double radius_error_left = 0.0;   // measured / true travel - 1, per wheel
  double radius_error_right = 0.0;
  double slip = 0.0;                // fraction of the travel lost (the mean when it varies)
  bool slip_varies = false;         // re-drawn per wheel every 2..5 s in 0..slip_max
  double slip_max = 0.0;
  double gyro_bias_dps = 0.0;
  double gyro_noise_dps_rthz = 0.0;  // white noise density
  double gyro_scale_error = 0.0;     // measured / true rate - 1
  // Once per run one wheel spins on the spot: its encoder counts wheel_spin_mps for
  // wheel_spin_s from wheel_spin_start_s (seconds from the first sample) without moving the robot.
  bool wheel_spin = false;
  bool wheel_spin_left = true;
  double wheel_spin_start_s = 0.0;
  double wheel_spin_s = 0.0;
  double wheel_spin_mps = 0.0;
};

// The figures for `settings` over a run of `duration_s` (where the wheel spin falls); all zero for
// kNone.
OdometryErrors odometry_errors(const OdometrySettings& settings, double duration_s);

// The base's true floor pose in the world at one sample time.
struct BaseTruth {
  std::int64_t t_ns = 0;  // on the camera's clock
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
  // The robot was lifted and put down elsewhere since the previous sample (a kidnap): its
  // wheels and gyro saw none of that step's motion.
  bool carried = false;
};

struct OdometrySample {
  std::int64_t t_ns = 0;  // on the MCU's clock
  double x_m = 0.0;       // base pose in the odometry frame (0, 0, 0 at the first sample)
  double y_m = 0.0;
  double theta_rad = 0.0;  // in (-pi, pi]
  double gyro_z_rps = 0.0;  // over the step that ends here (0 at the first sample)
  double v_left_mps = 0.0;
  double v_right_mps = 0.0;
};

// The MCU's reports for the truth samples (at least 2, times increasing). With kNone (all errors
// zero) they are the truth moved to start at (0, 0, 0), except that carried steps are not seen.
// Deterministic: the same inputs give the same samples.
Result<std::vector<OdometrySample>> simulate_odometry(const std::vector<BaseTruth>& truth,
                                                      const OdometrySettings& settings, const OdometryErrors& errors);

// T_BC of the sweeper rig: the body frame is the camera's optical centre with the base's axes,
// `drive` says where that is above and ahead of the turning axis.
Eigen::Isometry3d sweeper_T_BC(const Rig& rig, const DriveOptions& drive);

// The base's floor pose under a world camera pose: T_wc * T_BC^-1, projected on the floor.
BaseTruth base_under_camera(const Eigen::Isometry3d& T_wc, const Eigen::Isometry3d& T_BC);

// One rendered frame: its time on the camera clock and on the trajectory.
struct FrameTime {
  std::int64_t clock_ns = 0;
  double t_s = 0.0;
};

// The base's truth at rate_hz on the camera clock from the first frame to the last: between two
// frames of the same drive the trajectory time advances with the clock; across a kidnap (where it
// does not) the robot stays at the earlier frame's place until the later frame, and the step that
// puts it down is `carried`. `frames` in order, at least 2.
Result<std::vector<BaseTruth>> sample_base_truth(const Trajectory& trajectory, const Rig& rig,
                                                 const Eigen::Isometry3d& T_BC, const std::vector<FrameTime>& frames,
                                                 double rate_hz);

// `b` in the base frame of `origin` (yaw in (-pi, pi]): with origin the first sample, where the
// odometry should be.
BaseTruth in_frame_of(const BaseTruth& origin, const BaseTruth& b);

// <out>/mav0/odometry0/data.csv and sensor.yaml texts.
std::string odometry_csv_text(const std::vector<OdometrySample>& samples);
std::string odometry_yaml_text(const OdometrySettings& settings, const OdometryErrors& errors,
                               const Eigen::Isometry3d& T_BC, const std::string& comment);

}  // namespace ale::render
