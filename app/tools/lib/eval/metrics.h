// Trajectory error metrics: absolute (ATE), relative (RPE), coverage and tracking losses.
// Definitions follow evo (github.com/MichaelGrupp/evo) so that results can be compared with
// published numbers; docs/evaluation.md states them in full.
#pragma once

#include <cstddef>
#include <string_view>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "app/tools/lib/eval/align.h"
#include "app/tools/lib/eval/associate.h"
#include "app/tools/lib/eval/trajectory.h"

namespace ale::eval {

// Summary of a list of errors. std is the population standard deviation and median the mean of
// the two middle values for an even count (numpy's conventions, which evo uses).
struct ErrorStats {
  std::size_t count = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;
  double min = 0.0;
  double max = 0.0;
  double sse = 0.0;  // sum of squares
};

// Fails for an empty list.
Result<ErrorStats> compute_stats(std::vector<double> errors);

struct AteResult {
  ErrorStats trans_m;    // |p_gt - p_est| after alignment
  ErrorStats rot_deg;    // angle of R_gt^T R_est after alignment
  std::vector<double> t_s;             // time of each pair (ground truth's)
  std::vector<double> trans_errors_m;  // per pair, for plots
};

// On already associated and aligned pairs.
Result<AteResult> compute_ate(const PosePairs& pairs);

enum class DeltaUnit { kFrames, kMeters };
const char* to_string(DeltaUnit unit);
// "frames" or "m".
Result<DeltaUnit> parse_delta_unit(std::string_view name);

struct RpeOptions {
  double delta = 1.0;
  DeltaUnit unit = DeltaUnit::kFrames;
  // Which trajectory's path selects the pairs for DeltaUnit::kMeters. evo >= 1.13 uses the
  // estimate unless --pairs_from_reference is given.
  bool pairs_from_gt = false;
};

using IndexPairs = std::vector<std::pair<std::size_t, std::size_t>>;

// Consecutive, non-overlapping pairs as evo selects them:
//   frames: indices 0, d, 2d, ... and each with the next;
//   meters: walking the path, an index is taken each time the distance travelled since the
//   previously taken one (or, for the first, since the start) reaches delta; pairs are
//   consecutive taken indices. So the first pair starts delta metres into the path.
Result<IndexPairs> select_rpe_pairs(const std::vector<StampedPose>& poses, const RpeOptions& options);

struct RpeResult {
  ErrorStats trans_m;  // |translation of E| with E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j)
  ErrorStats rot_deg;  // rotation angle of E
  IndexPairs pairs;
  std::vector<double> trans_errors_m;  // per pair, for plots (at the time of its second pose)
};

// On associated (and, if wanted, aligned) pairs. Fails when delta yields no pair.
Result<RpeResult> compute_rpe(const PosePairs& pairs, const RpeOptions& options);

struct CoverageResult {
  double coverage = 0.0;   // share of the ground-truth time span covered by the estimate, 0..1
  std::size_t losses = 0;  // tracking losses, see compute_coverage
  double max_gap_s = 0.0;  // the gap threshold used
};

// Between two consecutive estimated poses the estimate "covers" the time in between, unless the
// gap is longer than max_gap_s or a `# lost` marker lies in it. Coverage is the covered part of
// [first, last] ground-truth time. A tracking loss is each such uncovered gap that overlaps the
// ground-truth span, plus one more when the estimate stops (marker or gap) before the ground
// truth ends. A late start (initialisation) lowers coverage but is not a loss.
// max_gap_s <= 0 selects the default: 5 times the median spacing of the estimate.
Result<CoverageResult> compute_coverage(const Trajectory& gt, const Trajectory& est, double max_gap_s);

}  // namespace ale::eval
