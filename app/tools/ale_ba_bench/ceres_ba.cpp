#include "app/tools/ale_ba_bench/ceres_ba.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <chrono>
#include <cmath>
#include <memory>

#include "core/optim/bundle_adjuster.h"
#include "core/optim/reprojection.h"

namespace ale::ceres_ref {

using geometry::SE3;
using geometry::SO3;
using geometry::Vec2;
using geometry::Vec3;

namespace {

// sqrt(information) * (project(R(aa) X + t) - uv); the same radial-tangential model as
// geometry::Camera (OpenCV order k1 k2 p1 p2 k3).
struct Reprojection {
  Reprojection(const geometry::CameraIntrinsics& k, const Vec2& uv, double information)
      : k_(k), uv_(uv), sqrt_info_(std::sqrt(information)) {}
  template <class T>
  bool operator()(const T* pose, const T* point, T* residual) const {
    T p[3];
    ceres::AngleAxisRotatePoint(pose + 3, point, p);
    p[0] += pose[0];
    p[1] += pose[1];
    p[2] += pose[2];
    const T x = p[0] / p[2], y = p[1] / p[2];
    const T r2 = x * x + y * y;
    const double k1 = k_.distortion[0], k2 = k_.distortion[1], p1 = k_.distortion[2], p2 = k_.distortion[3],
                 k3 = k_.distortion[4];
    const T radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const T xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
    const T yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
    residual[0] = sqrt_info_ * (k_.fx * xd + k_.cx - uv_.x());
    residual[1] = sqrt_info_ * (k_.fy * yd + k_.cy - uv_.y());
    return true;
  }
  geometry::CameraIntrinsics k_;
  Vec2 uv_;
  double sqrt_info_;
};

// Pose-only variant (point fixed) for the motion-only rounds.
struct PoseReprojection {
  PoseReprojection(const geometry::CameraIntrinsics& k, const Vec2& uv, double information, const Vec3& p_w)
      : r_(k, uv, information), p_w_(p_w) {}
  template <class T>
  bool operator()(const T* pose, T* residual) const {
    const T point[3] = {T(p_w_.x()), T(p_w_.y()), T(p_w_.z())};
    return r_(pose, point, residual);
  }
  Reprojection r_;
  Vec3 p_w_;
};

void to_block(const SE3& T, double* b) {
  b[0] = T.translation().x();
  b[1] = T.translation().y();
  b[2] = T.translation().z();
  const Vec3 aa = T.so3().log();
  b[3] = aa.x();
  b[4] = aa.y();
  b[5] = aa.z();
}

SE3 from_block(const double* b) { return SE3(SO3::exp(Vec3(b[3], b[4], b[5])), Vec3(b[0], b[1], b[2])); }

ceres::Solver::Options solver_options(const Options& o) {
  ceres::Solver::Options so;
  so.linear_solver_type = o.solver == Solver::kSparseSchur  ? ceres::SPARSE_SCHUR
                          : o.solver == Solver::kDenseSchur ? ceres::DENSE_SCHUR
                                                            : ceres::DENSE_QR;
  so.num_threads = 1;
  so.max_num_iterations = o.max_iterations;
  so.function_tolerance = o.function_tolerance;
  so.gradient_tolerance = o.gradient_tolerance;
  so.parameter_tolerance = o.parameter_tolerance;
  so.minimizer_progress_to_stdout = false;
  so.logging_type = ceres::SILENT;
  return so;
}

Result run(ceres::Problem* problem, const Options& o) {
  ceres::Solver::Summary summary;
  const auto t0 = std::chrono::steady_clock::now();
  ceres::Solve(solver_options(o), problem, &summary);
  const auto t1 = std::chrono::steady_clock::now();
  Result r;
  r.usable = summary.IsSolutionUsable();
  r.initial_cost = summary.initial_cost;
  r.final_cost = summary.final_cost;
  r.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  r.time_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  r.converged = summary.termination_type == ceres::CONVERGENCE;
  return r;
}

}  // namespace

Result solve_ba(const geometry::CameraIntrinsics& k, std::vector<SE3>* T_cw, const std::vector<bool>& pose_fixed,
                std::vector<Vec3>* points_w, const std::vector<Observation>& observations, const Options& o) {
  std::vector<double> poses(6 * T_cw->size());
  for (std::size_t i = 0; i < T_cw->size(); ++i) to_block((*T_cw)[i], &poses[6 * i]);
  std::vector<double> points(3 * points_w->size());
  for (std::size_t j = 0; j < points_w->size(); ++j) {
    for (int d = 0; d < 3; ++d) points[3 * j + d] = (*points_w)[j][d];
  }
  ceres::Problem problem;
  for (const Observation& ob : observations) {
    ceres::LossFunction* loss = o.huber_delta > 0 ? new ceres::HuberLoss(o.huber_delta) : nullptr;
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<Reprojection, 2, 6, 3>(new Reprojection(k, ob.uv_px, ob.information)), loss,
        &poses[6 * ob.pose], &points[3 * ob.point]);
  }
  for (std::size_t i = 0; i < T_cw->size(); ++i) {
    if (pose_fixed[i] && problem.HasParameterBlock(&poses[6 * i])) problem.SetParameterBlockConstant(&poses[6 * i]);
  }
  const Result r = run(&problem, o);
  for (std::size_t i = 0; i < T_cw->size(); ++i) (*T_cw)[i] = from_block(&poses[6 * i]);
  for (std::size_t j = 0; j < points_w->size(); ++j) (*points_w)[j] = Vec3(points[3 * j], points[3 * j + 1], points[3 * j + 2]);
  return r;
}

