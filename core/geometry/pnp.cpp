#include "core/geometry/pnp.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

namespace ale::geometry {

const char* to_string(PnpFailure failure) {
  switch (failure) {
    case PnpFailure::kNone: return "none";
    case PnpFailure::kTooFewPoints: return "too few points";
    case PnpFailure::kInvalidInput: return "invalid input";
    case PnpFailure::kDegenerate: return "degenerate configuration";
    case PnpFailure::kNoConsensus: return "no consensus";
    case PnpFailure::kNotConverged: return "not converged";
  }
  return "unknown";
}

namespace {

// ---- P3P ----

// Real roots of c3 x^3 + c2 x^2 + c1 x + c0 (coefficients of comparable size), polished by
// Newton steps on the original polynomial. Returns how many (0..3).
int real_cubic_roots(double c3, double c2, double c1, double c0, double roots[3]) {
  const double scale = std::max({std::abs(c3), std::abs(c2), std::abs(c1), std::abs(c0)});
  if (!(scale > 0.0) || !std::isfinite(scale)) return 0;
  int n = 0;
  if (std::abs(c3) < 1e-12 * scale) {
    // Effectively quadratic: the cubic's third root went to infinity.
    if (std::abs(c2) < 1e-12 * scale) {
      if (std::abs(c1) < 1e-12 * scale) return 0;
      roots[n++] = -c0 / c1;
    } else {
      const double disc = c1 * c1 - 4.0 * c2 * c0;
      if (disc < 0.0) return 0;
      const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
      roots[n++] = q / c2;
      if (q != 0.0) roots[n++] = c0 / q;
    }
  } else {
    const double a = c2 / c3, b = c1 / c3, c = c0 / c3;
    // x = t - a/3: t^3 + p t + q = 0.
    const double p = b - a * a / 3.0;
    const double q = 2.0 * a * a * a / 27.0 - a * b / 3.0 + c;
    const double shift = -a / 3.0;
    const double disc = 0.25 * q * q + p * p * p / 27.0;
    if (disc > 0.0) {
      const double s = std::sqrt(disc);
      // u = cbrt(-q/2 -+ s) with the sign that avoids cancellation; v = -p / (3u).
      const double u = std::cbrt(-0.5 * q + (q < 0.0 ? s : -s));
      const double v = u != 0.0 ? -p / (3.0 * u) : 0.0;
      roots[n++] = u + v + shift;
    } else {
      const double m = 2.0 * std::sqrt(std::max(-p / 3.0, 0.0));
      if (m == 0.0) {
        roots[n++] = shift;
      } else {
        const double arg = std::clamp(3.0 * q / (p * m), -1.0, 1.0);
        const double theta = std::acos(arg) / 3.0;
        constexpr double kTwoPiThirds = 2.0943951023931954923;
        for (int k = 0; k < 3; ++k) roots[n++] = m * std::cos(theta - kTwoPiThirds * k) + shift;
      }
    }
  }
  for (int i = 0; i < n; ++i) {
    double x = roots[i];
    for (int it = 0; it < 3; ++it) {
      const double f = ((c3 * x + c2) * x + c1) * x + c0;
      const double df = (3.0 * c3 * x + 2.0 * c2) * x + c1;
      if (df == 0.0) break;
      const double next = x - f / df;
      if (!std::isfinite(next)) break;
      x = next;
    }
    roots[i] = x;
  }
  return n;
}

double det3(const Vec3& a, const Vec3& b, const Vec3& c) { return a.dot(b.cross(c)); }

// Residuals of the three distance equations and their Jacobian in lambda.
struct DistanceEquations {
  double b12, b13, b23, a12, a13, a23;
  Vec3 residual(const Vec3& l) const {
    return Vec3(l(0) * l(0) + l(1) * l(1) - 2.0 * b12 * l(0) * l(1) - a12,
                l(0) * l(0) + l(2) * l(2) - 2.0 * b13 * l(0) * l(2) - a13,
                l(1) * l(1) + l(2) * l(2) - 2.0 * b23 * l(1) * l(2) - a23);
  }
  Mat3 jacobian(const Vec3& l) const {
    Mat3 J;
    J << 2.0 * (l(0) - b12 * l(1)), 2.0 * (l(1) - b12 * l(0)), 0.0,  //
        2.0 * (l(0) - b13 * l(2)), 0.0, 2.0 * (l(2) - b13 * l(0)),   //
        0.0, 2.0 * (l(1) - b23 * l(2)), 2.0 * (l(2) - b23 * l(1));
    return J;
  }
  // Gauss-Newton (square system: Newton) steps, kept only while they reduce the residual.
  void refine(Vec3* l) const {
    double err = residual(*l).squaredNorm();
    for (int it = 0; it < 5 && err > 0.0; ++it) {
      const Mat3 J = jacobian(*l);
      const Eigen::PartialPivLU<Mat3> lu(J);
      if (!(std::abs(lu.determinant()) > 0.0)) break;
      const Vec3 next = *l - lu.solve(residual(*l));
      const double next_err = residual(next).squaredNorm();
      if (!(next_err < err)) break;
      *l = next;
      err = next_err;
    }
  }
};

// Rays lambda = alpha u + beta w in the plane with normal n (unit) on the conic lambda^T D
// lambda = 0, with all three components positive; scaled by the distance equation that is best
// conditioned. Appends to out (at most 2).
int rays_on_plane(const Vec3& n, const Mat3& D, const DistanceEquations& eq, Vec3* out) {
  // Any vector not parallel to n gives a basis of the plane.
  const int k = n.cwiseAbs().minCoeff() == std::abs(n(0)) ? 0 : (n.cwiseAbs().minCoeff() == std::abs(n(1)) ? 1 : 2);
  const Vec3 u = n.cross(Vec3::Unit(k)).normalized();
  const Vec3 w = n.cross(u);
  const double q00 = u.dot(D * u), q01 = u.dot(D * w), q11 = w.dot(D * w);
  const double qs = std::max({std::abs(q00), std::abs(q01), std::abs(q11)});
  if (!(qs > 0.0)) return 0;  // the whole plane lies on the conic: no isolated rays
  double disc = q01 * q01 - q00 * q11;
  if (disc < -1e-12 * qs * qs) return 0;
  disc = std::sqrt(std::max(disc, 0.0));
  Vec2 dirs[2];
  int nd = 0;
  // q00 a^2 + 2 q01 a b + q11 b^2 = 0, solved for the ratio whose leading coefficient is larger.
  const double kk = -(q01 + std::copysign(disc, q01));
  if (std::abs(q00) >= std::abs(q11)) {
    dirs[nd++] = Vec2(kk / q00, 1.0);
    if (kk != 0.0 && disc > 0.0) dirs[nd++] = Vec2(q11 / kk, 1.0);
  } else {
    dirs[nd++] = Vec2(1.0, kk / q11);
    if (kk != 0.0 && disc > 0.0) dirs[nd++] = Vec2(1.0, q00 / kk);
  }
  int count = 0;
  for (int i = 0; i < nd; ++i) {
    Vec3 d = dirs[i](0) * u + dirs[i](1) * w;
    if (d.sum() < 0.0) d = -d;
    d.normalize();
    if (!(d.minCoeff() > 0.0)) continue;
    const double den12 = d(0) * d(0) + d(1) * d(1) - 2.0 * eq.b12 * d(0) * d(1);
    const double den13 = d(0) * d(0) + d(2) * d(2) - 2.0 * eq.b13 * d(0) * d(2);
    const double den23 = d(1) * d(1) + d(2) * d(2) - 2.0 * eq.b23 * d(1) * d(2);
    double num = eq.a12, den = den12;
    if (den13 > den) num = eq.a13, den = den13;
    if (den23 > den) num = eq.a23, den = den23;
    if (!(den > 0.0)) continue;
    Vec3 l = std::sqrt(num / den) * d;
    eq.refine(&l);
    if (l.allFinite() && l.minCoeff() > 0.0) out[count++] = l;
  }
  return count;
}

}  // namespace

int solve_p3p(const Vec3 bearings[3], const Vec3 points_w[3], SE3 poses_cw[4]) {
  for (int i = 0; i < 3; ++i) {
    if (!bearings[i].allFinite() || !points_w[i].allFinite() || !(bearings[i].squaredNorm() > 0.0)) return 0;
  }
  const Vec3 y1 = bearings[0].normalized(), y2 = bearings[1].normalized(), y3 = bearings[2].normalized();
  const Vec3& x1 = points_w[0];
  const Vec3 d12 = x1 - points_w[1], d13 = x1 - points_w[2], d23 = points_w[1] - points_w[2];
  const Vec3 n_x = d12.cross(d13);
  // Collinear or coincident points: the rotation about their line is not determined.
  if (!(n_x.squaredNorm() > 1e-20 * d12.squaredNorm() * d13.squaredNorm())) return 0;

  DistanceEquations eq{y1.dot(y2), y1.dot(y3), y2.dot(y3), d12.squaredNorm(), d13.squaredNorm(), d23.squaredNorm()};
  Mat3 M12, M13, M23;
  M12 << 1.0, -eq.b12, 0.0, -eq.b12, 1.0, 0.0, 0.0, 0.0, 0.0;
  M13 << 1.0, 0.0, -eq.b13, 0.0, 0.0, 0.0, -eq.b13, 0.0, 1.0;
  M23 << 0.0, 0.0, 0.0, 0.0, 1.0, -eq.b23, 0.0, -eq.b23, 1.0;
  // lambda^T M_ij lambda = a_ij; eliminating the right-hand sides gives two homogeneous
  // conics, scaled to unit norm so that the pencil parameter is of order one.
  Mat3 D1 = eq.a23 * M12 - eq.a12 * M23;
  Mat3 D2 = eq.a23 * M13 - eq.a13 * M23;
  D1 /= D1.norm();
  D2 /= D2.norm();

  // det(D1 + g D2) as a cubic in g, column by column.
  const Vec3 A0 = D1.col(0), A1 = D1.col(1), A2 = D1.col(2);
  const Vec3 B0 = D2.col(0), B1 = D2.col(1), B2 = D2.col(2);
  const double c3 = det3(B0, B1, B2);
  const double c2 = det3(A0, B1, B2) + det3(B0, A1, B2) + det3(B0, B1, A2);
  const double c1 = det3(B0, A1, A2) + det3(A0, B1, A2) + det3(A0, A1, B2);
  const double c0 = det3(A0, A1, A2);
  double gammas[3];
  const int n_gamma = real_cubic_roots(c3, c2, c1, c0, gammas);

  // Of the singular members, the best-conditioned pair of real planes: eigenvalues e0 < 0 < e2
  // around the (near) zero e1, with the smaller of |e0|, e2 as large as possible.
  double best_cond = 0.0;
  Mat3 best_vectors = Mat3::Identity();
  double best_e0 = 0.0, best_e2 = 0.0, best_gamma = 0.0;
  for (int i = 0; i < n_gamma; ++i) {
    const Mat3 A = D1 + gammas[i] * D2;
    const Eigen::SelfAdjointEigenSolver<Mat3> es(A);
    const Vec3 e = es.eigenvalues();
    const double cond = std::min(-e(0), e(2)) / std::max(std::abs(e(0)), std::abs(e(2)));
    if (cond > best_cond && std::abs(e(1)) < 1e-6 * std::max(-e(0), e(2))) {
      best_cond = cond;
      best_vectors = es.eigenvectors();
      best_e0 = e(0);
      best_e2 = e(2);
      best_gamma = gammas[i];
    }
  }
  if (!(best_cond > 0.0)) return 0;

  // The degenerate conic e0 p0^2 + e2 p2^2 = 0 (p = V^T lambda) is the planes
  // (sqrt(-e0) v0 -+ sqrt(e2) v2) . lambda = 0. On them D1 and D2 agree up to the factor -g;
  // intersect with the one whose restriction is larger (better conditioned).
  const Mat3& D = std::abs(best_gamma) > 1.0 ? D1 : D2;
  const Vec3 v0 = best_vectors.col(0), v2 = best_vectors.col(2);
  Vec3 lambdas[4];
  int n_l = 0;
  for (int sgn = -1; sgn <= 1; sgn += 2) {
    const Vec3 n = (std::sqrt(-best_e0) * v0 + sgn * std::sqrt(best_e2) * v2).normalized();
    n_l += rays_on_plane(n, D, eq, lambdas + n_l);
  }

  // R maps the world triangle's frame (d12, d13, d12 x d13) to the camera's.
  Mat3 X;
  X << d12, d13, n_x;
  const Mat3 X_inv = X.inverse();
  int count = 0;
  for (int i = 0; i < n_l; ++i) {
    const Vec3& l = lambdas[i];
    const Vec3 p1 = l(0) * y1, p2 = l(1) * y2, p3 = l(2) * y3;
    const Vec3 e12 = p1 - p2, e13 = p1 - p3;
    Mat3 Y;
    Y << e12, e13, e12.cross(e13);
    const Mat3 R = Y * X_inv;
    if (!R.allFinite()) continue;
    const SO3 rot = SO3::from_matrix(R);
    const Mat3 Rm = rot.matrix();
    const Vec3 t = (p1 + p2 + p3 - Rm * (points_w[0] + points_w[1] + points_w[2])) / 3.0;
    if (!t.allFinite()) continue;
    poses_cw[count++] = SE3(rot, t);
  }
  return count;
}

// ---- Residual and refinement ----

namespace {

// A pose as a rotation matrix and translation: the loops below transform every point by the same
// pose, and a matrix product costs a third of a quaternion rotation.
struct PoseRt {
  explicit PoseRt(const SE3& T) : R(T.rotation()), t(T.translation()) {}
  Mat3 R;
  Vec3 t;
};

bool residual_rt(const Camera& camera, const PoseRt& T_cw, const Vec3& p_w, const Vec2& uv, double sigma_px, Vec2* r,
                 Mat26* d_r_d_xi) {
  const Vec3 p_c = T_cw.R * p_w + T_cw.t;
  Vec2 proj;
  Mat23 d_uv_d_p;
  if (!camera.project(p_c, &proj, d_r_d_xi ? &d_uv_d_p : nullptr)) return false;
  const double inv_sigma = 1.0 / sigma_px;
  *r = (proj - uv) * inv_sigma;
  if (d_r_d_xi) {
    // d p_c / d xi = [I, -hat(p_c)] for the left perturbation.
    d_r_d_xi->leftCols<3>() = d_uv_d_p * inv_sigma;
    d_r_d_xi->rightCols<3>() = -d_uv_d_p * hat(p_c) * inv_sigma;
  }
  return true;
}

}  // namespace

bool pnp_residual(const Camera& camera, const SE3& T_cw, const Vec3& p_w, const Vec2& uv, double sigma_px, Vec2* r,
                  Mat26* d_r_d_xi) {
  return residual_rt(camera, PoseRt(T_cw), p_w, uv, sigma_px, r, d_r_d_xi);
}

namespace {

double sigma_of(const PnpInput& in, int i) { return in.sigma_px ? in.sigma_px[i] : 1.0; }

// Sum of squared whitened residuals over the mask; points that do not project count as the
// gate value `behind_cost` so that a step cannot gain by pushing points behind the camera.
double masked_cost(const Camera& camera, const PnpInput& in, const std::uint8_t* mask, const SE3& T,
                   double behind_cost) {
  const PoseRt T_cw(T);
  double cost = 0.0;
  for (int i = 0; i < in.size; ++i) {
    if (!mask[i]) continue;
    Vec2 r;
    cost += residual_rt(camera, T_cw, in.points_w[i], in.pixels[i], sigma_of(in, i), &r, nullptr) ? r.squaredNorm()
                                                                                                  : behind_cost;
  }
  return cost;
}

// Marks inliers of T_cw under the chi-square gate; returns the count and the truncated
// chi-square score (sum of chi2 - e^2 over inliers), and the sum of squared pixel errors.
int classify(const Camera& camera, const PnpInput& in, const SE3& T, double chi2, std::uint8_t* mask, double* score,
             double* sum_err2_px) {
  const PoseRt T_cw(T);
  int inliers = 0;
  double s = 0.0, e2px = 0.0;
  for (int i = 0; i < in.size; ++i) {
    Vec2 r;
    const double sigma = sigma_of(in, i);
    const bool in_front = residual_rt(camera, T_cw, in.points_w[i], in.pixels[i], sigma, &r, nullptr);
    const double e2 = in_front ? r.squaredNorm() : 0.0;
    const bool inlier = in_front && e2 < chi2;
    mask[i] = inlier ? 1 : 0;
    if (inlier) {
      ++inliers;
      s += chi2 - e2;
      e2px += e2 * sigma * sigma;
    }
  }
  if (score) *score = s;
  if (sum_err2_px) *sum_err2_px = e2px;
  return inliers;
}

struct PnpRansacProblem {
  static constexpr int kSampleSize = 3;
  static constexpr int kMaxModels = 4;
  using Model = SE3;

