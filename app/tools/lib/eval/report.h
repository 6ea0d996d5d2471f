// A self-contained HTML page (inline SVG, no scripts, no external files) with the figures of
// one evaluation: top view of the ground truth and the aligned estimate, error over time, and,
// given the run's frame log, brightness class, mean intensity, features, inliers, frame time
// and tracking state over the same time axis, the map and stage times, place recognition's
// time and loop closing's time. With a frame log the top view marks the relocalised frames (green
// rings, SVG class `relocalisation`), each new map's first pose (purple squares, class `new-map`)
// and the frames a loop was closed on (orange diamonds, class `loop-closure`) on the estimate;
// the place-recognition plot has a green line at each relocalised frame, and the error, frame
// time, map points, mapping and loop-closing plots an orange line at each loop closed (a log
// with the loop columns).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "app/tools/lib/eval/associate.h"
#include "app/tools/lib/eval/frame_log.h"
#include "app/tools/lib/eval/trajectory.h"

namespace ale::eval {

struct ReportInput {
  std::string title;                                         // e.g. "ATE (SE(3))"
  std::vector<std::string> summary;  // the page opens with these lines (summary_lines())
  std::vector<std::pair<std::string, std::string>> figures;  // the `key value` lines, below them
  // Both or neither; neither draws the frame log alone.
  const Trajectory* gt = nullptr;      // the whole ground truth, drawn as a path
  const PosePairs* aligned = nullptr;  // associated pairs, estimate already aligned
  double max_gap_s = 0.0;              // the estimate's path is broken at longer gaps
  // One error per time, e.g. the ATE of each pair or the RPE of each pose pair.
  std::vector<double> error_t_s;
  std::vector<double> error_values;
  std::string error_label;  // y axis, with unit
  const FrameLog* frame_log = nullptr;  // optional; needs ground truth with timestamps (not KITTI)
};

// The page as a string; fails when the input has neither poses nor a frame log, the error lists
// differ in size, or a frame log comes with a KITTI (index-timed) ground truth.
Result<std::string> render_report_html(const ReportInput& input);

// Renders and writes the page to path.
Status write_report(const std::string& path, const ReportInput& input);

}  // namespace ale::eval