Result solve_libmv(optim::LibmvProblem* p, const Options& o) {
  std::vector<Observation> obs;
  obs.reserve(p->observations.size());
  for (const optim::LibmvObservation& ob : p->observations) obs.push_back({ob.camera, ob.point, ob.uv_px, 1.0});
  return solve_ba(p->intrinsics, &p->T_cw, std::vector<bool>(p->T_cw.size(), false), &p->points_w, obs, o);
}

optim::MotionOnlyResult optimize_pose(const geometry::CameraIntrinsics& k, const SE3& T_cw_init,
                                      const optim::PoseObservation* obs, int n, const optim::MotionOnlyOptions& mo,
                                      std::uint8_t* inlier) {
  const geometry::Camera camera = geometry::Camera::create(k).value();
  optim::MotionOnlyResult res;
  double pose[6];
  to_block(T_cw_init, pose);
  for (int i = 0; i < n; ++i) inlier[i] = 1;
  Options o;
  o.solver = Solver::kDenseQr;
  o.max_iterations = mo.iterations;
  for (int round = 0; round < mo.rounds; ++round) {
    ceres::Problem problem;
    for (int i = 0; i < n; ++i) {
      if (!inlier[i]) continue;
      const double info = optim::level_information(mo.scale_factor, obs[i].level);
      ceres::LossFunction* loss = round < mo.robust_rounds ? new ceres::HuberLoss(mo.huber_delta) : nullptr;
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PoseReprojection, 2, 6>(
                                   new PoseReprojection(k, obs[i].uv_px, info, obs[i].p_w)),
                               loss, pose);
    }
    if (problem.NumResidualBlocks() > 0) res.iterations += run(&problem, o).iterations;
    const SE3 T = from_block(pose);
    res.inliers = 0;
    for (int i = 0; i < n; ++i) {
      Vec2 r;
      const bool ok = optim::reprojection_residual(camera, T, obs[i].p_w, obs[i].uv_px, &r);
      inlier[i] = ok && optim::level_information(mo.scale_factor, obs[i].level) * r.squaredNorm() <= mo.chi2_gate;
      res.inliers += inlier[i];
    }
    if (res.inliers < mo.min_inliers) break;
  }
  res.T_cw = from_block(pose);
  return res;
}

}  // namespace ale::ceres_ref
