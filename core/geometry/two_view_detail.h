// Pieces shared by fundamental.cpp, homography.cpp and two_view.cpp (not part of the API).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "core/geometry/two_view.h"

namespace ale::geometry::detail {

using Mat9 = Eigen::Matrix<double, 9, 9>;
using Vec9 = Eigen::Matrix<double, 9, 1>;

inline bool finite(const Vec2& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

inline Vec2 apply(const Mat3& T, const Vec2& p) {
  // T is a similarity (last row 0 0 1).
  return Vec2(T(0, 0) * p.x() + T(0, 2), T(1, 1) * p.y() + T(1, 2));
}

// The unit null vector of a 9x9 normal matrix A^T A, sign-normalised (largest entry positive,
// so that the same data give the same matrix). false when the second-smallest eigenvalue is
// within 1e-12 of the largest (the null space is not one-dimensional) or the matrix is not finite.
inline bool null_vector(const Mat9& ata, Vec9* v) {
  if (!ata.allFinite()) return false;
  const Eigen::SelfAdjointEigenSolver<Mat9> es(ata);
  if (es.info() != Eigen::Success) return false;
  const Vec9& ev = es.eigenvalues();  // ascending
  if (!(ev(8) > 0.0) || ev(1) <= 1e-12 * ev(8)) return false;
  *v = es.eigenvectors().col(0);
  Eigen::Index k = 0;
  v->cwiseAbs().maxCoeff(&k);
  if ((*v)(k) < 0.0) *v = -*v;
  return true;
}

inline Mat3 to_mat3(const Vec9& v) {
  Mat3 m;
  m << v(0), v(1), v(2), v(3), v(4), v(5), v(6), v(7), v(8);
  return m;
}

// Validates the matches and writes their Hartley-normalised copies into scratch.n1 / n2.
inline Status normalise_matches(const Vec2* x1, const Vec2* x2, int n, int min_matches, const char* who,
                                TwoViewScratch& scratch, Mat3* T1, Mat3* T2) {
  if (n < min_matches)
    return invalid_argument(std::string(who) + ": " + std::to_string(n) + " matches, at least " +
                            std::to_string(min_matches) + " needed");
  for (int i = 0; i < n; ++i)
    if (!finite(x1[i]) || !finite(x2[i]))
      return invalid_argument(std::string(who) + ": match " + std::to_string(i) + " has a non-finite coordinate");
  if (!hartley_normalisation(x1, n, T1) || !hartley_normalisation(x2, n, T2))
    return invalid_argument(std::string(who) + ": all points of an image coincide");
  scratch.n1.resize(static_cast<std::size_t>(n));
  scratch.n2.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    scratch.n1[static_cast<std::size_t>(i)] = apply(*T1, x1[i]);
    scratch.n2[static_cast<std::size_t>(i)] = apply(*T2, x2[i]);
  }
  return Status::ok_status();
}

// Normal-matrix rows: the epipolar constraint x2^T F x1 = 0 and the two DLT rows of x2 ~ H x1,
// each as one row vector a (the equation is a . vec(M) = 0, vec row-major).
inline Vec9 epipolar_row(const Vec2& p1, const Vec2& p2) {
  Vec9 a;
  a << p2.x() * p1.x(), p2.x() * p1.y(), p2.x(), p2.y() * p1.x(), p2.y() * p1.y(), p2.y(), p1.x(), p1.y(), 1.0;
  return a;
}

inline void add_homography_rows(const Vec2& p1, const Vec2& p2, double weight, Mat9* ata) {
  Vec9 a, b;
  a << 0.0, 0.0, 0.0, -p1.x(), -p1.y(), -1.0, p2.y() * p1.x(), p2.y() * p1.y(), p2.y();
  b << p1.x(), p1.y(), 1.0, 0.0, 0.0, 0.0, -p2.x() * p1.x(), -p2.x() * p1.y(), -p2.x();
  ata->noalias() += weight * (a * a.transpose());
  ata->noalias() += weight * (b * b.transpose());
}

// The matches a RANSAC problem sees: pixels (for scoring) and their normalised copies (for fitting).
struct MatchSet {
  const Vec2* x1;
  const Vec2* x2;
  const Vec2* n1;
  const Vec2* n2;
  Mat3 T1, T2;
  int n;
  double sigma_px;
  Mat3 K;  // the pinhole's intrinsics where a solver needs them (the essential refit), else identity
};

// A linear two-view model as a RANSAC problem (ransac.h). Solver provides Model and
//   // one match's normal-matrix rows, times weight
//   static void add(const Vec2& n1, const Vec2& n2, double weight, Mat9* ata);
//   static bool solve(const Mat9& ata, const MatchSet& m, Model* model);
//   static double score(const Model& model, const MatchSet& m, std::uint8_t* mask, int* inliers);
//   // Refit weights: Weights prepare(const Model&, const MatchSet&) once per refit, then
//   // double weight(const Weights&, const Vec2& n1, const Vec2& n2) per match.
template <class Solver>
struct LinearProblem {
  static constexpr int kSampleSize = kTwoViewSampleSize;
  static constexpr int kMaxModels = 1;
  using Model = typename Solver::Model;

