// Wheel odometry and the gyro as the sweeper's MCU reports them: the base's pose on the floor
// (x, y, theta) in the MCU's odometry frame, at any rate (15 Hz and up). The OdometryBuffer keeps
// the last samples in a fixed ring, checks each one as it arrives (a value that is not finite, a
// time that does not increase, a step faster than the robot can move) and interpolates the base
// pose at a camera time; camera_motion() turns the base's motion between two camera times into
// the camera's, through the camera's mounting T_bc. Metres and radians throughout.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/base/config_table.h"
#include "core/base/status.h"
#include "core/geometry/lie.h"
#include "core/map/map_store.h"

namespace ale::slam {

// One report of the MCU. The base frame sits on the floor under the turning axis: x forward,
// y left, z up; theta turns about z, anticlockwise seen from above.
struct OdometrySample {
  std::int64_t t_ns = 0;          // the MCU's clock
  std::uint32_t sequence = 0;     // the MCU's counter (gaps are lost reports)
  double x_m = 0.0, y_m = 0.0, theta_rad = 0.0;
  bool has_gyro = false;
  double gyro_z_rps = 0.0;        // turn rate about z, when has_gyro
  bool has_wheels = false;
  double v_left_mps = 0.0, v_right_mps = 0.0;  // wheel speeds, when has_wheels
};

struct BasePose2;

struct OdometryParams {
  // camera time = MCU time + clock_offset_ns (both in nanoseconds).
  std::int64_t clock_offset_ns = 0;
  // Samples kept: 512 is 10 s at 50 Hz, 5 s at 100 Hz; the tracker needs only the last frame's.
  int capacity = 512;
  // No interpolation between samples further apart than this: the robot may have done anything.
  double max_gap_s = 0.25;
  // A frame up to this much newer than the last sample is extrapolated from the last two (the
  // MCU's reports lag the camera by a few milliseconds on the robot).
  double max_extrapolation_s = 0.1;
  // A step faster than these is a jump (an encoder glitch, a reset of the MCU's frame): refused.
  // After jump_restart refusals in a row the stream is taken to have restarted from its new
  // value: the samples kept are dropped and counted as a restart.
  double max_speed_mps = 2.0;
  double max_turn_rate_rps = 12.0;
  int jump_restart = 3;
  // The camera in the base frame (EuRoC's T_BS convention: p_base = T_bc * p_camera).
  geometry::SE3 T_bc;
  // How the SLAM uses it. The map is put in metres at initialisation when the odometry moved the
  // camera at least min_init_baseline_m between the two frames (a shorter baseline gives a poor
  // ratio); from then on each frame's pose starts from the odometry's motion since the last
  // tracked frame, and its camera centre is held there by a prior of sigma
  // prior_sigma_m + prior_sigma_fraction x the odometry's step (wheel slip and radius errors).
  double min_init_baseline_m = 0.02;
  double prior_sigma_m = 0.002;
  double prior_sigma_fraction = 0.03;
  // The local BA holds each keyframe's centre to the odometry from the latest earlier keyframe of
  // its window when they are at most this far apart in time (the odometry's drift grows with it).
  // 30 s, not less: in the dark or before a bare wall the camera may track for several seconds
  // without making a keyframe (6.7 s on a dark lane render), and the first keyframe after such a
  // stretch, with no prior, slid 0.68 m along its optical axis in its first local BA, taking the
  // keyframes after it along (docs/slam.md).
  double keyframe_prior_max_span_s = 30.0;
  // A frame the camera cannot track in a metric map (too few features or inliers: a bare wall, the
  // lights off) is posed where the odometry's motion since the last posed frame puts it, and
  // tracking goes on from that pose, for at most coast_s after the last frame the camera tracked;
  // then tracking is lost (relocalisation, a new map after SlamParams::lost_timeout_s, placed where
  // the odometry puts the camera in the lost map's frame). The odometry drifts 1-3 cm in that time
  // (1.5 m at 0.3 m/s); 2 s lost more dark lane routes to relocalisations (docs/evaluation.md).
  // 0: lost at once.
  double coast_s = 5.0;
  // ... and each free keyframe's rotation to the odometry's turn from that keyframe (the base turns
  // about the floor's normal only): sigma rotation_prior_sigma_deg + rotation_prior_sigma_fraction
  // x the turn; 0: no rotation prior.
  double rotation_prior_sigma_deg = 0.2;
  double rotation_prior_sigma_fraction = 0.02;
  // The gyro's bias in the odometry's heading, estimated against the camera's: on frames the
  // camera tracked with at least GyroBias::kMinInliers inliers while the odometry turned slower than
  // GyroBias::kStraightRps (driving straight: no gyro scale error in it), the odometry's turn minus
  // the camera's, averaged over about gyro_bias_window_s. It is taken off the rotation prior's
  // target once its mean differs from zero by gyro_bias_z standard errors (with `normal` odometry,
  // 0.05 deg/s, seldom: the prior's target is left as it is; with 0.2 deg/s, within a minute).
  // 0: never.
  double gyro_bias_window_s = 60.0;
  double gyro_bias_z = 3.0;
  // The priors' sigma for an odometry step of step_m metres.
  double prior_sigma(double step_m) const;
  // The rotation prior's sigma (radians) for the base's turn from a to b.
  double rotation_prior_sigma(const BasePose2& a, const BasePose2& b) const;
};
// kInvalidArgument naming the first field out of range.
Status validate(const OdometryParams& p);

// OdometryParams::gyro_bias_*: the bias of the odometry's heading against the camera's.
class GyroBias {
 public:
  static constexpr int kMinInliers = 80;
  static constexpr double kStraightRps = 0.075;  // 4.3 deg/s
  static constexpr int kMinFrames = 30;