  const Camera& camera;
  const PnpInput& in;
  const Vec3* bearings;
  double chi2;
  mutable int models_fitted = 0;

  int size() const { return in.size; }
  int fit(const int* sample, SE3* models) const {
    const Vec3 y[3] = {bearings[sample[0]], bearings[sample[1]], bearings[sample[2]]};
    const Vec3 x[3] = {in.points_w[sample[0]], in.points_w[sample[1]], in.points_w[sample[2]]};
    const int m = solve_p3p(y, x, models);
    models_fitted += m;
    return m;
  }
  double score(const SE3& T_cw, std::uint8_t* mask, int* inliers) const {
    double s = 0.0;
    *inliers = classify(camera, in, T_cw, chi2, mask, &s, nullptr);
    return s;
  }
};

Status fail(PnpResult* result, PnpFailure failure, const std::string& message) {
  result->failure = failure;
  const std::string text = std::string("pnp: ") + to_string(failure) + ": " + message;
  return failure == PnpFailure::kInvalidInput || failure == PnpFailure::kTooFewPoints ? invalid_argument(text)
                                                                                      : not_found(text);
}

}  // namespace

bool refine_pnp(const Camera& camera, const PnpInput& in, const std::uint8_t* mask, int max_iterations, SE3* T_cw,
                int* iterations) {
  // A point that leaves the image plane's front costs more than any inlier could.
  constexpr double kBehindCost = 1e6;
  double cost = masked_cost(camera, in, mask, *T_cw, kBehindCost);
  double mu = 1e-4;  // LM damping, relative to the diagonal
  bool converged = false;
  int it = 0;
  while (it < max_iterations && !converged) {
    ++it;
    Mat6 H = Mat6::Zero();
    Vec6 g = Vec6::Zero();
    const PoseRt T_rt(*T_cw);
    for (int i = 0; i < in.size; ++i) {
      if (!mask[i]) continue;
      Vec2 r;
      Mat26 J;
      if (!residual_rt(camera, T_rt, in.points_w[i], in.pixels[i], sigma_of(in, i), &r, &J)) continue;
      H.noalias() += J.transpose() * J;
      g.noalias() += J.transpose() * r;
    }
    if (g.norm() < 1e-12 * (1.0 + cost)) {
      converged = true;
      break;
    }
    // Try damped steps until one lowers the cost (or the damping says we are at the minimum).
    bool stepped = false;
    while (!stepped && mu < 1e12) {
      Mat6 Hd = H;
      Hd.diagonal() += mu * H.diagonal().cwiseMax(1e-9);
      const Eigen::LDLT<Mat6> ldlt(Hd);
      if (ldlt.info() != Eigen::Success) {
        mu *= 10.0;
        continue;
      }
      const Vec6 delta = -ldlt.solve(g);
      if (!delta.allFinite()) {
        mu *= 10.0;
        continue;
      }
      const SE3 candidate = SE3::exp(delta) * *T_cw;
      const double new_cost = masked_cost(camera, in, mask, candidate, kBehindCost);
      if (new_cost < cost) {
        const double decrease = cost - new_cost;
        *T_cw = candidate;
        converged = delta.norm() < 1e-10 || decrease <= 1e-10 * cost;
        cost = new_cost;
        mu = std::max(mu * 0.1, 1e-12);
        stepped = true;
      } else {
        if (delta.norm() < 1e-10) {
          converged = true;  // no representable improvement left
          break;
        }
        mu *= 10.0;
      }
    }
    if (!stepped && !converged) {
      converged = true;  // damping exhausted: the gradient does not lead downhill any more
    }
  }
  if (iterations) *iterations = it;
  return converged;
}

Status solve_pnp_ransac(const Camera& camera, const PnpInput& in, const PnpParams& params, PnpResult* result,
                        PnpScratch& scratch) {
  const int n = in.size;
  result->T_cw = SE3();
  result->inliers.assign(static_cast<std::size_t>(std::max(n, 0)), 0);
  result->inlier_count = 0;
  result->ransac_iterations = 0;
  result->refine_iterations = 0;
  result->rms_px = 0.0;
  result->failure = PnpFailure::kNone;
  if (n < 4 || !in.points_w || !in.pixels) {
    return fail(result, PnpFailure::kTooFewPoints, std::to_string(std::max(n, 0)) + " correspondences, 4 needed");
  }

  scratch.bearings.resize(static_cast<std::size_t>(n));
  Vec3 mean = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    const double sigma = sigma_of(in, i);
    if (!in.points_w[i].allFinite() || !in.pixels[i].allFinite() || !std::isfinite(sigma) || !(sigma > 0.0)) {
      return fail(result, PnpFailure::kInvalidInput,
                  "correspondence " + std::to_string(i) + " has a non-finite point or pixel, or sigma <= 0");
    }
    if (!camera.unproject(in.pixels[i], &scratch.bearings[static_cast<std::size_t>(i)])) {
      return fail(result, PnpFailure::kInvalidInput, "pixel " + std::to_string(i) + " cannot be unprojected");
    }
    mean += in.points_w[i];
  }
  // Collinear (or coincident) points: the second principal spread vanishes.
  mean /= n;
  Mat3 cov = Mat3::Zero();
  for (int i = 0; i < n; ++i) {
    const Vec3 d = in.points_w[i] - mean;
    cov.noalias() += d * d.transpose();
  }
  const Vec3 spread = Eigen::SelfAdjointEigenSolver<Mat3>(cov, Eigen::EigenvaluesOnly).eigenvalues();
  if (!(spread(1) > 1e-12 * spread(2))) {
    return fail(result, PnpFailure::kDegenerate, "the points are collinear or coincide");
  }

