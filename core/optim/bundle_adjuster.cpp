#include "core/optim/bundle_adjuster.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/optim/reprojection.h"

namespace ale::optim {

using geometry::Mat23;
using geometry::Mat26;
using geometry::SE3;
using geometry::Vec2;
using geometry::Vec3;
using Vec6 = Eigen::Matrix<double, 6, 1>;

double level_information(double scale_factor, int level) {
  return 1.0 / std::pow(scale_factor, 2.0 * level);
}

void BundleAdjuster::reset(const geometry::Camera& camera) {
  camera_ = camera;
  poses_.clear();
  points_.clear();
  pose_fixed_.clear();
  point_fixed_.clear();
  obs_.clear();
  priors_.clear();
  rotation_priors_.clear();
  first_bad_observation_ = -1;
  bad_prior_ = false;
}

void BundleAdjuster::reserve(int poses, int points, int observations, int dense_max_dim) {
  const auto n_poses = static_cast<std::size_t>(poses), n_points = static_cast<std::size_t>(points),
             n_obs = static_cast<std::size_t>(observations);
  for (auto* v : {&poses_, &poses_candidate_}) grow_capacity(*v, n_poses);
  for (auto* v : {&points_, &points_candidate_}) grow_capacity(*v, n_points);
  grow_capacity(pose_fixed_, n_poses);
  grow_capacity(point_fixed_, n_points);
  grow_capacity(free_pose_, n_poses);
  grow_capacity(free_point_, n_points);
  grow_capacity(rotation_, n_poses);
  grow_capacity(obs_, n_obs);
  grow_capacity(priors_, n_poses);
  grow_capacity(rotation_priors_, n_poses);
  grow_capacity(inlier_, n_obs);
  for (auto* v : {&term_elim_, &term_keep_, &analysed_elim_, &analysed_keep_}) grow_capacity(*v, n_obs);
  for (Linearisation* l : {&lin_, &lin_candidate_}) {
    grow_capacity(l->r, n_obs);
    grow_capacity(l->jc, n_obs);
    grow_capacity(l->jl, n_obs);
    grow_capacity(l->w, n_obs);
  }
  grow_capacity(dx3_, n_points);
  grow_capacity(dx6_, n_poses);
  points_eliminated_.reserve(points, poses, observations, dense_max_dim);
}

int BundleAdjuster::add_pose(const SE3& T_cw, bool fixed) {
  poses_.push_back(T_cw);
  pose_fixed_.push_back(fixed ? 1 : 0);
  return num_poses() - 1;
}

int BundleAdjuster::add_point(const Vec3& p_w, bool fixed) {
  points_.push_back(p_w);
  point_fixed_.push_back(fixed ? 1 : 0);
  return num_points() - 1;
}

int BundleAdjuster::add_observation(int pose, int point, const Vec2& uv_px, double information,
                                    const RobustKernel& kernel) {
  const bool ok = pose >= 0 && pose < num_poses() && point >= 0 && point < num_points() &&
                  uv_px.allFinite() && std::isfinite(information) && information > 0.0 &&
                  (kernel.kind == RobustKind::kNone || (std::isfinite(kernel.delta) && kernel.delta > 0.0));
  if (!ok && first_bad_observation_ < 0) first_bad_observation_ = num_observations();
  obs_.push_back({ok ? pose : 0, ok ? point : 0, uv_px, information, kernel});
  return num_observations() - 1;
}

int BundleAdjuster::add_plane_observation(int pose, int point, const Vec3& normal_c, double offset, double information,
                                          const RobustKernel& kernel) {
  const int k = add_observation(pose, point, Vec2::Zero(), information, kernel);
  Observation& o = obs_.back();
  o.plane = true;
  o.normal = normal_c;
  o.offset = offset;
  if ((!normal_c.allFinite() || !std::isfinite(offset)) && first_bad_observation_ < 0) first_bad_observation_ = k;
  return k;
}

bool BundleAdjuster::residual(const Observation& o, const geometry::Mat3& R_cw, const Vec3& t_cw, const Vec3& p_w,
                              Vec2* r, Mat26* jc, Mat23* jl) const {
  if (!o.plane) return reprojection_residual(camera_, R_cw, t_cw, p_w, o.uv_px, r, jc, jl);
  // the plane's one residual in the first row; the second row is zero
  double e = 0.0;
  Eigen::Matrix<double, 1, 6> dpose;
  Eigen::Matrix<double, 1, 3> dpoint;
  if (!plane_residual(R_cw, t_cw, p_w, o.normal, o.offset, &e, jc ? &dpose : nullptr, jl ? &dpoint : nullptr)) return false;
  *r = Vec2(e, 0.0);
  if (jc != nullptr) {
    jc->row(0) = dpose;
    jc->row(1).setZero();
  }
  if (jl != nullptr) {
    jl->row(0) = dpoint;
    jl->row(1).setZero();
  }
  return true;
}

void BundleAdjuster::add_centre_prior(int pose, const Vec3& centre_w, double sigma, const RobustKernel& kernel) {
  if (pose < 0 || pose >= num_poses() || !centre_w.allFinite() || !(sigma > 0.0) || !std::isfinite(sigma)) {
    bad_prior_ = true;
    return;
  }
  const double information = 1.0 / (sigma * sigma);
  priors_.push_back({pose, centre_w, information, kernel});
}

void BundleAdjuster::add_rotation_prior(int pose, const geometry::Mat3& R_cw_target, double sigma_rad,
                                        const RobustKernel& kernel) {
  if (pose < 0 || pose >= num_poses() || !R_cw_target.allFinite() || !(sigma_rad > 0.0) || !std::isfinite(sigma_rad)) {
    bad_prior_ = true;
    return;
  }
  rotation_priors_.push_back({pose, R_cw_target, 1.0 / (sigma_rad * sigma_rad), kernel});
}

Status BundleAdjuster::validate() const {
  const geometry::CameraIntrinsics& k = camera_.intrinsics();
  if (!(k.fx > 0.0) || !(k.fy > 0.0)) return invalid_argument("bundle adjustment: no valid camera (reset() with Camera::create's)");
  if (bad_prior_)
    return invalid_argument("bundle adjustment: a centre or rotation prior has an unknown pose, a non-finite target or a sigma <= 0");
  if (first_bad_observation_ >= 0) {
    return invalid_argument("bundle adjustment: observation " + std::to_string(first_bad_observation_) +
                            " has an unknown pose or point index, a non-finite pixel, a non-positive information or a bad kernel threshold");
  }
  for (int i = 0; i < num_poses(); ++i) {
    if (!poses_[i].translation().allFinite() || !poses_[i].so3().quaternion().coeffs().allFinite()) {
      return invalid_argument("bundle adjustment: pose " + std::to_string(i) + " is not finite");
    }
  }
  for (int j = 0; j < num_points(); ++j) {
    if (!points_[j].allFinite()) return invalid_argument("bundle adjustment: point " + std::to_string(j) + " is not finite");
  }
  return Status();
}

double BundleAdjuster::evaluate(const std::vector<SE3>& poses, const std::vector<Vec3>& points, bool use_kernel,
                                Linearisation* lin) {
  for (std::size_t i = 0; i < poses.size(); ++i) rotation_[i] = poses[i].rotation();
  double cost = 0.0;
  for (const CentrePriorTerm& p : priors_) {
    const Vec3 e = centre_residual(rotation_[p.pose], poses[p.pose].translation(), p.centre_w);
    cost += 0.5 * p.kernel.rho(p.information * e.squaredNorm());
  }
  for (const RotationPriorTerm& p : rotation_priors_) {
    const Vec3 e = rotation_residual(rotation_[p.pose], p.R_target);
    cost += 0.5 * p.kernel.rho(p.information * e.squaredNorm());
  }
  for (std::size_t k = 0; k < obs_.size(); ++k) {
    const Observation& o = obs_[k];
    if (!inlier_[k]) {
      lin->w[k] = 0.0;
      continue;
    }
    const bool pose_free = free_pose_[o.pose] >= 0, point_free = free_point_[o.point] >= 0;
    if (!residual(o, rotation_[o.pose], poses[o.pose].translation(), points[o.point], &lin->r[k],
                  pose_free ? &lin->jc[k] : nullptr, point_free ? &lin->jl[k] : nullptr)) {
      return std::numeric_limits<double>::infinity();
    }
    const double s = o.information * lin->r[k].squaredNorm();
    double rho = s, weight = 1.0;
    if (use_kernel) o.kernel.evaluate(s, &rho, &weight);
    cost += 0.5 * rho;
    lin->w[k] = o.information * weight;
  }
  return cost;
}

int BundleAdjuster::classify(double chi2_gate) {
  int inliers = 0;
  for (std::size_t k = 0; k < obs_.size(); ++k) {
    if (!inlier_[k]) continue;
    const Observation& o = obs_[k];
    Vec2 r;
    const bool in_front = residual(o, poses_[o.pose].rotation(), poses_[o.pose].translation(), points_[o.point], &r, nullptr, nullptr);
    inlier_[k] = in_front && o.information * r.squaredNorm() <= chi2_gate ? 1 : 0;
    inliers += inlier_[k];
  }
  return inliers;
}

namespace {

// One observation's share of a variable's normal equations, for its 2 x N Jacobian j and IRLS
// weight w: the upper triangle of h += j^T (w j) (the Schur system reads no other part of a
// Hessian block) and g += (w j)^T r. Written out on the raw column-major arrays (w j computed
// once, each entry of h and g read and written once): fewer instructions than Eigen's expressions
// on ARM, and the same sums (each a two-term sum, so the same bits).
template <int N>
void add_normal_equations(Eigen::Matrix<double, N, N>& h, Eigen::Matrix<double, N, 1>& g,
                          const Eigen::Matrix<double, 2, N>& j, double w, const Vec2& r, double* __restrict wj_out) {
  double jv[2 * N], wj[2 * N];
#pragma GCC unroll 12
  for (int i = 0; i < 2 * N; ++i) {
    jv[i] = j.data()[i];
    wj[i] = w * jv[i];
  }
  double* __restrict hp = h.data();
  double* __restrict gp = g.data();
  const double r0 = r[0], r1 = r[1];
#pragma GCC unroll 6
  for (int c = 0; c < N; ++c) {
#pragma GCC unroll 6
    for (int row = 0; row <= c; ++row) hp[N * c + row] += jv[2 * row] * wj[2 * c] + jv[2 * row + 1] * wj[2 * c + 1];
    gp[c] += wj[2 * c] * r0 + wj[2 * c + 1] * r1;
  }
#pragma GCC unroll 12
  for (int i = 0; i < 2 * N; ++i) wj_out[i] = wj[i];
}

// The coupling block out = a^T b of an observation (a: 2 x A, b: 2 x B, out: A x B).
template <int A, int B>
void coupling_block(Eigen::Matrix<double, A, B>& out, const double* __restrict a, const double* __restrict b) {
  double* __restrict o = out.data();
#pragma GCC unroll 6
  for (int c = 0; c < B; ++c) {
#pragma GCC unroll 6
    for (int row = 0; row < A; ++row) o[A * c + row] = a[2 * row] * b[2 * c] + a[2 * row + 1] * b[2 * c + 1];
  }
}

}  // namespace

template <int E, int K>
void BundleAdjuster::accumulate(internal::SchurSystem<E, K>* s) const {
  constexpr bool kPointsElim = E == 3;
  s->zero_values();
  for (std::size_t k = 0; k < obs_.size(); ++k) {
    const double w = lin_.w[k];
    const int ip = free_pose_[obs_[k].pose], jl = free_point_[obs_[k].point];
    if (w == 0.0) {
      if (ip >= 0 && jl >= 0) s->hek[k].setZero();
      continue;
    }
    const Vec2& r = lin_.r[k];
    double wjc[12], wjl[6];
    if (ip >= 0) {
      Eigen::Matrix<double, 6, 6>& h = [&]() -> Eigen::Matrix<double, 6, 6>& {
        if constexpr (kPointsElim) return s->hkk[ip]; else return s->hee[ip];
      }();
      Vec6& g = [&]() -> Vec6& {
        if constexpr (kPointsElim) return s->gk[ip]; else return s->ge[ip];
      }();
      add_normal_equations(h, g, lin_.jc[k], w, r, wjc);
      if (jl >= 0) {
        if constexpr (kPointsElim) {
          coupling_block(s->hek[k], lin_.jl[k].data(), wjc);
        } else {
          coupling_block(s->hek[k], wjc, lin_.jl[k].data());
        }
      }
    }
    if (jl >= 0) {
      geometry::Mat3& h = [&]() -> geometry::Mat3& {
        if constexpr (kPointsElim) return s->hee[jl]; else return s->hkk[jl];
      }();
      Vec3& g = [&]() -> Vec3& {
        if constexpr (kPointsElim) return s->ge[jl]; else return s->gk[jl];
      }();
      add_normal_equations(h, g, lin_.jl[k], w, r, wjl);
    }
  }
  // a free pose's blocks of the normal equations and of the gradient, on either side
  auto pose_h = [&](int ip) -> Eigen::Matrix<double, 6, 6>& {
    if constexpr (kPointsElim) return s->hkk[ip]; else return s->hee[ip];
  };
  auto pose_g = [&](int ip) -> Vec6& {
    if constexpr (kPointsElim) return s->gk[ip]; else return s->ge[ip];
  };
  for (const CentrePriorTerm& p : priors_) {
    const int ip = free_pose_[p.pose];
    if (ip < 0) continue;
    const geometry::Mat3 R = poses_[p.pose].rotation();
    const Vec3 e = centre_residual(R, poses_[p.pose].translation(), p.centre_w);
    add_centre_normal_equations(pose_h(ip), pose_g(ip), R, e, p.information * p.kernel.weight(p.information * e.squaredNorm()));
  }
  for (const RotationPriorTerm& p : rotation_priors_) {
    const int ip = free_pose_[p.pose];
    if (ip < 0) continue;
    const Vec3 e = rotation_residual(poses_[p.pose].rotation(), p.R_target);
    add_rotation_normal_equations(pose_h(ip), pose_g(ip), e, p.information * p.kernel.weight(p.information * e.squaredNorm()));
  }
}

template <int E, int K>
void BundleAdjuster::apply_step(const std::vector<Eigen::Matrix<double, E, 1>>& dxe,
                                const std::vector<Eigen::Matrix<double, K, 1>>& dxk, double* step_norm) {
  constexpr bool kPointsElim = E == 3;
  double n2 = 0.0;
  for (int i = 0; i < num_poses(); ++i) {
    const int f = free_pose_[i];
    if (f < 0) {
      poses_candidate_[i] = poses_[i];
      continue;
    }
    Vec6 d;
    if constexpr (kPointsElim) {
      d = dxk[f];
    } else {
      d = dxe[f];
    }
    n2 += d.squaredNorm();
    poses_candidate_[i] = SE3::exp(d) * poses_[i];
  }
  for (int j = 0; j < num_points(); ++j) {
    const int f = free_point_[j];
    if (f < 0) {
      points_candidate_[j] = points_[j];
      continue;
    }
    Vec3 d;
    if constexpr (kPointsElim) {
      d = dxe[f];
    } else {
      d = dxk[f];
    }
    n2 += d.squaredNorm();
    points_candidate_[j] = points_[j] + d;
  }
  *step_norm = std::sqrt(n2);
}

double BundleAdjuster::state_norm() const {
  double n2 = 0.0;
  for (int i = 0; i < num_poses(); ++i) {
    if (free_pose_[i] < 0) continue;
    const Eigen::Quaterniond& q = poses_[i].so3().quaternion();
    const double angle = 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
    n2 += poses_[i].translation().squaredNorm() + angle * angle;
  }
  for (int j = 0; j < num_points(); ++j) {
    if (free_point_[j] >= 0) n2 += points_[j].squaredNorm();
  }
  return std::sqrt(n2);
}

template <int E, int K>
BaSummary BundleAdjuster::run(internal::SchurSystem<E, K>* s, const BaOptions& options) {
  std::vector<Eigen::Matrix<double, E, 1>>& dxe = [&]() -> auto& {
    if constexpr (E == 3) return dx3_; else return dx6_;
  }();
  std::vector<Eigen::Matrix<double, K, 1>>& dxk = [&]() -> auto& {
    if constexpr (K == 3) return dx3_; else return dx6_;
  }();
  BaSummary sum;
  sum.points_eliminated = E == 3;
  sum.sparse = s->sparse();
  sum.reduced_dim = s->reduced_dim();
  const int n_params = 6 * n_free_poses_ + 3 * n_free_points_;
  LmController lm;
  for (int pass = 0; pass < std::max(1, options.passes); ++pass) {
    if (pass > 0) {
      const int inliers = classify(options.chi2_gate);
      if (2 * inliers < n_params || inliers == 0) {
        sum.status = invalid_argument("bundle adjustment: " + std::to_string(inliers) +
                                      " inlier observations left after outlier removal for " +
                                      std::to_string(n_params) + " parameters");
        break;
      }
    }
    const bool use_kernel = pass == 0 || options.robust_after_first_pass;
    const double cost = evaluate(poses_, points_, use_kernel, &lin_);
    accumulate(s);
    LmOptions lm_options = options.lm;
    if (pass == 0 && options.passes > 1 && options.first_pass_iterations > 0)
      lm_options.max_iterations = std::min(lm_options.max_iterations, options.first_pass_iterations);
    if (pass == 0 && options.passes > 1)
      lm_options.function_tolerance = std::max(lm_options.function_tolerance, options.first_pass_function_tolerance);
    lm.start(lm_options, cost, s->gradient_max());
    if (pass == 0) sum.initial_cost = cost;
    while (!lm.done()) {
      double predicted = 0.0, step_norm = 0.0;
      if (!s->solve(lm, &dxe, &dxk, &predicted)) {
        lm.report_failed_step();
        continue;
      }
      apply_step<E, K>(dxe, dxk, &step_norm);
      const double new_cost = evaluate(poses_candidate_, points_candidate_, use_kernel, &lin_candidate_);
      if (lm.report_step(new_cost, predicted, step_norm, state_norm())) {
        poses_.swap(poses_candidate_);
        points_.swap(points_candidate_);
        lin_.swap(lin_candidate_);
        accumulate(s);
        lm.set_gradient(s->gradient_max());
      }
    }
    sum.iterations += lm.iterations();
    sum.passes = pass + 1;
    sum.stop = lm.stop();
    sum.final_cost = lm.cost();
  }
  if (options.chi2_gate > 0.0) classify(options.chi2_gate);
  for (std::uint8_t f : inlier_) sum.inliers += f;
  sum.outliers = num_observations() - sum.inliers;
  if (sum.status.ok()) {
    if (sum.stop == LmStop::kNumericalFailure) {
      sum.status = internal_error("bundle adjustment: non-finite cost or gradient");
    } else if (sum.stop == LmStop::kMaxIterations) {
      sum.status = Status(StatusCode::kNotConverged, "bundle adjustment: not converged within " +
                                                          std::to_string(options.lm.max_iterations) + " iterations");
    }
  }
  return sum;
}

BaSummary BundleAdjuster::solve(const BaOptions& options) {
  BaSummary early;
  if (Status st = validate(); !st.ok()) {
    early.status = st;
    return early;
  }
  const std::size_t n_obs = obs_.size();
  grow_resize(free_pose_, poses_.size());
  grow_resize(free_point_, points_.size());
  n_free_poses_ = n_free_points_ = 0;
  for (std::size_t i = 0; i < poses_.size(); ++i) free_pose_[i] = pose_fixed_[i] ? -1 : n_free_poses_++;
  for (std::size_t j = 0; j < points_.size(); ++j) free_point_[j] = point_fixed_[j] ? -1 : n_free_points_++;
  grow_resize(poses_candidate_, poses_.size());
  grow_resize(points_candidate_, points_.size());
  grow_resize(rotation_, poses_.size());
  lin_.resize(n_obs);
  lin_candidate_.resize(n_obs);
  grow_assign(inlier_, n_obs, std::uint8_t{1});
  // Observations that cannot be projected at the start (behind the camera) are outliers.
  int inliers = 0;
  for (std::size_t k = 0; k < n_obs; ++k) {
    Vec2 r;
    const Observation& o = obs_[k];
    inlier_[k] = residual(o, poses_[o.pose].rotation(), poses_[o.pose].translation(), points_[o.point], &r, nullptr, nullptr) ? 1 : 0;
    inliers += inlier_[k];
  }
  const int n_params = 6 * n_free_poses_ + 3 * n_free_points_;
  if (n_params == 0) {
    early.status = invalid_argument("bundle adjustment: every pose and point is fixed");
    return early;
  }
  if (2 * inliers < n_params) {
    early.status = invalid_argument("bundle adjustment: too few observations (" + std::to_string(inliers) +
                                    " in front of their cameras, " + std::to_string(2 * inliers) +
                                    " residuals for " + std::to_string(n_params) + " parameters)");
    return early;
  }

  bool points_elim = true;
  if (options.elimination == SchurElimination::kPoses) {
    points_elim = false;
  } else if (options.elimination == SchurElimination::kAuto) {
    points_elim = 6 * n_free_poses_ <= 3 * n_free_points_;
  }
  grow_resize(term_elim_, n_obs);
  grow_resize(term_keep_, n_obs);
  for (std::size_t k = 0; k < n_obs; ++k) {
    const int ip = free_pose_[obs_[k].pose], jl = free_point_[obs_[k].point];
    term_elim_[k] = points_elim ? jl : ip;
    term_keep_[k] = points_elim ? ip : jl;
  }
  const int n_elim = points_elim ? n_free_points_ : n_free_poses_;
  const int n_keep = points_elim ? n_free_poses_ : n_free_points_;
  const int kind = points_elim ? 0 : 1;
  if (kind != analysed_kind_ || options.dense_max_dim != analysed_dense_max_dim_ || n_elim != analysed_n_elim_ ||
      n_keep != analysed_n_keep_ || term_elim_ != analysed_elim_ || term_keep_ != analysed_keep_) {
    if (points_elim) {
      points_eliminated_.analyse(n_elim, n_keep, term_elim_, term_keep_, options.dense_max_dim);
    } else {
      poses_eliminated_.analyse(n_elim, n_keep, term_elim_, term_keep_, options.dense_max_dim);
    }
    analysed_kind_ = kind;
    analysed_dense_max_dim_ = options.dense_max_dim;
    analysed_n_elim_ = n_elim;
    analysed_n_keep_ = n_keep;
    grow_copy(analysed_elim_, term_elim_);
    grow_copy(analysed_keep_, term_keep_);
  }
  return points_elim ? run(&points_eliminated_, options) : run(&poses_eliminated_, options);
}

}  // namespace ale::optim
