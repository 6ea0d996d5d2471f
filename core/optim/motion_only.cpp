#include "core/optim/motion_only.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Cholesky>

#include "core/optim/reprojection.h"
#include "core/optim/robust.h"

namespace ale::optim {

using geometry::Mat26;
using geometry::Mat3;
using geometry::SE3;
using geometry::Vec2;
using geometry::Vec6;
using Mat6 = Eigen::Matrix<double, 6, 6>;

namespace {

constexpr int kMaxLevel = 31;

struct Normal {
  Mat6 h;
  Vec6 g;
};

// Robust cost over the current inliers at T_cw and, when `normal` is given, the IRLS normal
// equations. +inf when an inlier's point is behind the camera.
double evaluate(const geometry::Camera& camera, const SE3& T_cw, const PoseObservation* obs, int n,
                const std::uint8_t* inlier, const std::array<double, kMaxLevel + 1>& info,
                const RobustKernel& kernel, const CentrePrior& prior, Normal* normal) {
  const Mat3 r_cw = T_cw.rotation();
  double cost = 0.0;
  if (normal) {
    normal->h.setZero();
    normal->g.setZero();
  }
  if (prior.sigma > 0.0) {
    const double w = 1.0 / (prior.sigma * prior.sigma);
    const geometry::Vec3 e = centre_residual(r_cw, T_cw.translation(), prior.centre_w);
    cost += 0.5 * w * e.squaredNorm();
    if (normal) add_centre_normal_equations(normal->h, normal->g, r_cw, e, w);
  }
  for (int k = 0; k < n; ++k) {
    if (!inlier[k]) continue;
    Vec2 r;
    Mat26 j;
    if (!reprojection_residual(camera, r_cw, T_cw.translation(), obs[k].p_w, obs[k].uv_px, &r,
                               normal ? &j : nullptr, nullptr)) {
      return std::numeric_limits<double>::infinity();
    }
    const double w_info = info[std::clamp(obs[k].level, 0, kMaxLevel)];
    double rho = 0.0, weight = 0.0;
    kernel.evaluate(w_info * r.squaredNorm(), &rho, &weight);
    cost += 0.5 * rho;
    if (normal) {
      const Mat26 wj = (w_info * weight) * j;
      normal->h.noalias() += j.transpose() * wj;
      normal->g.noalias() += wj.transpose() * r;
    }
  }
  return cost;
}

}  // namespace

MotionOnlyResult optimize_pose(const geometry::Camera& camera, const SE3& T_cw_init, const PoseObservation* obs,
                               int n, const MotionOnlyOptions& o, std::uint8_t* inlier, const CentrePrior& prior) {
  MotionOnlyResult res;
  res.T_cw = T_cw_init;
  if (!(camera.intrinsics().fx > 0.0)) {
    res.status = invalid_argument("motion-only: no valid camera");
    return res;
  }
  if (n < 3 || obs == nullptr || inlier == nullptr) {
    res.status = invalid_argument("motion-only: " + std::to_string(n) + " observations, at least 3 needed");
    return res;
  }
  if (!T_cw_init.translation().allFinite() || !T_cw_init.so3().quaternion().coeffs().allFinite()) {
    res.status = invalid_argument("motion-only: initial pose is not finite");
    return res;
  }
  for (int k = 0; k < n; ++k) {
    if (!obs[k].p_w.allFinite() || !obs[k].uv_px.allFinite()) {
      res.status = invalid_argument("motion-only: observation " + std::to_string(k) + " is not finite");
      return res;
    }
  }
  std::array<double, kMaxLevel + 1> info{};
  for (int l = 0; l <= kMaxLevel; ++l) info[l] = 1.0 / std::pow(o.scale_factor, 2.0 * l);
  // Start with every observation that projects as an inlier (ORB-SLAM starts with all).
  for (int k = 0; k < n; ++k) {
    Vec2 r;
    inlier[k] = reprojection_residual(camera, T_cw_init, obs[k].p_w, obs[k].uv_px, &r) ? 1 : 0;
  }
  LmOptions lm_options = o.lm;
  lm_options.max_iterations = o.iterations;
  SE3 T = T_cw_init;
  Normal normal, candidate_normal;
  LmController lm;
  for (int round = 0; round < o.rounds; ++round) {
    const RobustKernel kernel = round < o.robust_rounds ? RobustKernel::huber(o.huber_delta) : RobustKernel::none();
    const double cost = evaluate(camera, T, obs, n, inlier, info, kernel, prior, &normal);
    lm.start(lm_options, cost, normal.g.cwiseAbs().maxCoeff());
    if (lm.stop() == LmStop::kNumericalFailure) {
      res.status = internal_error("motion-only: cost or gradient not finite");
      return res;
    }
    while (!lm.done()) {
      Mat6 a = normal.h;
      Vec6 d_diag;
      for (int i = 0; i < 6; ++i) {
        d_diag[i] = lm.damping_diagonal(normal.h(i, i));
        a(i, i) += lm.lambda() * d_diag[i];
      }
      const Eigen::LLT<Mat6> llt(a);
      const Vec6 dx = llt.solve(-normal.g);
      if (llt.info() != Eigen::Success || !dx.allFinite()) {
        lm.report_failed_step();
        continue;
      }
      const double predicted = 0.5 * dx.dot(lm.lambda() * d_diag.cwiseProduct(dx) - normal.g);
      const SE3 T_new = SE3::exp(dx) * T;
      const double new_cost = evaluate(camera, T_new, obs, n, inlier, info, kernel, prior, &candidate_normal);
      if (lm.report_step(new_cost, predicted, dx.norm(), T.translation().norm())) {
        T = T_new;
        std::swap(normal, candidate_normal);
        lm.set_gradient(normal.g.cwiseAbs().maxCoeff());
      }
    }
    res.iterations += lm.iterations();
    // Reclassify every observation with this round's pose.
    const Mat3 r_cw = T.rotation();
    int inliers = 0;
    for (int k = 0; k < n; ++k) {
      Vec2 r;
      const bool ok = reprojection_residual(camera, r_cw, T.translation(), obs[k].p_w, obs[k].uv_px, &r, nullptr, nullptr);
      const double chi2 = ok ? info[std::clamp(obs[k].level, 0, kMaxLevel)] * r.squaredNorm() : 0.0;
      inlier[k] = ok && chi2 <= o.chi2_gate ? 1 : 0;
      inliers += inlier[k];
    }
    res.inliers = inliers;
    if (inliers < o.min_inliers) break;  // ORB-SLAM: fewer than 10 edges left
  }
  res.T_cw = T;
  res.final_cost = evaluate(camera, T, obs, n, inlier, info, RobustKernel::none(), prior, nullptr);
  if (res.inliers < o.min_inliers) {
    res.status = not_found("motion-only: " + std::to_string(res.inliers) + " inliers, fewer than " +
                           std::to_string(o.min_inliers));
  }
  return res;
}

}  // namespace ale::optim
