// The damped normal equations of a two-kind least-squares problem (bundle adjustment: poses and
// points) solved by the Schur complement: the "eliminated" variables (block size E) are solved
// out, leaving the reduced system S over the "kept" variables (block size K):
//   [C  W] [de]   [-ge]       S = B - W^T C^-1 W,   S dk = -gk + W^T C^-1 ge,
//   [W' B] [dk] = [-gk]       de = C^-1 (-ge - W dk),
// with C block diagonal (E x E blocks) because every term couples one eliminated variable with
// at most one kept variable. BundleAdjuster uses E=3, K=6 (points eliminated, the usual case)
// or E=6, K=3 (poses eliminated: film-tracking problems with far more cameras than points).
//
// Each eliminated block is factorised, C_e = L L^T, and every term's coupling becomes
// Z = L^-1 W (E x K), so S = B - sum Z_a^T Z_b over the term pairs (a, b) of each eliminated
// variable, the right-hand side -gk + Z^T (L^-1 ge), and de = L^-T (-L^-1 ge - Z dk): no inverse
// is formed, and only the upper triangle of S (and of every Hessian block) is built and read.
//
// S is factorised densely (LLT) up to `dense_max_dim` and otherwise as a sparse matrix with a
// block AMD ordering (Eigen's SimplicialLLT on the ordered pattern, without its per-call copy). The structure is analysed
// once per problem structure; solving reuses every buffer, and every buffer keeps the largest size
// it had (core/base/grow.h; the dense S and its right-hand side are maps of their current size into
// storage of the largest size), so solving problems no larger than the largest one so far
// allocates nothing, whatever their structure, on the dense path. Damping is Marquardt's: each diagonal
// entry h gets lambda * lm.damping_diagonal(h) added.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/base/grow.h"
#include "core/optim/lm.h"

