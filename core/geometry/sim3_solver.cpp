#include "core/geometry/sim3_solver.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace ale::geometry {

namespace {

// A point set is degenerate when its scatter's middle eigenvalue is below this share of the
// largest (spread across the line below 1e-5 of the spread along it): the rotation about the
// line is then fixed by rounding and noise, not by the data.
constexpr double kCollinearRatio = 1e-10;

enum class FitError { kOk, kDegenerateX, kDegenerateY, kNoWeight, kBadScale };

bool scatter_degenerate(const Mat3& scatter) {
  // The iterative solver: computeDirect's closed-form cubic loses half the digits of a double
  // eigenvalue, which is exactly the collinear case (two zeros).
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(scatter, Eigen::EigenvaluesOnly);
  const Vec3 ev = eig.eigenvalues();  // ascending
  return !(ev[2] > 0.0) || !(ev[1] > kCollinearRatio * ev[2]);
}

// Umeyama's closed form over n matches given by get(i, &x, &y, &w); no allocation.
template <class Get>
FitError fit_closed_form(int n, Get get, bool with_scale, Sim3* out) {
  double w_sum = 0.0;
  Vec3 mean_x = Vec3::Zero(), mean_y = Vec3::Zero();
  Vec3 xi, yi;
  double wi;
  for (int i = 0; i < n; ++i) {
    get(i, &xi, &yi, &wi);
    w_sum += wi;
    mean_x += wi * xi;
    mean_y += wi * yi;
  }
  if (!(w_sum > 0.0)) return FitError::kNoWeight;
  mean_x /= w_sum;
  mean_y /= w_sum;
  Mat3 scatter_x = Mat3::Zero(), scatter_y = Mat3::Zero(), cov_yx = Mat3::Zero();
  for (int i = 0; i < n; ++i) {
    get(i, &xi, &yi, &wi);
    const Vec3 dx = xi - mean_x, dy = yi - mean_y;
    scatter_x += wi * dx * dx.transpose();
    scatter_y += wi * dy * dy.transpose();
    cov_yx += wi * dy * dx.transpose();
  }
  scatter_x /= w_sum;
  scatter_y /= w_sum;
  cov_yx /= w_sum;
  if (scatter_degenerate(scatter_x)) return FitError::kDegenerateX;
  if (scatter_degenerate(scatter_y)) return FitError::kDegenerateY;

  const Eigen::JacobiSVD<Mat3> svd(cov_yx, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Vec3 sign(1.0, 1.0, 1.0);
  // U V^T would be a reflection: flip the weakest axis (Umeyama's S).
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) sign[2] = -1.0;
  const Mat3 r = svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose();
  double scale = 1.0;
  if (with_scale) {
    scale = svd.singularValues().dot(sign) / scatter_x.trace();
    if (!(scale > 0.0) || !std::isfinite(scale)) return FitError::kBadScale;
  }
  // r is orthonormal to rounding already: no second orthonormalisation.
  const SO3 rot{Eigen::Quaterniond(r)};
  *out = Sim3(rot, mean_y - scale * (rot * mean_x), scale);
  return FitError::kOk;
}

const char* describe(FitError e) {
  switch (e) {
    case FitError::kOk: return "ok";
    case FitError::kDegenerateX: return "the x points are degenerate (all on one line or at one point)";
    case FitError::kDegenerateY: return "the y points are degenerate (all on one line or at one point)";
    case FitError::kNoWeight: return "the weights sum to 0";
    case FitError::kBadScale: return "no positive scale fits (the point sets do not correspond)";
  }
  return "?";
}

bool finite3(const Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

Status check_matches(const std::vector<Vec3>& x, const std::vector<Vec3>& y) {
  if (x.size() != y.size())
    return invalid_argument("sim3: " + std::to_string(x.size()) + " x points but " + std::to_string(y.size()) +
                            " y points");
  if (x.size() < 3) return invalid_argument("sim3: needs at least 3 matches, got " + std::to_string(x.size()));
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!finite3(x[i]) || !finite3(y[i])) return invalid_argument("sim3: match " + std::to_string(i) + " is not finite");
  return Status::ok_status();
}

// The RANSAC problem (ransac.h's contract) over the caller's matches.
class Sim3Problem {
 public:
  static constexpr int kSampleSize = 3;
  static constexpr int kMaxModels = 1;
  using Model = Sim3;

  Sim3Problem(const std::vector<Vec3>& x, const std::vector<Vec3>& y, const Sim3RansacParams& p)
      : x_(x), y_(y), with_scale_(p.with_scale), inv_gate_y_(1.0 / p.max_error_y),
        inv_gate_x_(p.max_error_x > 0.0 ? 1.0 / p.max_error_x : 0.0) {}

  int size() const { return static_cast<int>(x_.size()); }

  int fit(const int* sample, Sim3* model) const {
    const auto get = [&](int i, Vec3* xi, Vec3* yi, double* wi) {
      *xi = x_[static_cast<std::size_t>(sample[i])];
      *yi = y_[static_cast<std::size_t>(sample[i])];
      *wi = 1.0;
    };
    return fit_closed_form(kSampleSize, get, with_scale_, model) == FitError::kOk ? 1 : 0;
  }

