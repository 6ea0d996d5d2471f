#include "app/daemon/pose_frames.h"

#include <Eigen/Geometry>

#include <cmath>

namespace ale::app {
namespace {

Eigen::Quaterniond quat(const std::array<double, 4>& q) { return {q[0], q[1], q[2], q[3]}; }
Eigen::Vector3d vec(const std::array<double, 3>& p) { return {p[0], p[1], p[2]}; }
std::array<double, 4> arr(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }
std::array<double, 3> arr(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

bool tracked(const ale::hal::PoseEstimate& p) { return ale::has_pose(p.state); }

}  // namespace

std::optional<RigidTransform> rigid_from_row_major(const std::array<double, 16>& T) {
  Eigen::Matrix3d R;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R(r, c) = T[static_cast<std::size_t>(4 * r + c)];
  // A calibration's rotation is orthonormal to its printed digits (EuRoC: ~1e-7).
  if (!((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-5) || !(R.determinant() > 0))
    return std::nullopt;
  RigidTransform out;
  out.q = arr(Eigen::Quaterniond(R).normalized());
  out.p = {T[3], T[7], T[11]};
  return out;
}

void apply_body_frame(const std::optional<RigidTransform>& T_bc, ale::hal::PoseEstimate& pose) {
  if (!T_bc) {
    pose.body_valid = false;
    pose.p_bc = {0, 0, 0};
    pose.q_bc = {1, 0, 0, 0};
    pose.p_wb = pose.p_wc;
    pose.q_wb = pose.q_wc;
    return;
  }
  pose.body_valid = true;
  pose.p_bc = T_bc->p;
  pose.q_bc = T_bc->q;
  // T_cb = T_bc^-1: q_cb = q_bc^-1, p_cb = -(q_cb * p_bc); T_wb = T_wc * T_cb.
  const Eigen::Quaterniond q_cb = quat(T_bc->q).conjugate();
  const Eigen::Vector3d p_cb = -(q_cb * vec(T_bc->p));
  const Eigen::Quaterniond q_wc = quat(pose.q_wc);
  pose.q_wb = arr((q_wc * q_cb).normalized());
  pose.p_wb = arr(Eigen::Vector3d(q_wc * p_cb + vec(pose.p_wc)));
}

void apply_motion(const ale::hal::PoseEstimate& previous, ale::hal::PoseEstimate& pose) {
  pose.velocity_w_mps = {0, 0, 0};
  pose.angular_velocity_w_radps = {0, 0, 0};
  const double dt_s = static_cast<double>(pose.timestamp_ns - previous.timestamp_ns) * 1e-9;
  if (!tracked(previous) || !tracked(pose) || previous.map_id != pose.map_id || !(dt_s > 0)) return;
  pose.velocity_w_mps = arr(Eigen::Vector3d((vec(pose.p_wc) - vec(previous.p_wc)) / dt_s));
  // The rotation from the previous orientation to this one, in the map frame: q_wc * q_prev^-1.
  const Eigen::AngleAxisd delta(quat(pose.q_wc) * quat(previous.q_wc).conjugate());
  pose.angular_velocity_w_radps = arr(Eigen::Vector3d(delta.axis() * (delta.angle() / dt_s)));
}

}  // namespace ale::app
