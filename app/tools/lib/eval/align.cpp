#include "app/tools/lib/eval/align.h"

#include <string>

#include "core/geometry/sim3_solver.h"

namespace ale::eval {

const char* to_string(Alignment alignment) {
  switch (alignment) {
    case Alignment::kNone: return "none";
    case Alignment::kSe3: return "se3";
    case Alignment::kSim3: return "sim3";
  }
  return "?";
}

Result<Alignment> parse_alignment(std::string_view name) {
  for (Alignment a : {Alignment::kNone, Alignment::kSe3, Alignment::kSim3}) {
    if (name == to_string(a)) return a;
  }
  return invalid_argument("unknown alignment '" + std::string(name) + "' (expected se3, sim3 or none)");
}

Result<Sim3> umeyama(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& y,
                     bool with_scale) {
  // The messages speak of poses (what a trajectory user matched); the math is the solvers'.
  if (x.size() != y.size()) return invalid_argument("umeyama: point sets differ in size");
  if (x.size() < 3) {
    return invalid_argument("alignment needs at least 3 matched poses, got " + std::to_string(x.size()));
  }
  const Result<geometry::Sim3> s = geometry::umeyama(x, y, with_scale);
  if (!s.ok()) return invalid_argument("alignment impossible: " + s.status().message());
  Sim3 sim3;
  sim3.R = s->rotation();
  sim3.scale = s->scale();
  sim3.t = s->translation();
  return sim3;
}

Result<Sim3> align_estimate(Alignment alignment, PosePairs* pairs) {
  if (alignment == Alignment::kNone) return Sim3{};
  std::vector<Eigen::Vector3d> est_p;
  std::vector<Eigen::Vector3d> gt_p;
  est_p.reserve(pairs->est.size());
  gt_p.reserve(pairs->gt.size());
  for (std::size_t i = 0; i < pairs->est.size(); ++i) {
    est_p.push_back(pairs->est[i].p_wb);
    gt_p.push_back(pairs->gt[i].p_wb);
  }
  Result<Sim3> sim3 = umeyama(est_p, gt_p, alignment == Alignment::kSim3);
  if (!sim3.ok()) return sim3.status();
  for (StampedPose& pose : pairs->est) {
    pose.p_wb = sim3->apply(pose.p_wb);
    pose.R_wb = sim3->R * pose.R_wb;
  }
  return sim3;
}

}  // namespace ale::eval
