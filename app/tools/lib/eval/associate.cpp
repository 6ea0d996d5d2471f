#include "app/tools/lib/eval/associate.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ale::eval {
namespace {

// Index of the pose in `poses` nearest in time to t_s (sorted times; the earlier on a tie).
std::size_t nearest_index(const std::vector<StampedPose>& poses, double t_s) {
  const auto later = std::lower_bound(poses.begin(), poses.end(), t_s,
                                      [](const StampedPose& p, double t) { return p.t_s < t; });
  if (later == poses.begin()) return 0;
  if (later == poses.end()) return poses.size() - 1;
  const auto earlier = later - 1;
  const bool take_later = std::abs(later->t_s - t_s) < std::abs(earlier->t_s - t_s);
  return static_cast<std::size_t>((take_later ? later : earlier) - poses.begin());
}

std::string time_range(const Trajectory& t) {
  std::ostringstream out;
  out.precision(15);
  out << t.name << " [" << t.poses.front().t_s << ", " << t.poses.back().t_s << "] s";
  return out.str();
}

}  // namespace

Result<PosePairs> associate(const Trajectory& gt, const Trajectory& est, double max_dt_s) {
  if (!(max_dt_s >= 0.0)) return invalid_argument("max time difference must be >= 0");
  if (gt.poses.empty() || est.poses.empty()) return invalid_argument("associate: empty trajectory");
  const bool est_longer = est.poses.size() > gt.poses.size();
  const std::vector<StampedPose>& shorter = est_longer ? gt.poses : est.poses;
  const std::vector<StampedPose>& longer = est_longer ? est.poses : gt.poses;
  PosePairs pairs;
  for (const StampedPose& pose : shorter) {
    const StampedPose& match = longer[nearest_index(longer, pose.t_s)];
    if (!(std::abs(match.t_s - pose.t_s) <= max_dt_s)) continue;
    pairs.gt.push_back(est_longer ? pose : match);
    pairs.est.push_back(est_longer ? match : pose);
  }
  if (pairs.gt.empty()) {
    std::ostringstream out;
    out << "no pose of " << time_range(est) << " is within " << max_dt_s << " s of a pose of "
        << time_range(gt) << " (no overlap; check the time units or raise --max-dt)";
    return corrupt_data(out.str());
  }
  return pairs;
}

}  // namespace ale::eval
