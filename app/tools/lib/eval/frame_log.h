// Reading the daemon's per-frame log (`ale-slamd --frame-log FILE.csv`; the row type and its
// column table: core/base/frame_log.h) and the figures drawn from it.
//
// The header line (with or without '#') comes first and names the columns; they are found by
// name, so columns the reader does not know (a newer daemon's) are ignored, and a missing one
// is an error.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/frame_log.h"
#include "core/base/frame_state.h"
#include "core/base/status.h"

namespace ale::eval {

using FrameRecord = FrameLogRow;

struct FrameLog {
  std::string name;  // the file it came from, for messages
  std::vector<FrameRecord> frames;  // strictly increasing timestamp_ns
  bool has_slam_columns = false;    // the SLAM core's columns (map_id .. mapping_ms) were in the file
  bool has_place_column = false;    // place_ms was
  bool has_loop_columns = false;    // loops and loop_ms were
  bool has_merge_columns = false;   // merges and merges_refused were
};

Result<BrightnessClass> parse_brightness_class(std::string_view name);
Result<TrackingState> parse_tracking_state(std::string_view name);

// Parses `text`, the content of file `name` ("name:line: problem" in messages). Rejects a
// missing or incomplete header, a line with a column count other than the header's, values
// that are not numbers (or whole numbers >= 0 where counts are meant), unknown class or state
// names, timestamps that do not increase, and a log without a frame.
Result<FrameLog> parse_frame_log(std::string_view text, const std::string& name);
Result<FrameLog> read_frame_log(const std::string& path);

constexpr std::size_t kBrightnessClasses = 4;
// Frames with at least this many inliers count towards the valid inlier average (the
// article's VIA, spec section 8).
constexpr int kViaMinInliers = 10;

struct FrameLogSummary {
  std::size_t frames = 0;
  std::array<double, kBrightnessClasses> brightness_share{};  // by BrightnessClass, 0..1
  double features_mean = 0.0;
  double via = 0.0;  // mean inliers over the frames with >= kViaMinInliers; NaN when none
  std::size_t via_frames = 0;
  double frame_time_mean_ms = 0.0;
  double frame_time_median_ms = 0.0;  // the mean of the two middle values for an even count
  double frame_time_p95_ms = 0.0;  // nearest rank: the ceil(0.95 n)-th smallest
  double frame_time_max_ms = 0.0;
  std::size_t tracking_losses = 0;  // transitions from another state into lost
  std::size_t relocalisations = 0;  // frames posed by relocalisation after a loss
  double tracked_share = 0.0;       // frames in state tracking, 0..1
  std::size_t maps = 0;             // 1 + the new maps started (map_id changes, merges aside)
  int keyframes_last = 0;           // in the map after the last frame
  int landmarks_last = 0;
  double frontend_mean_ms = 0.0;    // per frame, by stage group
  double tracking_mean_ms = 0.0;
  double mapping_mean_ms = 0.0;
  double place_mean_ms = 0.0;       // place recognition (a part of tracking and mapping)
  double place_max_ms = 0.0;
  bool loops_logged = false;           // the log had the loop columns (FrameLog::has_loop_columns)
  std::size_t loops_closed = 0;        // frames a loop was closed on (loops_closed_at), loops each
  double loop_mean_ms = 0.0;           // loop closing (a part of mapping)
  double loop_max_ms = 0.0;
  double loop_frame_time_max_ms = 0.0;  // the longest frame a loop was closed on; 0 without one
  bool merges_logged = false;          // the log had the merge columns (FrameLog::has_merge_columns)
  std::size_t merges = 0;              // maps merged: the rises of `merges` (merges_at)
  std::size_t merges_refused = 0;      // the rises of `merges_refused`
};

// Needs at least one frame.
FrameLogSummary summarize(const FrameLog& log);

// The loops closed on frame i: its `loops` count above its predecessor's (the first frame's
// above 0); 0 when the count did not rise.
int loops_closed_at(const FrameLog& log, std::size_t i);
// The maps merged on frame i (the current map moved into an older one; its map_id changes to that
// map's): its `merges` count above its predecessor's, as loops_closed_at.
int merges_at(const FrameLog& log, std::size_t i);

}  // namespace ale::eval