namespace ale::optim::internal {

// Eigen's SimplicialLLT::factorize builds a temporary column array on every call; with the
// pattern already in fill-reducing order (natural ordering, upper triangle) the protected
// pre-ordered factorisation does the same work without it, so a trial step allocates nothing
// (its work vectors are on the stack up to Eigen's 128 KiB limit: 16384 unknowns).
class PreorderedSparseLlt
    : public Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Upper, Eigen::NaturalOrdering<int>> {
 public:
  void factorize_preordered_upper(const Eigen::SparseMatrix<double>& a) { factorize_preordered<false>(a); }
};

// A simplicial factorisation of a nearly dense matrix costs the dense flops at a few times the
// dense LLT's speed: above this fraction of nonzero blocks S is factorised densely whatever its
// size (film tracking with every point in most cameras).
constexpr double kMaxSparseDensity = 0.3;

// c = L L^T from c's upper triangle (L in l's lower triangle, 1 / L(d, d) in inv_diag); false
// when c is not positive definite (or not finite).
template <int N>
bool cholesky_upper(const Eigen::Matrix<double, N, N>& c, Eigen::Matrix<double, N, N>* l,
                    Eigen::Matrix<double, N, 1>* inv_diag) {
  for (int j = 0; j < N; ++j) {
    double d = c(j, j);
    for (int k = 0; k < j; ++k) d -= (*l)(j, k) * (*l)(j, k);
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    const double ljj = std::sqrt(d);
    (*l)(j, j) = ljj;
    (*inv_diag)[j] = 1.0 / ljj;
    for (int i = j + 1; i < N; ++i) {
      double v = c(j, i);
      for (int k = 0; k < j; ++k) v -= (*l)(i, k) * (*l)(j, k);
      (*l)(i, j) = v * (*inv_diag)[j];
    }
  }
  return true;
}

// m <- L^-1 m (forward substitution, every column).
template <int N, class M>
void forward_substitute(const Eigen::Matrix<double, N, N>& l, const Eigen::Matrix<double, N, 1>& inv_diag, M& m) {
  for (int r = 0; r < N; ++r) {
    for (int k = 0; k < r; ++k) m.row(r) -= l(r, k) * m.row(k);
    m.row(r) *= inv_diag[r];
  }
}

// v <- L^-T v (back substitution).
template <int N>
void back_substitute(const Eigen::Matrix<double, N, N>& l, const Eigen::Matrix<double, N, 1>& inv_diag,
                     Eigen::Matrix<double, N, 1>& v) {
  for (int r = N - 1; r >= 0; --r) {
    for (int k = r + 1; k < N; ++k) v[r] -= l(k, r) * v[k];
    v[r] *= inv_diag[r];
  }
}

// s -= a^T b for a, b of 3 x K (column-major), s of K x K with column stride `stride`: only the
// upper triangle when Upper. Written out so that a and b are read once and each entry of s is read
// and written once (Eigen's product re-reads a per entry). Each entry's dot product is summed left
// to right, (a0 b0 + a1 b1) + a2 b2, on every platform (Eigen's own order differs between x86 and
// ARM), so the host and the armhf build compute the same bits.
template <bool Upper, int K>
void subtract_gram3(double* s, Eigen::Index stride, const double* __restrict a, const double* __restrict b) {
  double at[3 * K];
#pragma GCC unroll 32
  for (int i = 0; i < 3 * K; ++i) at[i] = a[i];
  // a stays in registers; one column of s at a time (unrolling the columns too makes GCC keep
  // a pointer per entry, more instructions than it saves)
#pragma GCC unroll 1
  for (int c = 0; c < K; ++c, s += stride) {
    const double b0 = b[3 * c], b1 = b[3 * c + 1], b2 = b[3 * c + 2];
    double* sc = s;
#pragma GCC unroll 8
    for (int r = 0; r < (Upper ? c + 1 : K); ++r) sc[r] -= (at[3 * r] * b0 + at[3 * r + 1] * b1) + at[3 * r + 2] * b2;
  }
}

// The upper triangle of s -= a^T b (a, b: E x K; s: K x K) when `upper_only`, else all of it.
template <class Block, class Mat>
void subtract_gram(Block&& s, const Mat& a, const Mat& b, bool upper_only) {
  if constexpr (Mat::RowsAtCompileTime == 3) {  // the points-eliminated system's inner loop
    constexpr int K = Mat::ColsAtCompileTime;
    if (upper_only) {
      subtract_gram3<true, K>(s.data(), s.outerStride(), a.data(), b.data());
    } else {
      subtract_gram3<false, K>(s.data(), s.outerStride(), a.data(), b.data());
    }
    return;
  }
  if (!upper_only) {
    s.noalias() -= a.transpose() * b;
    return;
  }
  for (int c = 0; c < Mat::ColsAtCompileTime; ++c) {
    for (int r = 0; r <= c; ++r) s(r, c) -= a.col(r).dot(b.col(c));
  }
}

template <int E, int K>
class SchurSystem {
 public:
  using MatE = Eigen::Matrix<double, E, E>;
  using MatK = Eigen::Matrix<double, K, K>;
  using MatEK = Eigen::Matrix<double, E, K>;
  using VecE = Eigen::Matrix<double, E, 1>;
  using VecK = Eigen::Matrix<double, K, 1>;

  // Terms t (observations) couple eliminated variable term_elim[t] and kept variable
  // term_keep[t]; -1 when that side is fixed. Values are filled per linearisation below.
  void analyse(int n_elim, int n_keep, const std::vector<int>& term_elim, const std::vector<int>& term_keep,
               int dense_max_dim);

  void zero_values() {
    for (MatE& m : hee) m.setZero();
    for (VecE& v : ge) v.setZero();
    for (MatK& m : hkk) m.setZero();
    for (VecK& v : gk) v.setZero();
  }

  // Values: Hessian blocks (the upper triangle is what is read) and gradients per variable,
  // coupling block per term (only read for terms with both sides free).
  std::vector<MatE> hee;
  std::vector<VecE> ge;
  std::vector<MatK> hkk;
  std::vector<VecK> gk;
  std::vector<MatEK> hek;

