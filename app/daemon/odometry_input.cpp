#include "app/daemon/odometry_input.h"

#include <cmath>

#include "app/daemon/pose_frames.h"

namespace ale::app {
namespace {

std::optional<ale::geometry::SE3> se3_of(const std::array<double, 16>& m) {
  const std::optional<RigidTransform> r = rigid_from_row_major(m);
  if (!r) return std::nullopt;
  const Eigen::Quaterniond q(r->q[0], r->q[1], r->q[2], r->q[3]);
  return ale::geometry::SE3(ale::geometry::SO3(q), ale::geometry::Vec3(r->p[0], r->p[1], r->p[2]));
}

}  // namespace

std::vector<ale::slam::OdometrySample> odometry_samples(const ale::replay::OdometryTrack& track) {
  std::vector<ale::slam::OdometrySample> out;
  out.reserve(track.rows.size());
  for (std::size_t i = 0; i < track.rows.size(); ++i) {
    const ale::replay::OdometryRow& r = track.rows[i];
    ale::slam::OdometrySample s;
    s.t_ns = r.timestamp_ns;
    s.sequence = static_cast<std::uint32_t>(i);
    s.x_m = r.x_m;
    s.y_m = r.y_m;
    s.theta_rad = r.theta_rad;
    s.has_gyro = r.has_gyro;
    s.gyro_z_rps = r.gyro_z_rps;
    s.has_wheels = r.has_wheels;
    s.v_left_mps = r.v_left_mps;
    s.v_right_mps = r.v_right_mps;
    out.push_back(s);
  }
  return out;
}

ale::replay::OdometryRow odometry_row(const ale::slam::OdometrySample& s) {
  ale::replay::OdometryRow r;
  r.timestamp_ns = s.t_ns;
  r.x_m = s.x_m;
  r.y_m = s.y_m;
  r.theta_rad = s.theta_rad;
  r.has_gyro = s.has_gyro;
  r.gyro_z_rps = s.gyro_z_rps;
  r.has_wheels = s.has_wheels;
  r.v_left_mps = s.v_left_mps;
  r.v_right_mps = s.v_right_mps;
  return r;
}

Status resolve_odometry(DaemonConfig& config, const std::optional<ale::replay::OdometryTrack>& track,
                        OdometryPlan& plan) {
  plan = OdometryPlan{};
  const OdometryConfig& o = config.odometry;
  ale::slam::OdometryParams& params = config.slam.odometry;
  // The camera's mounting is the robot's, odometry or not (the floor's scale cue needs it too).
  Result<std::optional<std::array<double, 16>>> configured = parse_T_bc(o.T_bc);
  if (!configured.ok()) return configured.status();  // validate_config has said so already
  std::string T_bc_from;
  std::optional<std::array<double, 16>> T_bc;
  if (*configured) {
    params.T_bc = *se3_of(**configured);  // parse_T_bc checked it is rigid
    T_bc = *configured;
    T_bc_from = "odometry.T_bc";
  } else if (track && track->T_BC) {
    const std::optional<ale::geometry::SE3> T = se3_of(*track->T_BC);
    if (!T)
      return invalid_argument(track->sensor_yaml +
                              ": T_BC is not a rigid transform (its rotation block is not a rotation)");
    params.T_bc = *T;
    T_bc = track->T_BC;
    T_bc_from = track->sensor_yaml;
  }
  if (!o.enabled) {
    plan.note = "odometry off (odometry.enabled = false)" + (T_bc_from.empty() ? std::string() : ", T_bc from " + T_bc_from);
    return {};
  }
  params.clock_offset_ns = static_cast<std::int64_t>(std::llround(o.clock_offset_ms * 1e6));
  if (track && !track->rows.empty()) {
    if (T_bc_from.empty())
      return invalid_argument(track->sensor_yaml +
                              ": no T_BC (the camera in the base frame) for the dataset's odometry; add it, set "
                              "odometry.T_bc, or turn odometry off (--no-odometry)");
    plan.replay = odometry_samples(*track);
    plan.T_bc = T_bc;
    plan.rate_hz = track->rate_hz;
    plan.note = "odometry: " + std::to_string(plan.replay.size()) + " samples from " + track->list_file +
                ", T_bc from " + T_bc_from;
    return {};
  }
  if (o.channel.empty()) {
    plan.note = "odometry: no source (no samples in the dataset, odometry.channel empty)";
  } else if (T_bc_from.empty()) {
    plan.note = "odometry: not read from LCM channel " + o.channel + ": odometry.T_bc is not set";
  } else {
    plan.lcm_channel = o.channel;
    plan.T_bc = T_bc;
    plan.note = "odometry: ale_lcm.odometry_t on " + o.channel + ", T_bc from " + T_bc_from;
  }
  return {};
}

std::vector<ale::slam::OdometrySample> ReplayOdometry::due(std::int64_t frame_t_ns) {
  std::vector<ale::slam::OdometrySample> out;
  while (next_ < samples_.size() && samples_[next_].t_ns + clock_offset_ns_ <= frame_t_ns + lookahead_ns_)
    out.push_back(samples_[next_++]);
  return out;
}

}  // namespace ale::app
