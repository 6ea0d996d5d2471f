// The homography: normalised DLT, ORB-SLAM's score, its RANSAC, and Faugeras' decomposition.
#include <Eigen/LU>
#include <Eigen/SVD>

#include "core/geometry/two_view.h"
#include "core/geometry/two_view_detail.h"

namespace ale::geometry {

using detail::Mat9;
using detail::Vec9;

namespace {

// H from the normal matrix of normalised matches; false when it does not fix one solution or
// the homography is singular (no inverse for the transfer back to image 1).
bool homography_from_normal(const Mat9& ata, const Mat3& T1, const Mat3& T2, Mat3* H_21) {
  Vec9 h;
  if (!detail::null_vector(ata, &h)) return false;
  const Mat3 H = detail::denormalise_homography(detail::to_mat3(h), T1, T2);
  const double norm = H.norm();
  if (!(norm > 0.0) || !H.allFinite()) return false;
  *H_21 = H / norm;
  // A determinant this small relative to the unit norm means a rank-deficient map (the points
  // were collinear in one image).
  return std::abs(H_21->determinant()) > 1e-12;
}

struct HomographyPair {
  Mat3 H_21;
  Mat3 H_12;
};

// The least-squares DLT of 8-point samples (the fundamental matrix's samples for the same seed),
// scored in pixels in both directions.
struct HomographySolver {
  using Model = HomographyPair;
  static void add(const Vec2& n1, const Vec2& n2, double weight, Mat9* ata) {
    detail::add_homography_rows(n1, n2, weight, ata);
  }
  static bool solve(const Mat9& ata, const detail::MatchSet& m, Model* h) {
    if (!homography_from_normal(ata, m.T1, m.T2, &h->H_21)) return false;
    h->H_12 = h->H_21.inverse();
    return true;
  }
  static double score(const Model& h, const detail::MatchSet& m, std::uint8_t* mask, int* inliers) {
    return score_homography(h.H_21, h.H_12, m.x1, m.x2, m.n, m.sigma_px, mask, inliers);
  }
  // The DLT's residuals are already transfer errors scaled by the third coordinate, close to 1
  // in normalised coordinates: equal weights.
  struct Weights {};
  static Weights prepare(const Model&, const detail::MatchSet&) { return {}; }
  static double weight(const Weights&, const Vec2&, const Vec2&) { return 1.0; }
};

}  // namespace

bool homography_dlt(const Vec2* x1, const Vec2* x2, int n, Mat3* H_21) {
  if (n < 4) return false;
  Mat3 T1, T2;
  if (!hartley_normalisation(x1, n, &T1) || !hartley_normalisation(x2, n, &T2)) return false;
  Mat9 ata = Mat9::Zero();
  for (int i = 0; i < n; ++i) detail::add_homography_rows(detail::apply(T1, x1[i]), detail::apply(T2, x2[i]), 1.0, &ata);
  return homography_from_normal(ata, T1, T2, H_21);
}

double score_homography(const Mat3& H_21, const Mat3& H_12, const Vec2* x1, const Vec2* x2, int n, double sigma_px,
                        std::uint8_t* mask, int* inliers) {
  const double inv_sigma2 = 1.0 / (sigma_px * sigma_px);
  double score = 0.0;
  int count = 0;
  // One direction: the transfer of `from` by H against `to`; adds to the score when it passes.
  const auto side = [&](const Mat3& H, const Vec2& from, const Vec2& to) {
    const Vec3 w = H * Vec3(from.x(), from.y(), 1.0);
    if (!(std::abs(w.z()) > 1e-12)) return false;
    const double chi2 = (to - w.head<2>() / w.z()).squaredNorm() * inv_sigma2;
    if (!(chi2 <= kChi2TwoDof95)) return false;
    score += kChi2TwoDof95 - chi2;
    return true;
  };
  for (int i = 0; i < n; ++i) {
    const bool in2 = side(H_21, x1[i], x2[i]);
    const bool in1 = side(H_12, x2[i], x1[i]);
    const bool in = in1 && in2;
    mask[i] = in ? 1 : 0;
    count += in ? 1 : 0;
  }
  *inliers = count;
  return score;
}

int decompose_homography(const Mat3& A_21, std::array<Mat3, 8>* R_21, std::array<Vec3, 8>* t_21,
                         std::array<Vec3, 8>* n_1) {
  if (!A_21.allFinite()) return 0;
  const Eigen::JacobiSVD<Mat3> svd(A_21, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Mat3& U = svd.matrixU();
  const Mat3& V = svd.matrixV();
  const double s = U.determinant() * V.determinant();
  const Vec3 sv = svd.singularValues();
  const double d1 = sv(0), d2 = sv(1), d3 = sv(2);
  if (!(d3 > 0.0) || d1 / d2 < 1.00001 || d2 / d3 < 1.00001) return 0;

  // In the SVD's frame, diag(d1, d2, d3) = d' R' + t' n'^T with d' = +-d2 (Faugeras 1988,
  // "Motion and structure from motion in a piecewise planar environment"); n' = (x1, 0, x3).
  const double d1s = d1 * d1, d2s = d2 * d2, d3s = d3 * d3;
  const double x1 = std::sqrt((d1s - d2s) / (d1s - d3s));
  const double x3 = std::sqrt((d2s - d3s) / (d1s - d3s));
  const double e1[4] = {1.0, 1.0, -1.0, -1.0};
  const double e3[4] = {1.0, -1.0, 1.0, -1.0};
  const double root = std::sqrt((d1s - d2s) * (d2s - d3s));
  int k = 0;
  for (int branch = 0; branch < 2; ++branch) {
    const bool positive = branch == 0;  // d' = d2 or d' = -d2
    const double d_prime = positive ? d2 : -d2;
    // sin and cos of the rotation about the second axis of the SVD frame.
    const double sin_abs = positive ? root / ((d1 + d3) * d2) : root / ((d1 - d3) * d2);
    const double c = positive ? (d2s + d1 * d3) / ((d1 + d3) * d2) : (d1 * d3 - d2s) / ((d1 - d3) * d2);
    for (int i = 0; i < 4; ++i) {
      const double sn = sin_abs * e1[i] * e3[i];
      Mat3 Rp;
      if (positive) {
        Rp << c, 0.0, -sn, 0.0, 1.0, 0.0, sn, 0.0, c;
      } else {
        Rp << c, 0.0, sn, 0.0, -1.0, 0.0, sn, 0.0, -c;
      }
      const Mat3 R = s * U * Rp * V.transpose();
      // n keeps the sign the solution gives it: (R, t, n) and (R, -t, -n) explain the same
      // homography, and only cheirality tells the two poses apart.
      const Vec3 n = V * Vec3(e1[i] * x1, 0.0, e3[i] * x3);
      // A = s d' R + (U t')(V n')^T, so A / (s d') = R + t n^T with t = (A / (s d') - R) n for
      // the unit n.
      const Vec3 t = (A_21 / (s * d_prime) - R) * n;
      (*R_21)[static_cast<std::size_t>(k)] = R;
      (*t_21)[static_cast<std::size_t>(k)] = t;
      (*n_1)[static_cast<std::size_t>(k)] = n;
      ++k;
    }
  }
  return k;
}

Status estimate_homography(const Vec2* x1, const Vec2* x2, int n, const TwoViewParams& params, Mat3* H_21,
                           std::vector<std::uint8_t>& mask, RansacStats* stats, TwoViewScratch& scratch) {
  HomographyPair best;
  ALE_RETURN_IF_ERROR(detail::estimate_linear<HomographySolver>(x1, x2, n, params, "homography", &best, mask, stats, scratch));
  *H_21 = best.H_21;
  return Status::ok_status();
}

}  // namespace ale::geometry