  // Solves the system damped with lm.lambda(); false when it is not positive definite or the
  // step is not finite. predicted = 0.5 dx^T (lambda D dx - g).
  bool solve(const LmController& lm, std::vector<VecE>* dxe, std::vector<VecK>* dxk, double* predicted);

  double gradient_max() const {
    double m = 0.0;
    for (const VecE& v : ge) m = std::max(m, v.cwiseAbs().maxCoeff());
    for (const VecK& v : gk) m = std::max(m, v.cwiseAbs().maxCoeff());
    return m;
  }
  bool sparse() const { return use_sparse_; }
  // Room for problems up to this size without allocating (the buffers grow past it when needed).
  void reserve(int n_elim, int n_keep, int n_terms, int dense_max_dim);
  int reduced_dim() const { return K * n_keep_; }

 private:
  // S's block (pos_[i], pos_[j]) for pos_[i] <= pos_[j], as a map into the dense or sparse
  // storage; `pair` is the index of the (a, b) term pair in the sparse pair table.
  Eigen::Map<MatK, 0, Eigen::OuterStride<>> dense_block(int pi, int pj) {
    const Eigen::Index n = K * n_keep_;
    return Eigen::Map<MatK, 0, Eigen::OuterStride<>>(dense_.data() + static_cast<Eigen::Index>(K) * (pj * n + pi),
                                                     Eigen::OuterStride<>(n));
  }
  // The first n entries of a grow-only vector (Eigen reallocates a VectorXd on every size change).
  static Eigen::Map<Eigen::VectorXd, Eigen::AlignedMax> head(Eigen::VectorXd& v, Eigen::Index n) {
    return Eigen::Map<Eigen::VectorXd, Eigen::AlignedMax>(v.data(), n);
  }
  static void grow(Eigen::VectorXd& v, Eigen::Index n) {
    if (v.size() < n) v.resize(std::max(n, 2 * v.size()));
  }
  Eigen::Map<MatK, 0, Eigen::OuterStride<>> sparse_block(int offset, int pj) {
    return Eigen::Map<MatK, 0, Eigen::OuterStride<>>(sparse_.valuePtr() + offset, Eigen::OuterStride<>(col_stride_[pj]));
  }
  // false (nothing built) when more than max_density of S's upper blocks are nonzero.
  bool build_sparse_pattern(double max_density);

