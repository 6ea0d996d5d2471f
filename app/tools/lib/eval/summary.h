// The few lines a person reads first about a run (how far off, how much was tracked, how fast),
// figures rounded to what they mean; ale-eval prints them (--print summary) and the report opens
// with them, the raw `key value` table below.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "app/tools/lib/eval/align.h"
#include "app/tools/lib/eval/associate.h"
#include "app/tools/lib/eval/frame_log.h"
#include "app/tools/lib/eval/metrics.h"

namespace ale::eval {

// v with `digits` significant digits, without exponent and without trailing zeros after the
// point: 0.03214 -> "0.032", 14.3 -> "14", 1234 -> "1234" (whole numbers keep their digits).
std::string round_significant(double v, int digits);

// A share 0..1 as a whole percentage, with as many decimals (up to 3) as it takes for a share
// below 1 not to show as 100 nor one above 0 as 0: 0.934 -> "93", 0.996 -> "99.6", 1 -> "100".
std::string percent(double share);

// Length of the path through the poses, in metres.
double path_length_m(const std::vector<StampedPose>& poses);

struct SummaryInput {
  // ATE of the associated pairs (nullptr: no trajectory evaluated)
  const ErrorStats* ate_m = nullptr;
  Alignment alignment = Alignment::kSe3;
  double path_m = 0.0;  // ground truth's path over the associated poses
  std::size_t pairs = 0;
  double coverage = 0.0;  // share of the ground-truth time the estimate covers (without a frame log)
  std::size_t losses = 0;
  // the run's frame log (nullptr: none)
  const FrameLogSummary* frames = nullptr;
};

// Three lines at most: the ATE in cm and in % of the path; the share of frames tracked (or,
// without a frame log, of the time covered), the losses, relocalisations, loops closed (a log
// with the loop columns), maps merged (a log with the merge columns) and maps; the frame time's median and p95 (and the longest frame a loop
// was closed on).
std::vector<std::string> summary_lines(const SummaryInput& in);

}  // namespace ale::eval
