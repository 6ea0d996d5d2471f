#include "app/daemon/trajectory_file.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>

namespace ale::app {
namespace {

constexpr const char* kHeader = "# timestamp tx ty tz qx qy qz qw (camera in the map frame, TUM)\n";

}  // namespace

Status TrajectoryFile::open(const std::string& path, bool final_poses) {
  any_ = false;
  segment_ = 0;
  lines_.clear();
  path_ = path;
  final_poses_ = final_poses;
  ALE_RETURN_IF_ERROR(file_.open(path, "trajectory"));
  return file_.write(kHeader);
}

Status TrajectoryFile::write_line(TextFileWriter& file, const Line& l, bool new_segment) {
  char line[256];
  int used = 0;
  if (new_segment) used = std::snprintf(line, sizeof line, "# map %" PRIu32 "\n", l.map_id);
  const std::int64_t t = l.timestamp_ns;
  used += std::snprintf(line + used, sizeof line - static_cast<std::size_t>(used),
                        "%" PRId64 ".%09" PRId64 " %.6f %.6f %.6f %.7f %.7f %.7f %.7f\n", t / 1000000000,
                        t % 1000000000, l.p[0], l.p[1], l.p[2], l.q[1], l.q[2], l.q[3], l.q[0]);
  return file.write(line, static_cast<std::size_t>(used));
}

Status TrajectoryFile::append(const FrameRecord& r) {
  // online poses include the odometry's where the camera did not track; final ones are the
  // SLAM's alone (what the camera tracked)
  if (r.pose.odometry_only && final_poses_) return {};
  if (!file_.is_open() || !(has_pose(r.pose.state) || r.pose.odometry_only)) return {};
  const auto map_id = static_cast<std::uint32_t>(r.pose.map_id);
  const Line l{r.pose.frame_sequence, r.pose.timestamp_ns, map_id, segment_, r.pose.p_wc, r.pose.q_wc};
  const bool new_segment = !any_ || map_id != map_id_;
  map_id_ = map_id;
  any_ = true;
  if (final_poses_) lines_.push_back(l);
  return write_line(file_, l, new_segment);
}

Status TrajectoryFile::finish(const ale::slam::RefinedTrajectory* refined) {
  const bool was_open = file_.is_open();
  ALE_RETURN_IF_ERROR(file_.close());
  if (!was_open || !final_poses_ || refined == nullptr) return {};
  // Both lists are in processing order and every line's frame is in `refined`.
  const std::vector<ale::slam::TrajectoryPose>& poses = refined->poses();
  std::size_t r = 0;
  for (Line& l : lines_) {
    const double t = static_cast<double>(l.timestamp_ns) * 1e-9;
    while (r < poses.size() && !(poses[r].sequence == l.sequence && std::abs(poses[r].timestamp_s - t) < 1e-6)) ++r;
    if (r == poses.size()) break;
    const ale::slam::TrajectoryPose& f = poses[r++];
    if (!f.refined) continue;
    const ale::geometry::SE3 T_wc = f.T_cw.inverse();
    const Eigen::Vector3d p = T_wc.translation();
    const Eigen::Quaterniond& q = T_wc.so3().quaternion();
    if (!p.allFinite() || !q.coeffs().allFinite()) continue;
    l.p = {p.x(), p.y(), p.z()};
    l.q = {q.w(), q.x(), q.y(), q.z()};
    l.map_id = f.map_id;  // a map merged since into an older one: that map's segment
  }
  TextFileWriter out;
  const std::string tmp = path_ + ".tmp";
  Status s = out.open(tmp, "trajectory (final poses)");
  if (s.ok()) s = out.write(kHeader);
  for (std::size_t i = 0; i < lines_.size() && s.ok(); ++i) {
    s = write_line(out, lines_[i],
                   i == 0 || lines_[i].map_id != lines_[i - 1].map_id || lines_[i].segment != lines_[i - 1].segment);
  }
  const Status closed = out.close();
  if (s.ok()) s = closed;
  if (s.ok() && std::rename(tmp.c_str(), path_.c_str()) != 0) {
    s = io_error("trajectory " + path_ + ": cannot replace it with " + tmp);
  }
  if (!s.ok()) {
    std::remove(tmp.c_str());
    return Status(s.code(), s.message() + " (the online poses are kept)");
  }
  lines_.clear();
  return {};
}

}  // namespace ale::app
