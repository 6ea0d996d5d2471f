// The five-point essential matrix (essential.h) and its RANSAC.
#include "core/geometry/essential.h"

#include <algorithm>
#include <complex>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "core/geometry/two_view_detail.h"

namespace ale::geometry {

namespace {

// Polynomials in (x, y, z) of degree <= 3, as coefficients over kMonomials' order: the ten
// cubics first (they are eliminated), then the quotient basis x^2 xy xz y^2 yz z^2 x y z 1.
constexpr int kMonomials = 20;
constexpr int kExponents[kMonomials][3] = {{3, 0, 0}, {2, 1, 0}, {2, 0, 1}, {1, 2, 0}, {1, 1, 1}, {1, 0, 2}, {0, 3, 0},
                                           {0, 2, 1}, {0, 1, 2}, {0, 0, 3}, {2, 0, 0}, {1, 1, 0}, {1, 0, 1}, {0, 2, 0},
                                           {0, 1, 1}, {0, 0, 2}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 0}};
constexpr int kX = 16, kY = 17, kZ = 18, kOne = 19;

struct Poly {
  std::array<double, kMonomials> c{};
};

// product_index[i][j]: the monomial of monomial i times monomial j, -1 above degree 3.
struct ProductTable {
  int index[kMonomials][kMonomials];
  ProductTable() {
    for (int i = 0; i < kMonomials; ++i)
      for (int j = 0; j < kMonomials; ++j) {
        index[i][j] = -1;
        for (int k = 0; k < kMonomials; ++k)
          if (kExponents[k][0] == kExponents[i][0] + kExponents[j][0] &&
              kExponents[k][1] == kExponents[i][1] + kExponents[j][1] &&
              kExponents[k][2] == kExponents[i][2] + kExponents[j][2])
            index[i][j] = k;
      }
  }
};

const ProductTable& product_table() {
  static const ProductTable table;
  return table;
}

// a * b, dropping terms above degree 3 (the callers' products never have any). Only b's nonzero
// terms are visited (the callers' b is linear: 4 of 20): a skipped term would add a zero, which
// leaves every sum as it is (the sums start at +0), so the result is the same to the bit.
Poly mul(const Poly& a, const Poly& b) {
  const ProductTable& t = product_table();
  int nz[kMonomials];
  int count = 0;
  for (int j = 0; j < kMonomials; ++j) {
    if (b.c[static_cast<std::size_t>(j)] != 0.0) nz[count++] = j;
  }
  Poly r;
  for (int i = 0; i < kMonomials; ++i) {
    const double ai = a.c[static_cast<std::size_t>(i)];
    if (ai == 0.0) continue;
    for (int n = 0; n < count; ++n) {
      const int j = nz[n];
      const int k = t.index[i][j];
      if (k >= 0) r.c[static_cast<std::size_t>(k)] += ai * b.c[static_cast<std::size_t>(j)];
    }
  }
  return r;
}

void add_scaled(const Poly& a, double s, Poly* r) {
  for (int i = 0; i < kMonomials; ++i) r->c[static_cast<std::size_t>(i)] += s * a.c[static_cast<std::size_t>(i)];
}

using Mat10 = Eigen::Matrix<double, 10, 10>;

}  // namespace