  int n_elim_ = 0, n_keep_ = 0;
  bool use_sparse_ = false;
  std::vector<int> term_keep_;                 // copy of the kept side per term
  std::vector<int> elim_start_, elim_terms_;  // terms of each eliminated variable with a free kept side
  std::vector<int> pos_;                       // kept variable -> block position in S
  std::vector<MatE> chol_;      // per eliminated variable: L of its damped block (lower triangle)
  std::vector<VecE> inv_diag_;  // 1 / L(d, d)
  std::vector<VecE> gz_;        // L^-1 ge
  std::vector<MatEK> z_;        // L^-1 W per term
  std::vector<int> cursor_;
  Eigen::VectorXd rhs_, sol_;  // the first K * n_keep_ entries are used
  // dense: S column-major in the first (K * n_keep_)^2 entries, factorised in place
  Eigen::VectorXd dense_;
  // sparse: column-major, every block stored full (Eigen's LLT reads the upper triangle only)
  Eigen::SparseMatrix<double> sparse_;
  std::vector<int> col_stride_;        // per block column: entries per scalar column
  std::vector<int> diag_offset_;       // per block position: value offset of the diagonal block
  std::vector<int> pair_offset_;       // per (a <= b) term pair of each eliminated variable
  PreorderedSparseLlt sparse_llt_;
};

template <int E, int K>
void SchurSystem<E, K>::reserve(int n_elim, int n_keep, int n_terms, int dense_max_dim) {
  for (auto* v : {&elim_start_, &cursor_}) grow_capacity(*v, n_elim + 1);
  grow_capacity(hee, n_elim);
  grow_capacity(ge, n_elim);
  grow_capacity(chol_, n_elim);
  grow_capacity(inv_diag_, n_elim);
  grow_capacity(gz_, n_elim);
  grow_capacity(hkk, n_keep);
  grow_capacity(gk, n_keep);
  grow_capacity(pos_, n_keep);
  for (auto* v : {&term_keep_, &elim_terms_}) grow_capacity(*v, n_terms);
  grow_capacity(hek, n_terms);
  grow_capacity(z_, n_terms);
  grow(rhs_, K * n_keep);
  grow(sol_, K * n_keep);
  if (K * n_keep <= dense_max_dim) grow(dense_, static_cast<Eigen::Index>(K * n_keep) * (K * n_keep));
}

template <int E, int K>
void SchurSystem<E, K>::analyse(int n_elim, int n_keep, const std::vector<int>& term_elim,
                                const std::vector<int>& term_keep, int dense_max_dim) {
  n_elim_ = n_elim;
  n_keep_ = n_keep;
  const int n_terms = static_cast<int>(term_elim.size());
  grow_copy(term_keep_, term_keep);
  grow_resize(hee, n_elim);
  grow_resize(ge, n_elim);
  grow_resize(chol_, n_elim);
  grow_resize(inv_diag_, n_elim);
  grow_resize(gz_, n_elim);
  grow_resize(hkk, n_keep);
  grow_resize(gk, n_keep);
  grow_resize(hek, n_terms);
  grow_resize(z_, n_terms);
  grow_assign(elim_start_, n_elim + 1, 0);
  for (int t = 0; t < n_terms; ++t) {
    if (term_elim[t] >= 0 && term_keep[t] >= 0) ++elim_start_[term_elim[t] + 1];
  }
  for (int e = 0; e < n_elim; ++e) elim_start_[e + 1] += elim_start_[e];
  grow_resize(elim_terms_, elim_start_[n_elim]);
  grow_capacity(cursor_, n_elim);
  cursor_.assign(elim_start_.begin(), elim_start_.end() - 1);
  for (int t = 0; t < n_terms; ++t) {
    if (term_elim[t] >= 0 && term_keep[t] >= 0) elim_terms_[cursor_[term_elim[t]]++] = t;
  }
  grow_resize(pos_, n_keep);
  for (int i = 0; i < n_keep; ++i) pos_[i] = i;
  grow(rhs_, K * n_keep);
  grow(sol_, K * n_keep);
  // dense_max_dim < 0 forces the sparse path whatever the density (tests)
  use_sparse_ = K * n_keep > dense_max_dim && build_sparse_pattern(dense_max_dim < 0 ? 1.0 : kMaxSparseDensity);
  if (!use_sparse_) {
    grow(dense_, static_cast<Eigen::Index>(K * n_keep) * (K * n_keep));
    col_stride_.clear();
  }
  // Pairs (a <= b) of one eliminated variable's terms then land in the upper triangle.
  for (int e = 0; e < n_elim; ++e) {
    std::sort(elim_terms_.begin() + elim_start_[e], elim_terms_.begin() + elim_start_[e + 1],
              [&](int a, int b) { return pos_[term_keep_[a]] < pos_[term_keep_[b]]; });
  }
  if (use_sparse_) {
    pair_offset_.clear();
    for (int e = 0; e < n_elim; ++e) {
      for (int a = elim_start_[e]; a < elim_start_[e + 1]; ++a) {
        for (int b = a; b < elim_start_[e + 1]; ++b) {
          const int pi = pos_[term_keep_[elim_terms_[a]]], pj = pos_[term_keep_[elim_terms_[b]]];
          // block column pj holds its block rows in increasing order, each K rows tall
          const int* rows = sparse_.innerIndexPtr() + sparse_.outerIndexPtr()[K * pj];
          const int n_rows = col_stride_[pj];
          const int* hit = std::lower_bound(rows, rows + n_rows, K * pi);
          pair_offset_.push_back(sparse_.outerIndexPtr()[K * pj] + static_cast<int>(hit - rows));
        }
      }
    }
  }
}

template <int E, int K>
bool SchurSystem<E, K>::build_sparse_pattern(double max_density) {
  // Block pairs that S couples: every pair of kept variables sharing an eliminated one.
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < n_keep_; ++i) pairs.emplace_back(i, i);
  for (int e = 0; e < n_elim_; ++e) {
    for (int a = elim_start_[e]; a < elim_start_[e + 1]; ++a) {
      for (int b = a + 1; b < elim_start_[e + 1]; ++b) {
        const int i = term_keep_[elim_terms_[a]], j = term_keep_[elim_terms_[b]];
        if (i != j) pairs.emplace_back(std::min(i, j), std::max(i, j));
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  if (static_cast<double>(pairs.size()) > max_density * 0.5 * n_keep_ * (n_keep_ + 1.0)) return false;
  // AMD on the block graph (fill-reducing), expanded to blocks.
  {
    Eigen::SparseMatrix<int> graph(n_keep_, n_keep_);
    std::vector<Eigen::Triplet<int>> entries;
    for (const auto& [i, j] : pairs) {
      entries.emplace_back(i, j, 1);
      if (i != j) entries.emplace_back(j, i, 1);
    }
    graph.setFromTriplets(entries.begin(), entries.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p_inv;
    Eigen::AMDOrdering<int> amd;
    amd(graph, p_inv);  // p_inv(new) = old
    for (int k = 0; k < n_keep_; ++k) pos_[p_inv.indices()[k]] = k;
  }
  for (auto& [i, j] : pairs) {
    const int a = pos_[i], b = pos_[j];
    i = std::min(a, b);
    j = std::max(a, b);
  }
  std::sort(pairs.begin(), pairs.end(), [](const auto& x, const auto& y) {
    return x.second != y.second ? x.second < y.second : x.first < y.first;  // by column, then row
  });
  col_stride_.assign(n_keep_, 0);
  for (const auto& pr : pairs) col_stride_[pr.second] += K;
  const int n = K * n_keep_;
  long nnz = 0;
  for (int j = 0; j < n_keep_; ++j) nnz += static_cast<long>(K) * col_stride_[j];
  sparse_.resize(n, n);
  sparse_.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer = sparse_.outerIndexPtr();
  int* inner = sparse_.innerIndexPtr();
  diag_offset_.resize(n_keep_);
  std::size_t p = 0;
  int v = 0;
  outer[0] = 0;
  for (int j = 0; j < n_keep_; ++j) {
    const std::size_t first = p;
    while (p < pairs.size() && pairs[p].second == j) ++p;
    for (int c = 0; c < K; ++c) {
      for (std::size_t q = first; q < p; ++q) {
        for (int r = 0; r < K; ++r) inner[v++] = K * pairs[q].first + r;
      }
      outer[K * j + c + 1] = v;
    }
  }
  // Offsets are into the block column's first scalar column: what the OuterStride maps expect.
  for (int j = 0; j < n_keep_; ++j) {
    const int* rows = inner + outer[K * j];
    diag_offset_[j] = outer[K * j] + static_cast<int>(std::lower_bound(rows, rows + col_stride_[j], K * j) - rows);
  }
  sparse_.coeffs().setZero();
  sparse_llt_.analyzePattern(sparse_);
  return true;
}

template <int E, int K>
bool SchurSystem<E, K>::solve(const LmController& lm, std::vector<VecE>* dxe, std::vector<VecK>* dxk,
                              double* predicted) {
  const double lambda = lm.lambda();
  const Eigen::Index n = K * n_keep_;
  auto rhs = head(rhs_, n);
  auto sol = head(sol_, n);
  if (use_sparse_) {
    sparse_.coeffs().setZero();
  } else {
    head(dense_, n * n).setZero();
  }
  for (int i = 0; i < n_keep_; ++i) {
    MatK b = hkk[i];
    for (int d = 0; d < K; ++d) b(d, d) += lambda * lm.damping_diagonal(hkk[i](d, d));
    if (use_sparse_) {
      sparse_block(diag_offset_[pos_[i]], pos_[i]) = b;
    } else {
      dense_block(pos_[i], pos_[i]) = b;
    }
    rhs.template segment<K>(K * pos_[i]) = -gk[i];
  }
  int pair = 0;
  for (int e = 0; e < n_elim_; ++e) {
    MatE c = hee[e];
    for (int d = 0; d < E; ++d) c(d, d) += lambda * lm.damping_diagonal(hee[e](d, d));
    MatE& l = chol_[e];
    VecE& inv_diag = inv_diag_[e];
    if (!cholesky_upper(c, &l, &inv_diag)) return false;
    VecE& gz = gz_[e];
    gz = ge[e];
    forward_substitute(l, inv_diag, gz);
    const int begin = elim_start_[e], end = elim_start_[e + 1];
    for (int a = begin; a < end; ++a) {
      const int t = elim_terms_[a];
      z_[t] = hek[t];
      forward_substitute(l, inv_diag, z_[t]);
      rhs.template segment<K>(K * pos_[term_keep_[t]]).noalias() += z_[t].transpose() * gz;
    }
    for (int a = begin; a < end; ++a) {
      const int ta = elim_terms_[a];
      const int pi = pos_[term_keep_[ta]];
      for (int b = a; b < end; ++b) {
        const int tb = elim_terms_[b];
        const int pj = pos_[term_keep_[tb]];
        // a diagonal block of S: only its upper triangle is read
        const bool diagonal = pi == pj;
        if (use_sparse_) {
          subtract_gram(sparse_block(pair_offset_[pair], pj), z_[ta], z_[tb], diagonal);
        } else {
          subtract_gram(dense_block(pi, pj), z_[ta], z_[tb], diagonal);
        }
        ++pair;
        // A variable seen twice by the same eliminated one (duplicate observations) also
        // has the (b, a) product on its diagonal block.
        if (diagonal && a != b) {
          if (use_sparse_) {
            subtract_gram(sparse_block(pair_offset_[pair - 1], pj), z_[tb], z_[ta], true);
          } else {
            subtract_gram(dense_block(pi, pj), z_[tb], z_[ta], true);
          }
        }
      }
    }
  }
  if (use_sparse_) {
    sparse_llt_.factorize_preordered_upper(sparse_);
    if (sparse_llt_.info() != Eigen::Success) return false;
    sol = sparse_llt_.solve(rhs);
  } else {
    Eigen::Map<Eigen::MatrixXd, Eigen::AlignedMax> s(dense_.data(), n, n);
    const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Upper> llt(s);  // in place: no copy of S
    if (llt.info() != Eigen::Success) return false;
    sol = rhs;
    llt.solveInPlace(sol);
  }
  if (!sol.allFinite()) return false;
  grow_resize(*dxk, n_keep_);
  grow_resize(*dxe, n_elim_);
  double pred = 0.0;
  for (int i = 0; i < n_keep_; ++i) {
    const VecK d = sol.template segment<K>(K * pos_[i]);
    (*dxk)[i] = d;
    for (int r = 0; r < K; ++r) pred += d[r] * (lambda * lm.damping_diagonal(hkk[i](r, r)) * d[r] - gk[i][r]);
  }
  for (int e = 0; e < n_elim_; ++e) {
    VecE d = -gz_[e];
    for (int a = elim_start_[e]; a < elim_start_[e + 1]; ++a) {
      const int t = elim_terms_[a];
      d.noalias() -= z_[t] * (*dxk)[term_keep_[t]];
    }
    back_substitute(chol_[e], inv_diag_[e], d);
    if (!d.allFinite()) return false;
    (*dxe)[e] = d;
    for (int r = 0; r < E; ++r) pred += d[r] * (lambda * lm.damping_diagonal(hee[e](r, r)) * d[r] - ge[e][r]);
  }
  *predicted = 0.5 * pred;
  return true;
}

}  // namespace ale::optim::internal
