#include "app/tools/lib/eval/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace ale::eval {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

// Rotation angle of a (nearly) orthonormal matrix; atan2 keeps precision near 0 and pi where
// acos of the trace alone would not.
double rotation_angle_deg(const Eigen::Matrix3d& R) {
  const double cos_angle = std::clamp(0.5 * (R.trace() - 1.0), -1.0, 1.0);
  const Eigen::Vector3d axis(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  return std::atan2(0.5 * axis.norm(), cos_angle) * kRadToDeg;
}

// p_i^-1 p_j with the transpose as inverse (see StampedPose).
StampedPose relative(const StampedPose& i, const StampedPose& j) {
  StampedPose rel;
  rel.R_wb = i.R_wb.transpose() * j.R_wb;
  rel.p_wb = i.R_wb.transpose() * (j.p_wb - i.p_wb);
  return rel;
}

// The callers have at least one error, so the summaries cannot fail, but say so if they do.
Status summarise(std::vector<double> trans_m, std::vector<double> rot_deg, ErrorStats* trans,
                 ErrorStats* rot) {
  Result<ErrorStats> t = compute_stats(std::move(trans_m));
  if (!t.ok()) return t.status();
  Result<ErrorStats> r = compute_stats(std::move(rot_deg));
  if (!r.ok()) return r.status();
  *trans = *t;
  *rot = *r;
  return Status::ok_status();
}

}  // namespace