int essential_5point(const Vec2* q1, const Vec2* q2, std::array<Mat3, kEssentialMaxSolutions>* E_21) {
  Eigen::Matrix<double, kEssentialSampleSize, 9> A;
  for (int i = 0; i < kEssentialSampleSize; ++i) {
    if (!detail::finite(q1[i]) || !detail::finite(q2[i])) return 0;
    A.row(i) = detail::epipolar_row(q1[i], q2[i]).transpose();
  }
  // The null space from the full SVD of A (9 x 9 V): its last four columns. Rank below 5 (a
  // repeated point, ...) leaves a larger null space, i.e. no finite set of solutions.
  const Eigen::JacobiSVD<Eigen::Matrix<double, 9, 9>> svd(
      (Eigen::Matrix<double, 9, 9>() << A, Eigen::Matrix<double, 4, 9>::Zero()).finished(), Eigen::ComputeFullV);
  const auto& sv = svd.singularValues();
  if (!(sv(0) > 0.0) || sv(4) <= 1e-10 * sv(0)) return 0;
  const Eigen::Matrix<double, 9, 9>& V = svd.matrixV();

  // E's entries as linear polynomials x X + y Y + z Z + W.
  Poly e[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const int k = 3 * r + c;
      e[r][c].c[kX] = V(k, 5);
      e[r][c].c[kY] = V(k, 6);
      e[r][c].c[kZ] = V(k, 7);
      e[r][c].c[kOne] = V(k, 8);
    }
  // E E^T (quadratic) and its trace.
  Poly eet[3][3];
  Poly trace;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) add_scaled(mul(e[i][k], e[j][k]), 1.0, &eet[i][j]);
      if (i == j) add_scaled(eet[i][j], 1.0, &trace);
    }
  // Ten cubic constraints: det(E) and the nine entries of 2 E E^T E - tr(E E^T) E.
  Eigen::Matrix<double, 10, kMonomials> M;
  const Poly minor0 = mul(e[1][1], e[2][2]), minor0b = mul(e[1][2], e[2][1]);
  const Poly minor1 = mul(e[1][0], e[2][2]), minor1b = mul(e[1][2], e[2][0]);
  const Poly minor2 = mul(e[1][0], e[2][1]), minor2b = mul(e[1][1], e[2][0]);
  Poly m0 = minor0, m1 = minor1, m2 = minor2;
  add_scaled(minor0b, -1.0, &m0);
  add_scaled(minor1b, -1.0, &m1);
  add_scaled(minor2b, -1.0, &m2);
  Poly det = mul(e[0][0], m0);
  add_scaled(mul(e[0][1], m1), -1.0, &det);
  add_scaled(mul(e[0][2], m2), 1.0, &det);
  for (int k = 0; k < kMonomials; ++k) M(0, k) = det.c[static_cast<std::size_t>(k)];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Poly p = mul(trace, e[i][j]);
      for (int k = 0; k < kMonomials; ++k) p.c[static_cast<std::size_t>(k)] = -p.c[static_cast<std::size_t>(k)];
      for (int k = 0; k < 3; ++k) add_scaled(mul(eet[i][k], e[k][j]), 2.0, &p);
      for (int k = 0; k < kMonomials; ++k) M(1 + 3 * i + j, k) = p.c[static_cast<std::size_t>(k)];
    }
  // Gauss-Jordan on the cubic monomials: cubic_i = -G.row(i) . basis.
  const Eigen::FullPivLU<Mat10> lu(M.leftCols<10>());
  if (!lu.isInvertible()) return 0;
  const Mat10 G = lu.solve(M.rightCols<10>());
  if (!G.allFinite()) return 0;
  // Multiplication by x on the basis b = (x^2 xy xz y^2 yz z^2 x y z 1): x b = Ax b. x times
  // x^2 .. z^2 are the cubics x^3 x^2y x^2z xy^2 xyz xz^2 (rows 0-5 of G); x times x y z 1 are
  // basis monomials x^2 xy xz x.
  Mat10 Ax = Mat10::Zero();
  Ax.topRows<6>() = -G.topRows<6>();
  Ax(6, 0) = 1.0;
  Ax(7, 1) = 1.0;
  Ax(8, 2) = 1.0;
  Ax(9, 6) = 1.0;
  const Eigen::EigenSolver<Mat10> es(Ax);
  if (es.info() != Eigen::Success) return 0;
  int count = 0;
  for (int s = 0; s < 10; ++s) {
    const std::complex<double> lambda = es.eigenvalues()(s);
    if (std::abs(lambda.imag()) > 1e-8 * (1.0 + std::abs(lambda.real()))) continue;
    const Eigen::Matrix<std::complex<double>, 10, 1> v = es.eigenvectors().col(s);
    if (std::abs(v(9)) < 1e-12 * v.norm()) continue;  // the solution is at infinity in (x, y, z)
    const double x = (v(6) / v(9)).real();
    const double y = (v(7) / v(9)).real();
    const double z = (v(8) / v(9)).real();
    Eigen::Matrix<double, 9, 1> ev = x * V.col(5) + y * V.col(6) + z * V.col(7) + V.col(8);
    const double norm = ev.norm();
    if (!(norm > 0.0) || !ev.allFinite()) continue;
    ev /= norm;
    (*E_21)[static_cast<std::size_t>(count++)] = detail::to_mat3(ev);
  }
  return count;
}

