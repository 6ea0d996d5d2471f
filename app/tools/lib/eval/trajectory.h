// Trajectories for evaluation and the readers of the three file formats the field uses.
//
//   TUM    `t tx ty tz qx qy qz qw`, whitespace separated, t in seconds, '#' comments.
//   EuRoC  state CSV `#timestamp, p_RS_R_x, p_RS_R_y, p_RS_R_z, q_RS_w, q_RS_x, q_RS_y, q_RS_z, ...`,
//          t in nanoseconds, quaternion w first; any further columns (velocity, biases) ignored.
//   KITTI  12 numbers per line, the row-major 3x4 matrix [R | p]; no timestamps, so the line
//          index (0, 1, 2 ...) is the time.
//
// Tracking-loss marker (TUM and EuRoC): a comment line `# lost <t>` (t in the file's own time
// unit) says the estimator lost tracking at t; the next pose line is the recovery. Tools that
// ignore comments (evo) still read such files.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/status.h"

namespace ale::eval {

enum class TrajectoryFormat { kAuto, kTum, kEuroc, kKitti };

const char* to_string(TrajectoryFormat format);
// "tum", "euroc", "kitti" or "auto".
Result<TrajectoryFormat> parse_format(std::string_view name);

// Pose of the body (or camera) frame b in the world frame w at time t_s.
struct StampedPose {
  double t_s = 0.0;
  // Kept exactly as read (KITTI matrices are not perfectly orthonormal); inverses use the
  // transpose, as evo does, so results agree with it to rounding.
  Eigen::Matrix3d R_wb = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_wb = Eigen::Vector3d::Zero();
};

struct Trajectory {
  std::string name;  // the file it came from, for messages
  TrajectoryFormat format = TrajectoryFormat::kAuto;
  std::vector<StampedPose> poses;      // strictly increasing t_s
  std::vector<double> loss_marks_s;    // explicit `# lost <t>` markers, in seconds
  std::size_t duplicates_skipped = 0;  // see ReadOptions::skip_duplicate_times
};

struct ReadOptions {
  TrajectoryFormat format = TrajectoryFormat::kAuto;
  // Some estimators write a pose twice with the same timestamp (evo's own EuRoC V1_02 example
  // does). An error by default; when set, the first pose of each timestamp is kept.
  bool skip_duplicate_times = false;
};

// Guesses the format from the first data line: commas -> EuRoC, 8 columns -> TUM,
// 12 columns -> KITTI.
Result<TrajectoryFormat> detect_format(std::string_view text, const std::string& name);

// Parses `text` (the content of file `name`, used in messages "name:line: problem").
// Rejects: wrong column count, non-numbers, NaN/inf, zero quaternions, timestamps that do not
// strictly increase (unsorted or duplicate), and files without a single pose.
Result<Trajectory> parse_trajectory(std::string_view text, const ReadOptions& options,
                                    const std::string& name);

// Reads and parses a file.
Result<Trajectory> read_trajectory(const std::string& path, const ReadOptions& options = {});

}  // namespace ale::eval