  // MSAC: inliers score 1 - (e / gate)^2 with the tighter of the two normalised errors.
  double score(const Sim3& s, std::uint8_t* mask, int* inliers) const {
    const Mat3 sr = s.scale() * s.rotation();
    const Vec3& t = s.translation();
    const double inv_s = 1.0 / s.scale();
    double total = 0.0;
    int count = 0;
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const double e = (y_[i] - (sr * x_[i] + t)).norm();
      double normalised = e * inv_gate_y_;
      if (inv_gate_x_ > 0.0) normalised = std::max(normalised, e * inv_s * inv_gate_x_);
      const bool in = normalised < 1.0;
      mask[i] = in ? 1 : 0;
      if (in) {
        total += 1.0 - normalised * normalised;
        ++count;
      }
    }
    *inliers = count;
    return total;
  }

 private:
  const std::vector<Vec3>& x_;
  const std::vector<Vec3>& y_;
  bool with_scale_;
  double inv_gate_y_, inv_gate_x_;
};

}  // namespace

Result<Sim3> umeyama(const std::vector<Vec3>& x, const std::vector<Vec3>& y, bool with_scale,
                     const std::vector<double>& weights) {
  ALE_RETURN_IF_ERROR(check_matches(x, y));
  if (!weights.empty()) {
    if (weights.size() != x.size())
      return invalid_argument("sim3: " + std::to_string(weights.size()) + " weights for " + std::to_string(x.size()) +
                              " matches");
    for (std::size_t i = 0; i < weights.size(); ++i)
      if (!(weights[i] >= 0.0) || !std::isfinite(weights[i]))
        return invalid_argument("sim3: weight " + std::to_string(i) + " is negative or not finite");
  }
  const auto get = [&](int i, Vec3* xi, Vec3* yi, double* wi) {
    const auto k = static_cast<std::size_t>(i);
    *xi = x[k];
    *yi = y[k];
    *wi = weights.empty() ? 1.0 : weights[k];
  };
  Sim3 s;
  const FitError e = fit_closed_form(static_cast<int>(x.size()), get, with_scale, &s);
  if (e != FitError::kOk) return invalid_argument(std::string("sim3: ") + describe(e));
  return s;
}

Status solve_sim3_ransac(const std::vector<Vec3>& x, const std::vector<Vec3>& y, const Sim3RansacParams& params,
                         Sim3RansacResult* result, Sim3Scratch& scratch) {
  ALE_RETURN_IF_ERROR(check_matches(x, y));
  if (!(params.max_error_y > 0.0) || !std::isfinite(params.max_error_y))
    return invalid_argument("sim3 ransac: max_error_y must be positive, got " + std::to_string(params.max_error_y));
  if (!(params.max_error_x >= 0.0) || !std::isfinite(params.max_error_x))
    return invalid_argument("sim3 ransac: max_error_x must be 0 (off) or positive, got " +
                            std::to_string(params.max_error_x));
  // Whole-set degeneracy is the caller's problem, not bad luck in sampling: say so.
  {
    const auto get = [&](int i, Vec3* xi, Vec3* yi, double* wi) {
      *xi = x[static_cast<std::size_t>(i)];
      *yi = y[static_cast<std::size_t>(i)];
      *wi = 1.0;
    };
    Sim3 all;
    const FitError e = fit_closed_form(static_cast<int>(x.size()), get, params.with_scale, &all);
    if (e == FitError::kDegenerateX || e == FitError::kDegenerateY)
      return invalid_argument(std::string("sim3 ransac: ") + describe(e));
  }

  const Sim3Problem problem(x, y, params);
  const int min_inliers = std::max(params.min_inliers, Sim3Problem::kSampleSize);
  Sim3RansacResult& r = *result;
  ALE_RETURN_IF_ERROR(ransac(problem, params.ransac, min_inliers, &r.S_yx, r.inlier_mask, &r.stats, scratch.ransac));

  // Refinement: the closed form over all inliers of the best model, kept while it scores no
  // worse (local optimisation in the sense of LO-RANSAC, without the random inner samples).
  double best_score = r.stats.score;
  int best_inliers = r.stats.inliers;
  scratch.mask.resize(x.size());
  for (int round = 0; round < params.refine_rounds; ++round) {
    scratch.x_in.clear();
    scratch.y_in.clear();
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (!r.inlier_mask[i]) continue;
      scratch.x_in.push_back(x[i]);
      scratch.y_in.push_back(y[i]);
    }
    const auto get = [&](int i, Vec3* xi, Vec3* yi, double* wi) {
      *xi = scratch.x_in[static_cast<std::size_t>(i)];
      *yi = scratch.y_in[static_cast<std::size_t>(i)];
      *wi = 1.0;
    };
    Sim3 refined;
    if (fit_closed_form(static_cast<int>(scratch.x_in.size()), get, params.with_scale, &refined) != FitError::kOk)
      break;
    int inliers = 0;
    const double score = problem.score(refined, scratch.mask.data(), &inliers);
    if (score < best_score) break;
    const bool same_set = std::equal(scratch.mask.begin(), scratch.mask.end(), r.inlier_mask.begin());
    r.S_yx = refined;
    r.inlier_mask.swap(scratch.mask);
    best_score = score;
    best_inliers = inliers;
    if (same_set) break;
  }

  r.inliers = best_inliers;
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (r.inlier_mask[i]) sum_sq += (y[i] - r.S_yx * x[i]).squaredNorm();
  r.rms_error_y = r.inliers > 0 ? std::sqrt(sum_sq / r.inliers) : 0.0;
  if (r.inliers < min_inliers)
    return not_found("sim3 ransac: " + std::to_string(r.inliers) + " inliers after refinement, " +
                     std::to_string(min_inliers) + " needed");
  return Status::ok_status();
}

}  // namespace ale::geometry