Result<ErrorStats> compute_stats(std::vector<double> errors) {
  if (errors.empty()) return invalid_argument("no errors to summarise");
  ErrorStats s;
  s.count = errors.size();
  const double n = static_cast<double>(errors.size());
  double sum = 0.0;
  for (double e : errors) {
    sum += e;
    s.sse += e * e;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(s.sse / n);
  double var = 0.0;
  for (double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(var / n);
  std::sort(errors.begin(), errors.end());
  s.min = errors.front();
  s.max = errors.back();
  const std::size_t mid = errors.size() / 2;
  s.median = errors.size() % 2 == 1 ? errors[mid] : 0.5 * (errors[mid - 1] + errors[mid]);
  return s;
}

Result<AteResult> compute_ate(const PosePairs& pairs) {
  AteResult ate;
  std::vector<double> rot_deg;
  ate.t_s.reserve(pairs.gt.size());
  ate.trans_errors_m.reserve(pairs.gt.size());
  rot_deg.reserve(pairs.gt.size());
  for (std::size_t i = 0; i < pairs.gt.size(); ++i) {
    ate.t_s.push_back(pairs.gt[i].t_s);
    ate.trans_errors_m.push_back((pairs.est[i].p_wb - pairs.gt[i].p_wb).norm());
    rot_deg.push_back(rotation_angle_deg(pairs.gt[i].R_wb.transpose() * pairs.est[i].R_wb));
  }
  ALE_RETURN_IF_ERROR(summarise(ate.trans_errors_m, std::move(rot_deg), &ate.trans_m, &ate.rot_deg));
  return ate;
}

const char* to_string(DeltaUnit unit) { return unit == DeltaUnit::kFrames ? "frames" : "m"; }

Result<DeltaUnit> parse_delta_unit(std::string_view name) {
  if (name == "frames" || name == "f") return DeltaUnit::kFrames;
  if (name == "m" || name == "meters") return DeltaUnit::kMeters;
  return invalid_argument("unknown delta unit '" + std::string(name) + "' (expected frames or m)");
}

Result<IndexPairs> select_rpe_pairs(const std::vector<StampedPose>& poses, const RpeOptions& options) {
  IndexPairs pairs;
  std::vector<std::size_t> taken;
  if (options.unit == DeltaUnit::kFrames) {
    if (!(options.delta >= 1.0) || options.delta != std::floor(options.delta)) {
      return invalid_argument("delta in frames must be a whole number >= 1");
    }
    const auto step = static_cast<std::size_t>(options.delta);
    for (std::size_t i = 0; i < poses.size(); i += step) taken.push_back(i);
  } else {
    if (!(options.delta > 0.0)) return invalid_argument("delta in metres must be > 0");
    double path_m = 0.0;
    for (std::size_t i = 1; i < poses.size(); ++i) {
      path_m += (poses[i].p_wb - poses[i - 1].p_wb).norm();
      if (path_m >= options.delta) {
        taken.push_back(i);
        path_m = 0.0;
      }
    }
  }
  for (std::size_t k = 1; k < taken.size(); ++k) pairs.emplace_back(taken[k - 1], taken[k]);
  return pairs;
}

Result<RpeResult> compute_rpe(const PosePairs& pairs, const RpeOptions& options) {
  Result<IndexPairs> selected = select_rpe_pairs(options.pairs_from_gt ? pairs.gt : pairs.est, options);
  if (!selected.ok()) return selected.status();
  if (selected->empty()) {
    return invalid_argument("delta " + std::to_string(options.delta) + " " + to_string(options.unit) +
                            " gives no pose pair over " + std::to_string(pairs.gt.size()) +
                            " matched poses; use a smaller delta");
  }
  RpeResult rpe;
  rpe.pairs = std::move(*selected);
  std::vector<double> trans_m;
  std::vector<double> rot_deg;
  for (const auto& [i, j] : rpe.pairs) {
    const StampedPose error = relative(relative(pairs.gt[i], pairs.gt[j]), relative(pairs.est[i], pairs.est[j]));
    trans_m.push_back(error.p_wb.norm());
    rot_deg.push_back(rotation_angle_deg(error.R_wb));
  }
  ALE_RETURN_IF_ERROR(summarise(trans_m, std::move(rot_deg), &rpe.trans_m, &rpe.rot_deg));
  rpe.trans_errors_m = std::move(trans_m);
  return rpe;
}

Result<CoverageResult> compute_coverage(const Trajectory& gt, const Trajectory& est, double max_gap_s) {
  if (gt.poses.size() < 2) return invalid_argument(gt.name + ": coverage needs at least 2 ground-truth poses");
  if (est.poses.empty()) return invalid_argument(est.name + ": no estimated poses");
  const double gt_begin = gt.poses.front().t_s;
  const double gt_end = gt.poses.back().t_s;
  CoverageResult result;
  if (max_gap_s <= 0.0 && est.poses.size() >= 2) {
    std::vector<double> spacing;
    for (std::size_t k = 1; k < est.poses.size(); ++k) spacing.push_back(est.poses[k].t_s - est.poses[k - 1].t_s);
    Result<ErrorStats> stats = compute_stats(std::move(spacing));
    if (!stats.ok()) return stats.status();
    max_gap_s = 5.0 * stats->median;
  }
  result.max_gap_s = std::max(max_gap_s, 0.0);

  std::vector<double> marks = est.loss_marks_s;
  std::sort(marks.begin(), marks.end());
  const auto marked = [&marks](double from, double to) {
    const auto first = std::lower_bound(marks.begin(), marks.end(), from);
    return first != marks.end() && *first < to;
  };
  double covered_s = 0.0;
  for (std::size_t k = 1; k < est.poses.size(); ++k) {
    const double a = est.poses[k - 1].t_s;
    const double b = est.poses[k].t_s;
    const bool lost = b - a > result.max_gap_s || marked(a, b);
    const double overlap = std::min(b, gt_end) - std::max(a, gt_begin);
    if (lost) {
      if (overlap > 0.0) ++result.losses;
    } else if (overlap > 0.0) {
      covered_s += overlap;
    }
  }
  const double last = est.poses.back().t_s;
  if (last < gt_end && (gt_end - last > result.max_gap_s || marked(last, std::numeric_limits<double>::infinity()))) ++result.losses;
  result.coverage = covered_s / (gt_end - gt_begin);
  return result;
}

}  // namespace ale::eval
