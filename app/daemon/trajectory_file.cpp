#include "app/daemon/trajectory_file.h"

#include <cinttypes>
#include <cstdio>

namespace ale::app {

Status TrajectoryFile::open(const std::string& path) {
  any_ = false;
  ALE_RETURN_IF_ERROR(file_.open(path, "trajectory"));
  return file_.write("# timestamp tx ty tz qx qy qz qw (camera in the map frame, TUM)\n");
}

Status TrajectoryFile::append(const FrameRecord& r) {
  if (!file_.is_open() || r.pose.state != TrackingState::kTracking) return {};
  char line[256];
  int used = 0;
  if (!any_ || r.map_id != map_id_) {
    used = std::snprintf(line, sizeof line, "# map %" PRIu32 "\n", r.map_id);
    map_id_ = r.map_id;
    any_ = true;
  }
  const std::int64_t t = r.pose.timestamp_ns;
  const auto& p = r.pose.p_wc;
  const auto& q = r.pose.q_wc;  // w x y z
  used += std::snprintf(line + used, sizeof line - static_cast<std::size_t>(used),
                        "%" PRId64 ".%09" PRId64 " %.6f %.6f %.6f %.7f %.7f %.7f %.7f\n", t / 1000000000,
                        t % 1000000000, p[0], p[1], p[2], q[1], q[2], q[3], q[0]);
  return file_.write(line, static_cast<std::size_t>(used));
}

}  // namespace ale::app
