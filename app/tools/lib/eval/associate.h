// Association of an estimate with the ground truth by timestamp.
#pragma once

#include <vector>

#include "core/base/status.h"
#include "app/tools/lib/eval/trajectory.h"

namespace ale::eval {

// Ground-truth and estimated poses at matched times: gt[i] belongs with est[i].
struct PosePairs {
  std::vector<StampedPose> gt;
  std::vector<StampedPose> est;
};

// Matches the same way as evo's `associate_trajectories`, so metrics agree with it: every
// timestamp of the trajectory with fewer poses (the estimate when both have the same count) is
// paired with the nearest timestamp of the other one (the earlier on a tie) when they differ by
// at most max_dt_s. Pairs stay in time order; a pose of the longer trajectory may be used twice.
// Fails, naming both files and the time ranges, when nothing matches.
Result<PosePairs> associate(const Trajectory& gt, const Trajectory& est, double max_dt_s);

}  // namespace ale::eval
