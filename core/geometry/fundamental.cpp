// The fundamental matrix: Hartley's normalised 8-point algorithm, ORB-SLAM's score, its RANSAC,
// and the four poses of the essential matrix.
#include <Eigen/SVD>

#include "core/geometry/two_view.h"
#include "core/geometry/two_view_detail.h"

namespace ale::geometry {

using detail::Mat9;
using detail::Vec9;

bool hartley_normalisation(const Vec2* pts, int n, Mat3* T) {
  if (n < 1) return false;
  Vec2 c = Vec2::Zero();
  for (int i = 0; i < n; ++i) {
    if (!detail::finite(pts[i])) return false;
    c += pts[i];
  }
  c /= static_cast<double>(n);
  double mean_dist = 0.0;
  for (int i = 0; i < n; ++i) mean_dist += (pts[i] - c).norm();
  mean_dist /= static_cast<double>(n);
  // Relative to the points' magnitude, so that a cloud far from the origin still counts as one point.
  if (!(mean_dist > 1e-12 * (1.0 + c.norm()))) return false;
  const double s = std::sqrt(2.0) / mean_dist;
  *T << s, 0.0, -s * c.x(), 0.0, s, -s * c.y(), 0.0, 0.0, 1.0;
  return true;
}

namespace {

// Rank 2 by zeroing the smallest singular value; unit Frobenius norm.
Mat3 enforce_rank2(const Mat3& F) {
  const Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Vec3 s = svd.singularValues();
  s(2) = 0.0;
  return svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();
}

}  // namespace

namespace detail {

bool fundamental_from_normal(const Mat9& ata, const Mat3& T1, const Mat3& T2, Mat3* F_21) {
  Vec9 f;
  if (!detail::null_vector(ata, &f)) return false;
  const Mat3 F = detail::denormalise_fundamental(enforce_rank2(detail::to_mat3(f)), T1, T2);
  const double norm = F.norm();
  if (!(norm > 0.0) || !F.allFinite()) return false;
  *F_21 = F / norm;
  return true;
}

}  // namespace detail

bool fundamental_8point(const Vec2* x1, const Vec2* x2, int n, Mat3* F_21) {
  if (n < kTwoViewSampleSize) return false;
  Mat3 T1, T2;
  if (!hartley_normalisation(x1, n, &T1) || !hartley_normalisation(x2, n, &T2)) return false;
  Mat9 ata = Mat9::Zero();
  for (int i = 0; i < n; ++i) detail::FundamentalSolver::add(detail::apply(T1, x1[i]), detail::apply(T2, x2[i]), 1.0, &ata);
  return detail::fundamental_from_normal(ata, T1, T2, F_21);
}

double score_fundamental(const Mat3& F_21, const Vec2* x1, const Vec2* x2, int n, double sigma_px,
                         std::uint8_t* mask, int* inliers, double beat) {
  const double inv_sigma2 = 1.0 / (sigma_px * sigma_px);
  double score = 0.0;
  int count = 0;
  // A match adds at most 2 * kChi2TwoDof95. The running sum may differ from the exact one by a
  // few ulps per term, so the bound gives up a relative 1e-9 of margin (far above that).
  constexpr double kMaxPerMatch = 2.0 * kChi2TwoDof95;
  const bool bounded = beat > 0.0;
  const double target = beat * (1.0 - 1e-9);
  // One side: the point p against the epipolar line l in its image; adds to the score when it passes.
  const auto side = [&](const Vec3& l, const Vec3& p) {
    const double den = l.x() * l.x() + l.y() * l.y();
    const double num = l.dot(p);
    const double chi2 = num * num / den * inv_sigma2;
    if (!(den > 0.0) || !(chi2 <= kChi2OneDof95)) return false;
    score += kChi2TwoDof95 - chi2;
    return true;
  };
  for (int i = 0; i < n; ++i) {
    if (bounded && (i & 15) == 0 && score + kMaxPerMatch * static_cast<double>(n - i) < target) {
      *inliers = count;  // partial: the caller drops a model that cannot beat `beat`
      return score + kMaxPerMatch * static_cast<double>(n - i);
    }
    const Vec3 p1(x1[i].x(), x1[i].y(), 1.0);
    const Vec3 p2(x2[i].x(), x2[i].y(), 1.0);
    const bool in2 = side(F_21 * p1, p2);
    const bool in1 = side(F_21.transpose() * p2, p1);
    const bool in = in1 && in2;
    mask[i] = in ? 1 : 0;
    count += in ? 1 : 0;
  }
  *inliers = count;
  return score;
}

void decompose_essential(const Mat3& E_21, std::array<Mat3, 4>* R_21, std::array<Vec3, 4>* t_21) {
  const Eigen::JacobiSVD<Mat3> svd(E_21, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 U = svd.matrixU();
  Mat3 V = svd.matrixV();
  // E is defined up to sign, so flipping a column of U or V keeps it an essential matrix of the
  // same geometry; it makes both proper rotations so that U W V^T is one.
  if (U.determinant() < 0.0) U.col(2) = -U.col(2);
  if (V.determinant() < 0.0) V.col(2) = -V.col(2);
  Mat3 W;
  W << 0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0;
  const Mat3 Ra = U * W * V.transpose();
  const Mat3 Rb = U * W.transpose() * V.transpose();
  const Vec3 t = U.col(2).normalized();
  *R_21 = {Ra, Ra, Rb, Rb};
  *t_21 = {t, -t, t, -t};
}

Status estimate_fundamental(const Vec2* x1, const Vec2* x2, int n, const TwoViewParams& params, Mat3* F_21,
                            std::vector<std::uint8_t>& mask, RansacStats* stats, TwoViewScratch& scratch) {
  return detail::estimate_linear<detail::FundamentalSolver>(x1, x2, n, params, "fundamental", F_21, mask, stats, scratch);
}

}  // namespace ale::geometry
