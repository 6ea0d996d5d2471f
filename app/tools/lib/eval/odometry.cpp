#include "app/tools/lib/eval/odometry.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>

namespace ale::eval {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct BasePose {
  double x = 0.0, y = 0.0, theta = 0.0;
};

Eigen::Isometry3d base_transform(const BasePose& b) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(b.theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(b.x, b.y, 0.0);
  return T;
}

// The row-major 4x4 as a rigid transform, or an error when its rotation block is not a rotation
// (1e-6) or its last row is not 0 0 0 1.
Result<Eigen::Isometry3d> rigid(const std::array<double, 16>& m, const std::string& name) {
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = m[static_cast<std::size_t>(4 * r + c)];
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  const bool finite = M.allFinite();
  if (!finite || (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0.0 ||
      (M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9)
    return invalid_argument(name + ": T_BC is not a rigid transform (rotation block not a rotation, or last row "
                                   "not 0 0 0 1)");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = M.topRightCorner<3, 1>();
  return T;
}

StampedPose camera_pose(std::int64_t t_ns, const BasePose& b, const Eigen::Isometry3d& T_BC) {
  const Eigen::Isometry3d T_wc = base_transform(b) * T_BC;
  StampedPose p;
  p.t_s = 1e-9 * static_cast<double>(t_ns);
  p.R_wb = T_wc.linear();
  p.p_wb = T_wc.translation();
  return p;
}

}  // namespace

Result<Trajectory> odometry_camera_trajectory(const replay::OdometryTrack& track,
                                              const std::vector<std::int64_t>& at_ns) {
  if (!track.T_BC)
    return invalid_argument(track.sensor_yaml + ": no T_BC (the camera in the base frame): the odometry cannot be "
                                                "turned into the camera's trajectory");
  Result<Eigen::Isometry3d> T_BC = rigid(*track.T_BC, track.sensor_yaml);
  if (!T_BC.ok()) return T_BC.status();
  std::vector<BasePose> base;
  base.reserve(track.rows.size());
  for (std::size_t i = 0; i < track.rows.size(); ++i) {
    const replay::OdometryRow& r = track.rows[i];
    if (!std::isfinite(r.x_m) || !std::isfinite(r.y_m) || !std::isfinite(r.theta_rad))
      return invalid_argument(track.list_file + ": row " + std::to_string(i + 1) +
                              " (after the header): x, y or theta is not a finite number");
    base.push_back({r.x_m, r.y_m, r.theta_rad});
  }
  Trajectory out;
  out.name = track.list_file;
  out.format = TrajectoryFormat::kTum;
  if (at_ns.empty()) {
    for (std::size_t i = 0; i < base.size(); ++i)
      out.poses.push_back(camera_pose(track.rows[i].timestamp_ns, base[i], *T_BC));
  } else {
    std::size_t k = 0;  // rows[k] <= t < rows[k + 1]
    for (const std::int64_t t : at_ns) {
      if (t < track.rows.front().timestamp_ns || t > track.rows.back().timestamp_ns) continue;
      while (k + 1 < track.rows.size() && track.rows[k + 1].timestamp_ns <= t) ++k;
      BasePose b = base[k];
      if (k + 1 < track.rows.size() && t > track.rows[k].timestamp_ns) {
        const double a = static_cast<double>(t - track.rows[k].timestamp_ns) /
                         static_cast<double>(track.rows[k + 1].timestamp_ns - track.rows[k].timestamp_ns);
        const BasePose& n = base[k + 1];
        const double dtheta = std::remainder(n.theta - b.theta, 2.0 * kPi);
        b = {b.x + a * (n.x - b.x), b.y + a * (n.y - b.y), b.theta + a * dtheta};
      }
      if (!out.poses.empty() && 1e-9 * static_cast<double>(t) <= out.poses.back().t_s) continue;
      out.poses.push_back(camera_pose(t, b, *T_BC));
    }
  }
  if (out.poses.empty())
    return invalid_argument(track.list_file + ": no odometry row within the times asked for");
  return out;
}

std::string tum_text(const Trajectory& trajectory, const std::string& comment) {
  std::string text = "# " + comment + "\n# t tx ty tz qx qy qz qw\n";
  char line[256];
  for (const StampedPose& p : trajectory.poses) {
    const Eigen::Quaterniond q(p.R_wb);
    std::snprintf(line, sizeof line, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", p.t_s, p.p_wb.x(), p.p_wb.y(),
                  p.p_wb.z(), q.x(), q.y(), q.z(), q.w());
    text += line;
  }
  return text;
}

}  // namespace ale::eval