namespace {

// F_21 = K^-T E K^-1 at unit Frobenius norm.
Mat3 fundamental_of(const Mat3& E, const Mat3& K_inv) {
  const Mat3 F = K_inv.transpose() * E * K_inv;
  return F / F.norm();
}

// The five-point samples as a RANSAC problem (ransac.h); models are pixel F matrices.
struct EssentialProblem {
  static constexpr int kSampleSize = kEssentialSampleSize;
  static constexpr int kMaxModels = kEssentialMaxSolutions;
  using Model = Mat3;

  detail::MatchSet m;
  const Vec2* q1;  // K^-1 x1
  const Vec2* q2;
  Mat3 K_inv;

  int size() const { return m.n; }
  int fit(const int* sample, Model* models) const {
    Vec2 a[kSampleSize], b[kSampleSize];
    for (int k = 0; k < kSampleSize; ++k) {
      a[k] = q1[sample[k]];
      b[k] = q2[sample[k]];
    }
    std::array<Mat3, kEssentialMaxSolutions> E;
    const int count = essential_5point(a, b, &E);
    int out = 0;
    for (int s = 0; s < count; ++s) {
      const Mat3 F = fundamental_of(E[static_cast<std::size_t>(s)], K_inv);
      if (F.allFinite()) models[out++] = F;
    }
    return out;
  }
  double score(const Model& F, std::uint8_t* mask, int* inliers) const {
    return score_fundamental(F, m.x1, m.x2, m.n, m.sigma_px, mask, inliers);
  }
  // ransac.h's early exit: the exact score when it is above beat.
  double score(const Model& F, std::uint8_t* mask, int* inliers, double beat) const {
    return score_fundamental(F, m.x1, m.x2, m.n, m.sigma_px, mask, inliers, beat);
  }
};

// Local optimisation on the essential matrices themselves: a linear 8-point refit would hand
// back the two extra degrees of freedom that overfit near-planar scenes, so each round refines
// (R, t) by Gauss-Newton on the Sampson error over the matches within a looser gate
// (kRefitSigmaScale, as the 8-point path) and keeps the result when the score improves. Any of
// E's four decompositions parametrises the same E up to sign, so the first one serves.
// scratch.r1 / r2 hold K^-1 x.
void refine_essential(const Vec2* x1, const Vec2* x2, int n, const Mat3& K, const Mat3& K_inv, const TwoViewParams& params,
                      Mat3* F_21, std::vector<std::uint8_t>& mask, RansacStats* st, TwoViewScratch& scratch) {
  for (int round = 0; params.refine_on_inliers && round < detail::kRefitRounds; ++round) {
    scratch.mask_tmp.resize(static_cast<std::size_t>(n));
    int loose_inliers = 0;
    score_fundamental(*F_21, x1, x2, n, params.sigma_px * detail::kRefitSigmaScale[round], scratch.mask_tmp.data(),
                      &loose_inliers);
    if (loose_inliers < kEssentialSampleSize) break;
    std::array<Mat3, 4> Rs;
    std::array<Vec3, 4> ts;
    decompose_essential(K.transpose() * *F_21 * K, &Rs, &ts);
    Mat3 R = Rs[0];
    Vec3 t = ts[0];
    detail::refine_pose_sampson(scratch.r1.data(), scratch.r2.data(), n, scratch.mask_tmp.data(), &R, &t);
    const Mat3 refit = fundamental_of(hat(t) * R, K_inv);
    if (!refit.allFinite()) continue;
    int inliers = 0;
    const double score = score_fundamental(refit, x1, x2, n, params.sigma_px, scratch.mask_tmp.data(), &inliers);
    if (!(score > st->score)) continue;
    *F_21 = refit;
    st->score = score;
    st->inliers = inliers;
    mask.swap(scratch.mask_tmp);
  }
}

// Validates the input and fills scratch.n1 / n2 (Hartley) and r1 / r2 (K^-1 x); the problem
// the five-point RANSAC samples.
Status prepare_essential(const Vec2* x1, const Vec2* x2, int n, const Mat3& K, const TwoViewParams& params,
                         TwoViewScratch& scratch, EssentialProblem* problem) {
  ALE_RETURN_IF_ERROR(validate(params));
  if (!K.allFinite() || !(std::abs(K.determinant()) > 0.0))
    return invalid_argument("essential: the intrinsics matrix is not finite and invertible");
  Mat3 T1, T2;
  ALE_RETURN_IF_ERROR(detail::normalise_matches(x1, x2, n, kTwoViewSampleSize, "essential", scratch, &T1, &T2));
  const Mat3 K_inv = K.inverse();
  scratch.r1.resize(static_cast<std::size_t>(n));
  scratch.r2.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    scratch.r1[static_cast<std::size_t>(i)] = (K_inv * Vec3(x1[i].x(), x1[i].y(), 1.0)).hnormalized();
    scratch.r2[static_cast<std::size_t>(i)] = (K_inv * Vec3(x2[i].x(), x2[i].y(), 1.0)).hnormalized();
  }
  *problem = EssentialProblem{{x1, x2, scratch.n1.data(), scratch.n2.data(), T1, T2, n, params.sigma_px, K},
                              scratch.r1.data(),
                              scratch.r2.data(),
                              K_inv};
  return Status::ok_status();
}