  const int min_inliers = std::max(params.min_inliers, 4);
  const PnpRansacProblem problem{camera, in, scratch.bearings.data(), params.chi2};
  SE3 T_cw;
  RansacStats stats;
  const Status rs = ransac(problem, params.ransac, min_inliers, &T_cw, result->inliers, &stats, scratch.ransac);
  result->ransac_iterations = stats.iterations;
  if (!rs.ok()) {
    std::fill(result->inliers.begin(), result->inliers.end(), std::uint8_t{0});
    if (problem.models_fitted == 0) {
      return fail(result, PnpFailure::kDegenerate,
                  "no minimal sample gave a pose in " + std::to_string(stats.iterations) + " iterations");
    }
    return fail(result, PnpFailure::kNoConsensus,
                std::to_string(stats.inliers) + " inliers, " + std::to_string(min_inliers) + " needed");
  }
  const SE3 T_ransac = T_cw;

  // Refine on the inliers, reclassify, repeat while the set changes.
  scratch.mask.resize(static_cast<std::size_t>(n));
  bool converged = true;
  int inliers = stats.inliers;
  double sum_err2_px = 0.0;
  for (int round = 0; round < std::max(params.refine_rounds, 1); ++round) {
    int its = 0;
    SE3 T_try = T_cw;
    converged = refine_pnp(camera, in, result->inliers.data(), params.max_refine_iterations, &T_try, &its);
    result->refine_iterations += its;
    if (!T_try.translation().allFinite() || !T_try.so3().quaternion().coeffs().allFinite()) {
      converged = false;
      break;
    }
    T_cw = T_try;
    inliers = classify(camera, in, T_cw, params.chi2, scratch.mask.data(), nullptr, &sum_err2_px);
    const bool same = std::equal(scratch.mask.begin(), scratch.mask.end(), result->inliers.begin());
    result->inliers.swap(scratch.mask);
    if (same || inliers < min_inliers) break;
  }
  result->inlier_count = inliers;
  result->rms_px = inliers > 0 ? std::sqrt(sum_err2_px / inliers) : 0.0;
  if (!converged) {
    result->T_cw = T_ransac;
    result->inlier_count = classify(camera, in, T_ransac, params.chi2, result->inliers.data(), nullptr, &sum_err2_px);
    result->rms_px = result->inlier_count > 0 ? std::sqrt(sum_err2_px / result->inlier_count) : 0.0;
    return fail(result, PnpFailure::kNotConverged,
                "refinement did not converge in " + std::to_string(params.max_refine_iterations) + " iterations");
  }
  result->T_cw = T_cw;
  if (inliers < min_inliers) {
    return fail(result, PnpFailure::kNoConsensus,
                std::to_string(inliers) + " inliers after refinement, " + std::to_string(min_inliers) + " needed");
  }
  return Status::ok_status();
}

}  // namespace ale::geometry