  explicit GyroBias(const OdometryParams& params) : params_(params) {}
  // One tracked frame dt_s after the last: the odometry's and the camera's turns about the floor's
  // normal over it (radians, counter-clockwise seen from above).
  void add(double odometry_turn_rad, double camera_turn_rad, double dt_s, int inliers);
  // The bias to take off the odometry's heading change, rad/s (0 until it is evident).
  double rate_rps() const { return rate_rps_; }

 private:
  OdometryParams params_;
  double sum_ = 0.0, sum_sq_ = 0.0, frames_ = 0.0, time_s_ = 0.0;  // exponentially forgotten
  double rate_rps_ = 0.0;
};
// The buffer's checks as keys (core/base/config_table.h; the daemon's `slam.odometry.*`). The
// clock offset and T_bc are the deployment's (the daemon's `odometry.*`), not in the table.
extern const ConfigTable kOdometryConfig;

struct BasePose2 {
  double x_m = 0.0, y_m = 0.0, theta_rad = 0.0;
};

// What the buffer did with the samples it was given, since start.
struct OdometryCounters {
  std::uint64_t accepted = 0;
  std::uint64_t not_finite = 0;     // refused: NaN or infinite value
  std::uint64_t not_increasing = 0; // refused: a time at or before the last sample's
  std::uint64_t jumps = 0;          // refused: faster than max_speed_mps / max_turn_rate_rps
  std::uint64_t restarts = 0;       // the stream restarted after jump_restart jumps in a row
  std::uint64_t gaps = 0;           // accepted after more than max_gap_s without a sample
  std::uint64_t lost_reports = 0;   // sequence numbers skipped
  std::uint64_t refused() const { return not_finite + not_increasing + jumps; }
};

class OdometryBuffer {
 public:
  explicit OdometryBuffer(const OdometryParams& params);

  // Checks and keeps one sample. kFrameRejected naming the problem when it is refused (and
  // counted); the samples kept are then unchanged.
  Status add(const OdometrySample& sample);
  // The base pose at a camera time, interpolated between the samples around it (or extrapolated
  // up to max_extrapolation_s past the last); nullopt outside the samples kept or across a gap.
  std::optional<BasePose2> at(std::int64_t camera_t_ns) const;
  // The camera's motion between two camera times, T_c2_c1 (p_c2 = T * p_c1), translation in
  // metres; nullopt unless the base pose is known at both times.
  std::optional<geometry::SE3> camera_motion(std::int64_t t1_ns, std::int64_t t2_ns) const;
  // The same for the base: T_b1_b2 (the pose of b2 in b1).
  std::optional<geometry::SE3> base_motion(std::int64_t t1_ns, std::int64_t t2_ns) const;

  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  const OdometryCounters& counters() const { return counters_; }
  const OdometryParams& params() const { return params_; }
  void clear();

 private:
  const OdometrySample& sample(std::size_t i) const;  // i-th oldest kept
  bool is_jump(const OdometrySample& last, const OdometrySample& next) const;

  OdometryParams params_;
  std::vector<OdometrySample> ring_;
  std::size_t head_ = 0;  // where the oldest sample is
  std::size_t size_ = 0;
  int jumps_in_row_ = 0;
  OdometryCounters counters_;
};

// The base's planar pose as a 3-D transform (rotation about z, on the floor plane).
geometry::SE3 base_pose_se3(const BasePose2& pose);
// b's pose in a's base frame, T_ab (relative to a directly, not through the odometry frame's
// origin, far away after a long run).
geometry::SE3 base_between(const BasePose2& a, const BasePose2& b);
// The camera at b in the camera at a, T_ca_cb (p_ca = T * p_cb), for the mounting T_bc.
geometry::SE3 camera_between(const geometry::SE3& T_bc, const BasePose2& a, const BasePose2& b);
// a - b wrapped to (-pi, pi], radians.
double angle_difference(double a, double b);
// The base pose a keyframe stored (map::Keyframe::odometry_*; meaningful when has_odometry).
BasePose2 keyframe_odometry(const map::Keyframe& k);

}  // namespace ale::slam