// Unit-norm calibrated E of a pixel F, sign fixed by its largest entry.
Mat3 unit_essential(const Mat3& F_21, const Mat3& K) {
  Mat3 E = K.transpose() * F_21 * K;
  const double norm = E.norm();
  if (!(norm > 0.0)) return Mat3::Zero();
  E /= norm;
  Eigen::Index r = 0, c = 0;
  E.cwiseAbs().maxCoeff(&r, &c);
  return E(r, c) < 0.0 ? Mat3(-E) : E;
}

}  // namespace

double essential_distance(const Mat3& F_a, const Mat3& F_b, const Mat3& K) {
  const Mat3 a = unit_essential(F_a, K);
  const Mat3 b = unit_essential(F_b, K);
  return std::min((a - b).norm(), (a + b).norm());
}

Status estimate_essential(const Vec2* x1, const Vec2* x2, int n, const Mat3& K, const TwoViewParams& params,
                          Mat3* F_21, std::vector<std::uint8_t>& mask, RansacStats* stats, TwoViewScratch& scratch) {
  EssentialProblem problem{};
  ALE_RETURN_IF_ERROR(prepare_essential(x1, x2, n, K, params, scratch, &problem));
  // Every sample up to the cap: the adaptive count assumes the best model's inliers are the
  // true ones, which on near-planar scenes a wrong essential matrix (fitting the plane) can
  // also claim, and five-point samples make the count small (57 for 60 % inliers).
  RansacParams rp = params.ransac;
  rp.min_iterations = std::max(rp.min_iterations, rp.max_iterations);
  RansacStats st;
  const Status s = ransac(problem, rp, kTwoViewSampleSize, F_21, mask, &st, scratch.ransac);
  if (!s.ok()) {
    if (stats) *stats = st;
    return Status(s.code(), std::string("essential: ") + s.message());
  }
  refine_essential(x1, x2, n, K, problem.K_inv, params, F_21, mask, &st, scratch);
  if (stats) *stats = st;
  return Status::ok_status();
}

