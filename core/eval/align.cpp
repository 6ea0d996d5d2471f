#include "core/eval/align.h"

#include <Eigen/LU>
#include <Eigen/SVD>

#include <limits>
#include <string>

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
  if (x.size() != y.size()) return invalid_argument("umeyama: point sets differ in size");
  if (x.size() < 3) {
    return invalid_argument("alignment needs at least 3 matched poses, got " + std::to_string(x.size()));
  }
  const double n = static_cast<double>(x.size());
  Eigen::Vector3d mean_x = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_y = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < x.size(); ++i) {
    mean_x += x[i];
    mean_y += y[i];
  }
  mean_x /= n;
  mean_y /= n;
  double var_x = 0.0;
  Eigen::Matrix3d cov_yx = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < x.size(); ++i) {
    const Eigen::Vector3d dx = x[i] - mean_x;
    var_x += dx.squaredNorm();
    cov_yx += (y[i] - mean_y) * dx.transpose();
  }
  var_x /= n;
  cov_yx /= n;

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov_yx, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d& d = svd.singularValues();
  // A rotation is determined once two directions are (points not all on one line).
  int rank = 0;
  for (int i = 0; i < 3; ++i) rank += d[i] > std::numeric_limits<double>::epsilon() ? 1 : 0;
  if (rank < 2) {
    return invalid_argument("alignment impossible: the matched positions are degenerate "
                            "(all on one line or one point)");
  }
  Eigen::Matrix3d s = Eigen::Matrix3d::Identity();
  // Reflections are not rotations: flip the weakest axis when U V^T would mirror.
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) s(2, 2) = -1.0;

  Sim3 sim3;
  sim3.R = svd.matrixU() * s * svd.matrixV().transpose();
  sim3.scale = with_scale ? (d.asDiagonal() * s).trace() / var_x : 1.0;
  sim3.t = mean_y - sim3.scale * (sim3.R * mean_x);
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