  MatchSet m;

  int size() const { return m.n; }
  int fit(const int* sample, Model* models) const {
    Mat9 ata = Mat9::Zero();
    for (int k = 0; k < kSampleSize; ++k) Solver::add(m.n1[sample[k]], m.n2[sample[k]], 1.0, &ata);
    return Solver::solve(ata, m, &models[0]) ? 1 : 0;
  }
  double score(const Model& model, std::uint8_t* mask, int* inliers) const {
    return Solver::score(model, m, mask, inliers);
  }
};

// Gate scale of each refit round: from three times the noise down to the real gate.
constexpr int kRefitRounds = 6;
constexpr double kRefitSigmaScale[kRefitRounds] = {3.0, 2.0, 1.5, 1.0, 1.0, 1.0};

// Local optimisation (in the spirit of LO-RANSAC, Chum et al. 2003) of a RANSAC winner: the
// minimal models under pixel noise are coarse (on the 1 px synthetic scenes the best of 200
// 8-point samples holds 55-90 % of the true inliers), and a least-squares refit on only their
// inliers can settle on that subset. So each round refits on the matches within a looser gate
// (sigma scaled by kRefitSigmaScale) and keeps the refit when its score at the real gate improves.
template <class Solver>
void local_refit(const MatchSet& m, const Vec2* n1, const Vec2* n2, typename Solver::Model* best,
                 std::vector<std::uint8_t>& mask, RansacStats* st, TwoViewScratch& scratch) {
  const int n = m.n;
  for (int round = 0; round < kRefitRounds; ++round) {
    MatchSet loose = m;
    loose.sigma_px *= kRefitSigmaScale[round];
    scratch.mask_tmp.resize(static_cast<std::size_t>(n));
    int loose_inliers = 0;
    Solver::score(*best, loose, scratch.mask_tmp.data(), &loose_inliers);
    const typename Solver::Weights weights = Solver::prepare(*best, m);
    Mat9 ata = Mat9::Zero();
    for (int i = 0; i < n; ++i) {
      if (!scratch.mask_tmp[static_cast<std::size_t>(i)]) continue;
      Solver::add(n1[i], n2[i], Solver::weight(weights, n1[i], n2[i]), &ata);
    }
    typename Solver::Model refit;
    if (!Solver::solve(ata, m, &refit)) continue;
    int inliers = 0;
    const double score = Solver::score(refit, m, scratch.mask_tmp.data(), &inliers);
    if (!(score > st->score)) continue;
    *best = refit;
    st->score = score;
    st->inliers = inliers;
    mask.swap(scratch.mask_tmp);
  }
}

// Validates and normalises the matches, runs RANSAC with 8-point samples, then (when asked)
// refines the winner by local_refit.
template <class Solver>
Status estimate_linear(const Vec2* x1, const Vec2* x2, int n, const TwoViewParams& params, const char* who,
                       typename Solver::Model* best, std::vector<std::uint8_t>& mask, RansacStats* stats,
                       TwoViewScratch& scratch) {
  ALE_RETURN_IF_ERROR(validate(params));
  Mat3 T1, T2;
  ALE_RETURN_IF_ERROR(normalise_matches(x1, x2, n, kTwoViewSampleSize, who, scratch, &T1, &T2));
  const LinearProblem<Solver> problem{
      {x1, x2, scratch.n1.data(), scratch.n2.data(), T1, T2, n, params.sigma_px, Mat3::Identity()}};
  RansacStats st;
  const Status s = ransac(problem, params.ransac, kTwoViewSampleSize, best, mask, &st, scratch.ransac);
  if (!s.ok()) {
    if (stats) *stats = st;
    return Status(s.code(), std::string(who) + ": " + s.message());
  }
  if (params.refine_on_inliers) local_refit<Solver>(problem.m, scratch.n1.data(), scratch.n2.data(), best, mask, &st, scratch);
  if (stats) *stats = st;
  return Status::ok_status();
}

// F from the normal matrix of Hartley-normalised matches (rank 2, unit Frobenius norm, in
// pixels); false when it does not fix one solution (fundamental.cpp).
bool fundamental_from_normal(const Mat9& ata, const Mat3& T1, const Mat3& T2, Mat3* F_21);

// Gauss-Newton on the Sampson error of E = hat(t) R over the matches of r1, r2 (normalised
// image-plane coordinates) where use[i] is 1; *R, *t kept when the cost does not decrease
// (two_view.cpp).
void refine_pose_sampson(const Vec2* r1, const Vec2* r2, int n, const std::uint8_t* use, Mat3* R, Vec3* t);

// The 8-point F as a solver of estimate_linear / local_refit.
struct FundamentalSolver {
  using Model = Mat3;
  static void add(const Vec2& n1, const Vec2& n2, double weight, Mat9* ata) {
    const Vec9 a = epipolar_row(n1, n2);
    ata->noalias() += weight * (a * a.transpose());
  }
  static bool solve(const Mat9& ata, const MatchSet& m, Model* F) { return fundamental_from_normal(ata, m.T1, m.T2, F); }
  static double score(const Model& F, const MatchSet& m, std::uint8_t* mask, int* inliers) {
    return score_fundamental(F, m.x1, m.x2, m.n, m.sigma_px, mask, inliers);
  }
  // Sampson weights: dividing each algebraic residual x2^T F x1 by its gradient's norm turns the
  // least squares into a first-order geometric fit (Torr and Murray 1997), which the plain
  // algebraic one is not: on the 1 px synthetic scenes it halves the translation direction error.
  using Weights = Mat3;  // F in normalised coordinates
  static Weights prepare(const Model& F, const MatchSet& m) { return m.T2.inverse().transpose() * F * m.T1.inverse(); }
  static double weight(const Weights& Fn, const Vec2& n1, const Vec2& n2) {
    const Vec3 l2 = Fn * Vec3(n1.x(), n1.y(), 1.0);
    const Vec3 l1 = Fn.transpose() * Vec3(n2.x(), n2.y(), 1.0);
    const double g = l2.x() * l2.x() + l2.y() * l2.y() + l1.x() * l1.x() + l1.y() * l1.y();
    return g > 1e-300 ? 1.0 / g : 1.0;
  }
};

// F (or H) estimated in normalised coordinates back to pixels.
inline Mat3 denormalise_fundamental(const Mat3& Fn, const Mat3& T1, const Mat3& T2) { return T2.transpose() * Fn * T1; }
inline Mat3 denormalise_homography(const Mat3& Hn, const Mat3& T1, const Mat3& T2) { return T2.inverse() * Hn * T1; }

}  // namespace ale::geometry::detail