Status estimate_essential_hypotheses(const Vec2* x1, const Vec2* x2, int n, const Mat3& K, const TwoViewParams& params,
                                     const EssentialHypothesesParams& hp, std::vector<EssentialHypothesis>* out,
                                     TwoViewScratch& scratch, const std::function<double(const Mat3& F_21)>& rescore) {
  out->clear();
  if (hp.max_hypotheses < 1 || !(hp.min_separation >= 0.0) || hp.candidates_per_hypothesis < 1)
    return invalid_argument("essential hypotheses: max_hypotheses and candidates_per_hypothesis must be >= 1, "
                            "min_separation >= 0");
  EssentialProblem problem{};
  ALE_RETURN_IF_ERROR(prepare_essential(x1, x2, n, K, params, scratch, &problem));
  // The same sample stream as ransac() with this seed, every sample up to the cap; the pool of
  // raw candidates keeps the best-scoring model of each neighbourhood (min_separation), more of
  // them than are returned, since local refinement can take two to one optimum.
  const int pool_size = hp.max_hypotheses * hp.candidates_per_hypothesis;
  std::vector<EssentialHypothesis> pool;
  pool.reserve(static_cast<std::size_t>(pool_size));
  scratch.ransac.pool.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) scratch.ransac.pool[static_cast<std::size_t>(i)] = i;
  SplitMix64 rng(params.ransac.seed);
  int sample[kEssentialSampleSize];
  Mat3 models[kEssentialMaxSolutions];
  const int cap = std::max(params.ransac.max_iterations, 1);
  std::vector<EssentialHypothesis>& models_seen = scratch.hypotheses_tmp;
  models_seen.clear();
  double best_own = 0.0;
  for (int it = 0; it < cap; ++it) {
    ransac_draw(rng, n, kEssentialSampleSize, scratch.ransac.pool, sample);
    const int m = problem.fit(sample, models);
    for (int j = 0; j < m; ++j) {
      int inliers = 0;
      scratch.mask_tmp.resize(static_cast<std::size_t>(n));
      const double score = problem.score(models[j], scratch.mask_tmp.data(), &inliers);
      if (inliers < kTwoViewSampleSize) continue;
      models_seen.push_back({models[j], score, inliers});
      best_own = std::max(best_own, score);
    }
  }
  for (EssentialHypothesis& cand : models_seen) {
    if (rescore) {
      if (cand.score < hp.rescore_min_share * best_own) continue;
      cand.score = rescore(cand.F_21);
    }
    int near = -1, worst = -1;
    for (int k = 0; k < static_cast<int>(pool.size()); ++k) {
      const EssentialHypothesis& h = pool[static_cast<std::size_t>(k)];
      if (near < 0 && essential_distance(h.F_21, cand.F_21, K) < hp.min_separation) near = k;
      if (worst < 0 || h.score < pool[static_cast<std::size_t>(worst)].score) worst = k;
    }
    if (near >= 0) {
      if (cand.score > pool[static_cast<std::size_t>(near)].score) pool[static_cast<std::size_t>(near)] = cand;
    } else if (static_cast<int>(pool.size()) < pool_size) {
      pool.push_back(cand);
    } else if (cand.score > pool[static_cast<std::size_t>(worst)].score) {
      pool[static_cast<std::size_t>(worst)] = cand;
    }
  }
  if (pool.empty()) return not_found("essential hypotheses: no model has " + std::to_string(kTwoViewSampleSize) + " inliers");
  for (EssentialHypothesis& h : pool) {
    if (rescore) break;
    RansacStats st;
    st.score = h.score;
    st.inliers = h.inliers;
    refine_essential(x1, x2, n, K, problem.K_inv, params, &h.F_21, scratch.mask_f, &st, scratch);
    h.score = st.score;
    h.inliers = st.inliers;
  }
  std::stable_sort(pool.begin(), pool.end(),
                   [](const EssentialHypothesis& a, const EssentialHypothesis& b) { return a.score > b.score; });
  for (const EssentialHypothesis& h : pool) {
    bool distinct = true;
    for (const EssentialHypothesis& kept : *out)
      distinct = distinct && essential_distance(kept.F_21, h.F_21, K) >= hp.min_separation;
    if (distinct) out->push_back(h);
    if (static_cast<int>(out->size()) == hp.max_hypotheses) break;
  }
  return Status::ok_status();
}

}  // namespace ale::geometry
