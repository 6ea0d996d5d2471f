// `ale-slamd --trajectory OUT.tum`: one TUM line per frame with a pose ("t tx ty tz qx qy qz qw",
// the camera in the map frame, t in seconds), for ale-eval and evo. A new map (after tracking was
// lost for good) starts a new segment, marked by a comment line "# map <id>" that TUM readers skip;
// the frame log's map_id column says the same per frame. So does a map file loaded while running
// (start_segment()), even when its id is one this run used before.
//
// Lines are written as frames are published (the online pose, what the motion controller got), so
// a run that is killed keeps what stdio had flushed of them. With `daemon.trajectory_poses = final` (the default) finish()
// then rewrites the file with each frame's final pose: its pose relative to its reference keyframe
// composed with that keyframe's pose at the end of the run (core/slam/refined_trajectory.h),
// ORB-SLAM's convention for the trajectory it saves, which the peers' figures use. A map merged
// into an older one (core/slam/loop_closer.h) then has its frames in the older map's segment.
// Poses the wheel odometry carried (pose_t.odometry_only: frames the camera did not track) are in
// the online file only; the final one holds what the camera tracked.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "app/daemon/frame_pipeline.h"
#include "core/base/text_file.h"
#include "core/slam/refined_trajectory.h"

namespace ale::app {

class TrajectoryFile {
 public:
  // kIoError naming the path when it cannot be created. final_poses: finish() rewrites the file.
  Status open(const std::string& path, bool final_poses);
  // Writes the record's pose when it has one; nothing when not open.
  Status append(const FrameRecord& record);
  // Closes the file, first rewriting it with final poses when opened so: each line whose frame
  // `refined` holds with a refined, finite pose (matched by sequence number and timestamp) takes
  // that pose, the others keep theirs. The rewrite goes to PATH.tmp, renamed over PATH, so an
  // error leaves the online file whole; kIoError naming the file if anything was lost.
  Status finish(const ale::slam::RefinedTrajectory* refined);
  // The poses from the next one on are in another frame even if their map_id is the same (a map
  // file loaded while running may hold the id of a map this run made): a new segment starts.
  void start_segment() {
    ++segment_;
    any_ = false;  // the next line opens a segment
  }

 private:
  struct Line {
    std::uint64_t sequence = 0;
    std::int64_t timestamp_ns = 0;
    std::uint32_t map_id = 0;
    std::uint32_t segment = 0;  // start_segment()'s count when the line was written
    std::array<double, 3> p{};
    std::array<double, 4> q{};  // w x y z
  };
  static Status write_line(TextFileWriter& file, const Line& line, bool new_segment);

  TextFileWriter file_;
  std::string path_;
  bool final_poses_ = false;
  std::vector<Line> lines_;  // what was written, for the rewrite (final poses only)
  std::uint32_t map_id_ = 0;
  std::uint32_t segment_ = 0;
  bool any_ = false;
};

}  // namespace ale::app
