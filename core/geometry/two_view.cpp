// Model selection, decomposition and the acceptance rules of two_view.h.
#include "core/geometry/two_view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "core/base/median.h"
#include "core/geometry/essential.h"
#include "core/geometry/triangulation.h"
#include "core/geometry/two_view_detail.h"

namespace ale::geometry {

const char* to_string(TwoViewModel m) {
  switch (m) {
    case TwoViewModel::kNone: return "none";
    case TwoViewModel::kHomography: return "homography";
    case TwoViewModel::kFundamental: return "fundamental";
  }
  return "unknown";
}

const char* to_string(TwoViewFailure f) {
  switch (f) {
    case TwoViewFailure::kNone: return "none";
    case TwoViewFailure::kInvalidInput: return "invalid input";
    case TwoViewFailure::kTooFewMatches: return "too few matches";
    case TwoViewFailure::kDegenerate: return "degenerate";
    case TwoViewFailure::kLowParallax: return "not enough parallax";
    case TwoViewFailure::kAmbiguous: return "ambiguous";
    case TwoViewFailure::kTooFewTriangulated: return "too few triangulated";
  }
  return "unknown";
}

Status validate(const TwoViewParams& p) {
  const auto bad = [](const char* field, double v) {
    return invalid_argument(std::string("TwoViewParams.") + field + " out of range: " + std::to_string(v));
  };
  if (!(p.sigma_px > 0.0) || !std::isfinite(p.sigma_px)) return bad("sigma_px", p.sigma_px);
  if (!(p.h_ratio_threshold >= 0.0 && p.h_ratio_threshold <= 1.0)) return bad("h_ratio_threshold", p.h_ratio_threshold);
  if (!(p.min_parallax_deg >= 0.0 && p.min_parallax_deg < 90.0)) return bad("min_parallax_deg", p.min_parallax_deg);
  if (p.min_triangulated < 0) return bad("min_triangulated", p.min_triangulated);
  if (!(p.min_good_ratio >= 0.0 && p.min_good_ratio <= 1.0)) return bad("min_good_ratio", p.min_good_ratio);
  if (!(p.clear_winner_ratio_f > 0.0 && p.clear_winner_ratio_f <= 1.0))
    return bad("clear_winner_ratio_f", p.clear_winner_ratio_f);
  if (!(p.clear_winner_ratio_h > 0.0 && p.clear_winner_ratio_h <= 1.0))
    return bad("clear_winner_ratio_h", p.clear_winner_ratio_h);
  if (!(p.ransac.confidence > 0.0 && p.ransac.confidence < 1.0)) return bad("ransac.confidence", p.ransac.confidence);
  if (p.ransac.max_iterations < 1) return bad("ransac.max_iterations", p.ransac.max_iterations);
  return Status::ok_status();
}

namespace {

Status fail(TwoViewResult* r, TwoViewFailure f, StatusCode code, const std::string& why) {
  r->failure = f;
  return Status(code, std::string("two-view: ") + to_string(f) + ": " + why);
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

Status check_pinhole(const CameraIntrinsics& k) {
  if (k.model != CameraModel::kPinholeRadTan) return invalid_argument("the pinhole must be kPinholeRadTan");
  for (double d : k.distortion)
    if (d != 0.0) return invalid_argument("pixels must be undistorted: the pinhole's distortion must be zero");
  if (!(k.fx > 0.0) || !(k.fy > 0.0) || !std::isfinite(k.fx) || !std::isfinite(k.fy) || !std::isfinite(k.cx) ||
      !std::isfinite(k.cy))
    return invalid_argument("pinhole focal lengths must be positive and finite");
  return Status::ok_status();
}

// How one candidate pose explains the model's inliers.
struct CandidateFigures {
  int good = 0;
  int valid = 0;
};

// Triangulates every inlier under (R_21, t_21) (t unit) and counts good and valid points (rules
// at the top of two_view.h); points, validity and the valid points' parallax (deg) go to the
// scratch's *_tmp buffers.
CandidateFigures check_candidate(const Camera& camera, const Mat3& R_21, const Vec3& t_21, const Vec2* x1,
                                 const Vec2* x2, int n, const std::uint8_t* inlier, double sigma_px,
                                 TwoViewScratch& scratch) {
  CandidateFigures fig;
  const SE3 T_1w;
  const SE3 T_2w(SO3::from_matrix(R_21), t_21);
  const Mat3 R = T_2w.rotation();
  const CameraIntrinsics& k = camera.intrinsics();
  const TriangulationParams tp;  // ORB-SLAM's 0.99998 and the 2-dof gate
  const double gate = tp.chi2 * sigma_px * sigma_px;
  // Pixel error of a point at any depth sign (for points whose depth sign is noise).
  const auto err2 = [&k](const Vec3& p_c, const Vec2& uv) {
    if (std::abs(p_c.z()) < 1e-12) return std::numeric_limits<double>::infinity();
    return Vec2(k.fx * p_c.x() / p_c.z() + k.cx - uv.x(), k.fy * p_c.y() / p_c.z() + k.cy - uv.y()).squaredNorm();
  };
  scratch.points_tmp.resize(static_cast<std::size_t>(n));
  scratch.valid_tmp.assign(static_cast<std::size_t>(n), 0);
  scratch.parallax_tmp.clear();
  scratch.parallax_tmp.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    if (!inlier[i]) continue;
    const Triangulation tri = triangulate_pixels(camera, T_1w, T_2w, x1[i], x2[i], sigma_px, sigma_px, tp);
    bool good = false;
    switch (tri.status) {
      case TriangulationStatus::kOk:
        good = true;
        scratch.valid_tmp[static_cast<std::size_t>(i)] = 1;
        scratch.points_tmp[static_cast<std::size_t>(i)] = tri.p_w;
        scratch.parallax_tmp.push_back(std::acos(std::clamp(tri.cos_parallax, -1.0, 1.0)) * 180.0 / M_PI);
        ++fig.valid;
        break;
      case TriangulationStatus::kLowParallax:
        good = true;
        break;
      case TriangulationStatus::kBehindFirst:
      case TriangulationStatus::kBehindSecond:
        good = tri.cos_parallax >= tp.max_cos_parallax && err2(tri.p_w, x1[i]) <= gate &&
               err2(R * tri.p_w + t_21, x2[i]) <= gate;
        break;
      default:
        break;
    }
    fig.good += good ? 1 : 0;
  }
  return fig;
}

}  // namespace

namespace detail {

// Sampson residual (first-order geometric epipolar error, in normalised image units) of one
// match under the essential matrix E.
double sampson_residual(const Mat3& E, const Vec3& p1, const Vec3& p2) {
  const Vec3 l2 = E * p1;
  const Vec3 l1 = E.transpose() * p2;
  const double den = l2.x() * l2.x() + l2.y() * l2.y() + l1.x() * l1.x() + l1.y() * l1.y();
  return den > 1e-300 ? p2.dot(l2) / std::sqrt(den) : 0.0;
}

// Gauss-Newton on the Sampson error of E = hat(t) R over the matches in `use` (5 degrees of
// freedom: R perturbed on the left, t on its tangent plane, numeric Jacobians). The linear
// eight-point estimate minimises an algebraic error; this minimises a geometric one, which the
// decomposition's pose then inherits (on the real EuRoC pairs it roughly halves the direction
// error). Stops after kRefineIterations or when the step is below 1e-10; keeps the input when
// the cost does not decrease. Fixed-size arithmetic only: nothing is allocated.
constexpr int kRefineIterations = 10;

void refine_pose_sampson(const Vec2* r1, const Vec2* r2, int n, const std::uint8_t* use, Mat3* R, Vec3* t) {
  using Vec5 = Eigen::Matrix<double, 5, 1>;
  using Mat5 = Eigen::Matrix<double, 5, 5>;
  const auto tangent_basis = [](const Vec3& dir, Vec3* b1, Vec3* b2) {
    const Vec3 helper = std::abs(dir.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    *b1 = dir.cross(helper).normalized();
    *b2 = dir.cross(*b1);
  };
  const auto apply_step = [&](const Mat3& R0, const Vec3& t0, const Vec5& d, Mat3* R_out, Vec3* t_out) {
    Vec3 b1, b2;
    tangent_basis(t0, &b1, &b2);
    *R_out = SO3::exp(d.head<3>()).matrix() * R0;
    *t_out = (t0 + d(3) * b1 + d(4) * b2).normalized();
  };
  const auto cost = [&](const Mat3& Rc, const Vec3& tc) {
    const Mat3 E = hat(tc) * Rc;
    double c = 0.0;
    for (int i = 0; i < n; ++i) {
      if (!use[i]) continue;
      const double r = sampson_residual(E, r1[i].homogeneous(), r2[i].homogeneous());
      c += r * r;
    }
    return c;
  };
  constexpr double kStep = 1e-7;
  double current = cost(*R, *t);
  for (int it = 0; it < kRefineIterations; ++it) {
    const Mat3 E0 = hat(*t) * *R;
    std::array<Mat3, 5> dE;
    for (int k = 0; k < 5; ++k) {
      Vec5 d = Vec5::Zero();
      d(k) = kStep;
      Mat3 Rk;
      Vec3 tk;
      apply_step(*R, *t, d, &Rk, &tk);
      dE[static_cast<std::size_t>(k)] = hat(tk) * Rk;
    }
    Mat5 JtJ = Mat5::Zero();
    Vec5 Jtr = Vec5::Zero();
    for (int i = 0; i < n; ++i) {
      if (!use[i]) continue;
      const Vec3 p1 = r1[i].homogeneous();
      const Vec3 p2 = r2[i].homogeneous();
      const double r0 = sampson_residual(E0, p1, p2);
      Vec5 J;
      for (int k = 0; k < 5; ++k) J(k) = (sampson_residual(dE[static_cast<std::size_t>(k)], p1, p2) - r0) / kStep;
      JtJ.noalias() += J * J.transpose();
      Jtr.noalias() += J * r0;
    }
    // A little damping keeps the step finite when the data leave a direction unobserved.
    JtJ.diagonal().array() += 1e-9 * (1.0 + JtJ.diagonal().maxCoeff());
    const Vec5 step = -JtJ.ldlt().solve(Jtr);
    if (!step.allFinite()) return;
    Mat3 R_new;
    Vec3 t_new;
    apply_step(*R, *t, step, &R_new, &t_new);
    const double next = cost(R_new, t_new);
    if (!(next < current)) return;
    *R = R_new;
    *t = t_new;
    current = next;
    if (step.norm() < 1e-10) return;
  }
}

}  // namespace detail

Mat3 fundamental_from_pose(const CameraIntrinsics& pinhole, const Mat3& R_21, const Vec3& t_21) {
  Mat3 K_inv = Mat3::Identity();
  K_inv(0, 0) = 1.0 / pinhole.fx;
  K_inv(1, 1) = 1.0 / pinhole.fy;
  K_inv(0, 2) = -pinhole.cx / pinhole.fx;
  K_inv(1, 2) = -pinhole.cy / pinhole.fy;
  const Mat3 F = K_inv.transpose() * hat(t_21) * R_21 * K_inv;
  const double norm = F.norm();
  return norm > 0.0 ? Mat3(F / norm) : Mat3::Zero();
}

namespace {

Status reconstruct(const std::vector<Vec2>& x1_px, const std::vector<Vec2>& x2_px, const Mat3* given_F_21,
                   const CameraIntrinsics& pinhole, const TwoViewParams& params, TwoViewResult* result,
                   TwoViewScratch& scratch) {
  TwoViewResult& r = *result;
  r.model = TwoViewModel::kNone;
  r.failure = TwoViewFailure::kNone;
  r.R_21.setIdentity();
  r.t_21.setZero();
  r.F_21.setZero();
  r.H_21.setZero();
  r.score_f = r.score_h = r.ratio_h = 0.0;
  r.inliers_f = r.inliers_h = 0;
  r.ransac_f = r.ransac_h = RansacStats{};
  r.candidates = 0;
  r.candidate_good.fill(0);
  r.best_candidate = -1;
  r.parallax_deg = 0.0;
  r.num_valid = 0;
  const int n = static_cast<int>(x1_px.size());
  r.points_1.assign(static_cast<std::size_t>(n), Vec3::Zero());
  r.valid.assign(static_cast<std::size_t>(n), 0);
  r.inlier_mask.assign(static_cast<std::size_t>(n), 0);

  if (Status s = validate(params); !s.ok()) return fail(&r, TwoViewFailure::kInvalidInput, s.code(), s.message());
  if (Status s = check_pinhole(pinhole); !s.ok()) return fail(&r, TwoViewFailure::kInvalidInput, s.code(), s.message());
  if (x2_px.size() != x1_px.size())
    return fail(&r, TwoViewFailure::kInvalidInput, StatusCode::kInvalidArgument,
                std::to_string(x1_px.size()) + " points in image 1, " + std::to_string(x2_px.size()) + " in image 2");
  if (n < kTwoViewSampleSize)
    return fail(&r, TwoViewFailure::kTooFewMatches, StatusCode::kInvalidArgument,
                std::to_string(n) + " matches, " + std::to_string(kTwoViewSampleSize) + " needed");
  for (int i = 0; i < n; ++i)
    if (!detail::finite(x1_px[static_cast<std::size_t>(i)]) || !detail::finite(x2_px[static_cast<std::size_t>(i)]))
      return fail(&r, TwoViewFailure::kInvalidInput, StatusCode::kInvalidArgument,
                  "match " + std::to_string(i) + " has a non-finite coordinate");
  const Result<Camera> camera = Camera::create(pinhole);
  if (!camera.ok())
    return fail(&r, TwoViewFailure::kInvalidInput, camera.status().code(), camera.status().message());

  const Vec2* x1 = x1_px.data();
  const Vec2* x2 = x2_px.data();
  Mat3 K = Mat3::Identity();
  K(0, 0) = pinhole.fx;
  K(1, 1) = pinhole.fy;
  K(0, 2) = pinhole.cx;
  K(1, 2) = pinhole.cy;
  bool use_h = false;
  if (given_F_21) {
    // The caller's epipolar geometry: scored on the matches, no RANSAC, no homography.
    r.F_21 = *given_F_21;
    scratch.mask_f.resize(static_cast<std::size_t>(n));
    r.score_f = score_fundamental(r.F_21, x1, x2, n, params.sigma_px, scratch.mask_f.data(), &r.inliers_f);
    r.ransac_f.score = r.score_f;
    r.ransac_f.inliers = r.inliers_f;
    if (r.inliers_f < kTwoViewSampleSize)
      return fail(&r, TwoViewFailure::kDegenerate, StatusCode::kNotFound,
                  "the given fundamental matrix has " + std::to_string(r.inliers_f) + " inliers, " +
                      std::to_string(kTwoViewSampleSize) + " needed");
  } else {
    // The general model from five-point samples (essential.h): it proposes only true essential
    // matrices, where the 8-point F's two extra degrees of freedom overfit near-planar scenes.
    const bool f_ok = estimate_essential(x1, x2, n, K, params, &r.F_21, scratch.mask_f, &r.ransac_f, scratch).ok();
    const bool h_ok = estimate_homography(x1, x2, n, params, &r.H_21, scratch.mask_h, &r.ransac_h, scratch).ok();
    if (f_ok) {
      r.score_f = r.ransac_f.score;
      r.inliers_f = r.ransac_f.inliers;
    }
    if (h_ok) {
      r.score_h = r.ransac_h.score;
      r.inliers_h = r.ransac_h.inliers;
    }
    if (!f_ok && !h_ok)
      return fail(&r, TwoViewFailure::kDegenerate, StatusCode::kNotFound,
                  "neither a fundamental matrix nor a homography has " + std::to_string(kTwoViewSampleSize) + " inliers");
    const double score_sum = r.score_h + r.score_f;
    r.ratio_h = score_sum > 0.0 ? r.score_h / score_sum : 0.0;
    use_h = h_ok && (!f_ok || r.ratio_h > params.h_ratio_threshold);
    r.model = use_h ? TwoViewModel::kHomography : TwoViewModel::kFundamental;
    r.inlier_mask.swap(use_h ? scratch.mask_h : scratch.mask_f);
  }
  if (given_F_21) {
    r.model = TwoViewModel::kFundamental;
    r.inlier_mask.swap(scratch.mask_f);
  }
  const int model_inliers = use_h ? r.inliers_h : r.inliers_f;
  // Candidate poses of the chosen model.
  std::array<Mat3, 8> Rs;
  std::array<Vec3, 8> ts;
  if (use_h) {
    const Mat3 A = K.inverse() * r.H_21 * K;
    std::array<Vec3, 8> normals;
    r.candidates = decompose_homography(A, &Rs, &ts, &normals);
    if (r.candidates == 0) {
      const Vec3 sv = Eigen::JacobiSVD<Mat3>(A).singularValues();
      // All three equal: the homography is a rotation (no translation to triangulate from).
      if (sv(0) / sv(2) < 1.0001)
        return fail(&r, TwoViewFailure::kLowParallax, StatusCode::kNotFound,
                    "the homography is a pure rotation (singular values " + fmt(sv(0)) + " " + fmt(sv(1)) + " " +
                        fmt(sv(2)) + ")");
      return fail(&r, TwoViewFailure::kDegenerate, StatusCode::kNotFound,
                  "two singular values of the homography coincide (" + fmt(sv(0)) + " " + fmt(sv(1)) + " " +
                      fmt(sv(2)) + ")");
    }
  } else {
    std::array<Mat3, 4> Re;
    std::array<Vec3, 4> te;
    decompose_essential(K.transpose() * r.F_21 * K, &Re, &te);
    for (int i = 0; i < 4; ++i) {
      Rs[static_cast<std::size_t>(i)] = Re[static_cast<std::size_t>(i)];
      ts[static_cast<std::size_t>(i)] = te[static_cast<std::size_t>(i)];
    }
    r.candidates = 4;
  }

  int best = -1;
  int best_good = -1;
  int best_valid = 0;
  for (int c = 0; c < r.candidates; ++c) {
    const Vec3& t = ts[static_cast<std::size_t>(c)];
    const double t_norm = t.norm();
    if (!(t_norm > 1e-12) || !Rs[static_cast<std::size_t>(c)].allFinite()) continue;  // nothing to triangulate from
    const CandidateFigures fig = check_candidate(*camera, Rs[static_cast<std::size_t>(c)], t / t_norm, x1, x2, n,
                                                 r.inlier_mask.data(), params.sigma_px, scratch);
    r.candidate_good[static_cast<std::size_t>(c)] = fig.good;
    if (fig.good > best_good) {
      best_good = fig.good;
      best_valid = fig.valid;
      best = c;
      r.points_1.swap(scratch.points_tmp);
      r.valid.swap(scratch.valid_tmp);
      scratch.parallax_best.swap(scratch.parallax_tmp);
    }
  }
  if (best < 0)
    return fail(&r, TwoViewFailure::kDegenerate, StatusCode::kNotFound, "no candidate pose has a translation");
  r.best_candidate = best;
  r.R_21 = Rs[static_cast<std::size_t>(best)];
  r.t_21 = ts[static_cast<std::size_t>(best)].normalized();
  r.num_valid = best_valid;
  r.parallax_deg = median_in_place(scratch.parallax_best);

  if (r.parallax_deg < params.min_parallax_deg)
    return fail(&r, TwoViewFailure::kLowParallax, StatusCode::kNotFound,
                "median parallax " + fmt(r.parallax_deg) + " deg < " + fmt(params.min_parallax_deg) + " deg over " +
                    std::to_string(best_valid) + " points");
  const double clear_ratio = use_h ? params.clear_winner_ratio_h : params.clear_winner_ratio_f;
  int similar = 0;
  for (int c = 0; c < r.candidates; ++c)
    if (c != best && r.candidate_good[static_cast<std::size_t>(c)] > clear_ratio * best_good) ++similar;
  if (similar > 0)
    return fail(&r, TwoViewFailure::kAmbiguous, StatusCode::kNotFound,
                std::to_string(similar) + " other candidate(s) explain more than " + fmt(clear_ratio) +
                    " of the best's " + std::to_string(best_good) + " points");
  if (best_good < params.min_good_ratio * model_inliers || best_valid < params.min_triangulated)
    return fail(&r, TwoViewFailure::kTooFewTriangulated, StatusCode::kNotFound,
                std::to_string(best_good) + " good of " + std::to_string(model_inliers) + " inliers (need " +
                    fmt(params.min_good_ratio) + " of them), " + std::to_string(best_valid) + " triangulated (need " +
                    std::to_string(params.min_triangulated) + ")");
  if (!use_h && params.refine_pose) {
    // The refined pose re-triangulates the same matches; it replaces the decomposition's only
    // when it keeps at least as many of them good.
    scratch.r1.resize(static_cast<std::size_t>(n));
    scratch.r2.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const Vec2& a = x1[i];
      const Vec2& b = x2[i];
      scratch.r1[static_cast<std::size_t>(i)] = Vec2((a.x() - pinhole.cx) / pinhole.fx, (a.y() - pinhole.cy) / pinhole.fy);
      scratch.r2[static_cast<std::size_t>(i)] = Vec2((b.x() - pinhole.cx) / pinhole.fx, (b.y() - pinhole.cy) / pinhole.fy);
    }
    Mat3 R = r.R_21;
    Vec3 t = r.t_21;
    detail::refine_pose_sampson(scratch.r1.data(), scratch.r2.data(), n, r.valid.data(), &R, &t);
    const CandidateFigures fig = check_candidate(*camera, R, t, x1, x2, n, r.inlier_mask.data(), params.sigma_px, scratch);
    if (fig.good >= best_good && fig.valid >= params.min_triangulated) {
      r.R_21 = R;
      r.t_21 = t;
      r.num_valid = fig.valid;
      r.points_1.swap(scratch.points_tmp);
      r.valid.swap(scratch.valid_tmp);
      r.parallax_deg = median_in_place(scratch.parallax_tmp);
    }
  }
  // Points outside the winner's valid set are not handed on.
  for (int i = 0; i < n; ++i)
    if (!r.valid[static_cast<std::size_t>(i)]) r.points_1[static_cast<std::size_t>(i)].setZero();
  return Status::ok_status();
}

}  // namespace

Status reconstruct_two_view(const std::vector<Vec2>& x1_px, const std::vector<Vec2>& x2_px,
                            const CameraIntrinsics& pinhole, const TwoViewParams& params, TwoViewResult* result,
                            TwoViewScratch& scratch) {
  return reconstruct(x1_px, x2_px, nullptr, pinhole, params, result, scratch);
}

Status reconstruct_two_view_from(const Mat3& F_21, const std::vector<Vec2>& x1_px, const std::vector<Vec2>& x2_px,
                                 const CameraIntrinsics& pinhole, const TwoViewParams& params, TwoViewResult* result,
                                 TwoViewScratch& scratch) {
  if (!F_21.allFinite() || !(F_21.norm() > 0.0)) {
    *result = TwoViewResult{};
    result->failure = TwoViewFailure::kInvalidInput;
    return invalid_argument("reconstruct_two_view_from: the fundamental matrix is zero or not finite");
  }
  return reconstruct(x1_px, x2_px, &F_21, pinhole, params, result, scratch);
}

}  // namespace ale::geometry
