#include "core/optim/pose_graph.h"

#include "core/geometry/portable_math.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include <Eigen/OrderingMethods>

namespace ale::optim {

using geometry::Sim3;
using geometry::SE3;

// Products of two 6x6 or 7x7 matrices are written as lazyProduct: Eigen sends 7x7 products
// (rows + cols + depth >= 20) through its general GEMM with packing, several times slower at
// this size than the coefficient loop.

template <class Group>
typename PoseGraphGroup<Group>::Tangent pose_graph_residual(const Group& T_ij, const Group& T_iw, const Group& T_jw,
                                                             typename PoseGraphGroup<Group>::Matrix* d_e_d_i,
                                                             typename PoseGraphGroup<Group>::Matrix* d_e_d_j) {
  const Group error = T_ij * T_jw * T_iw.inverse();
  const typename PoseGraphGroup<Group>::Tangent e = error.log();
  if (d_e_d_i != nullptr || d_e_d_j != nullptr) {
    const typename PoseGraphGroup<Group>::Matrix jl_inv = Group::left_jacobian_inverse(e);
    if (d_e_d_i != nullptr) *d_e_d_i = -jl_inv.lazyProduct(error.adjoint());
    if (d_e_d_j != nullptr) *d_e_d_j = jl_inv.lazyProduct(T_ij.adjoint());
  }
  return e;
}

namespace {

bool finite(const SE3& t) {
  return t.translation().allFinite() && t.so3().quaternion().coeffs().allFinite();
}

bool finite(const Sim3& s) {
  return s.translation().allFinite() && s.so3().quaternion().coeffs().allFinite() && std::isfinite(s.scale()) &&
         s.scale() > 0.0;
}

int find_root(std::vector<int>& parent, int v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

}  // namespace

template <class Group>
double PoseGraphOptimizer<Group>::cost(const std::vector<PoseGraphEdge<Group>>& edges,
                                       const std::vector<Group>& poses) {
  double total = 0.0;
  for (const PoseGraphEdge<Group>& edge : edges) {
    const Tangent e = pose_graph_residual<Group>(edge.T_ij, poses[edge.i], poses[edge.j], nullptr, nullptr);
    total += edge.kernel.rho(e.dot(edge.information * e));
  }
  return 0.5 * total;
}

template <class Group>
Status PoseGraphOptimizer<Group>::check_inputs(const std::vector<PoseGraphEdge<Group>>& edges,
                                               const std::vector<int>& fixed_vertices,
                                               const std::vector<Group>& poses) const {
  const int n = static_cast<int>(poses.size());
  if (edges.empty()) return invalid_argument("pose graph: no edges");
  if (fixed_vertices.empty()) return invalid_argument("pose graph: no fixed vertex, the gauge is free");
  for (int v : fixed_vertices) {
    if (v < 0 || v >= n) {
      return invalid_argument("pose graph: fixed vertex " + std::to_string(v) + " not in 0.." + std::to_string(n - 1));
    }
  }
  for (int v = 0; v < n; ++v) {
    if (!finite(poses[v])) return invalid_argument("pose graph: vertex " + std::to_string(v) + " is not finite");
  }
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge<Group>& edge = edges[k];
    // Built only on failure: the check runs on every call and must not allocate.
    auto name = [&]() {
      return "pose graph: edge " + std::to_string(k) + " (" + std::to_string(edge.i) + ", " + std::to_string(edge.j) +
             ")";
    };
    if (edge.i < 0 || edge.i >= n || edge.j < 0 || edge.j >= n) {
      return invalid_argument(name() + " names a vertex outside 0.." + std::to_string(n - 1));
    }
    if (edge.i == edge.j) return invalid_argument(name() + " joins a vertex to itself");
    if (!finite(edge.T_ij)) return invalid_argument(name() + ": measurement is not finite");
    if (edge.kernel.kind != RobustKind::kNone && !(std::isfinite(edge.kernel.delta) && edge.kernel.delta > 0.0)) {
      return invalid_argument(name() + ": robust kernel threshold must be finite and > 0");
    }
    const Block& info = edge.information;
    if (!info.allFinite() || !info.isApprox(info.transpose(), 1e-12)) {
      return invalid_argument(name() + ": information matrix is not finite and symmetric");
    }
    Eigen::LLT<Block> llt(info);
    if (llt.info() != Eigen::Success) return invalid_argument(name() + ": information matrix is not positive definite");
  }
  return Status::ok_status();
}

template <class Group>
bool PoseGraphOptimizer<Group>::same_structure(const std::vector<PoseGraphEdge<Group>>& edges,
                                               const std::vector<int>& fixed_vertices,
                                               std::size_t vertex_count) const {
  if (vertex_count != vertex_count_ || edges.size() * 2 != edge_ends_.size()) return false;
  for (std::size_t k = 0; k < edges.size(); ++k) {
    if (edges[k].i != edge_ends_[2 * k] || edges[k].j != edge_ends_[2 * k + 1]) return false;
  }
  // Same fixed set: every listed vertex was fixed, and every vertex fixed before is listed.
  for (int v : fixed_vertices) {
    if (position_[v] != -1) return false;
    fixed_mark_[v] = 1;
  }
  bool same = true;
  for (int v : fixed_sorted_) same = same && fixed_mark_[v] != 0;
  for (int v : fixed_vertices) fixed_mark_[v] = 0;
  return same;
}

template <class Group>
Status PoseGraphOptimizer<Group>::build_structure(const std::vector<PoseGraphEdge<Group>>& edges,
                                                  const std::vector<int>& fixed_vertices, std::size_t vertex_count) {
  vertex_count_ = 0;  // invalid until the end
  const int n = static_cast<int>(vertex_count);
  std::vector<std::uint8_t> is_fixed(vertex_count, 0);
  for (int v : fixed_vertices) is_fixed[v] = 1;

  // Gauge: every connected component must hold a fixed vertex.
  std::vector<int> parent(vertex_count);
  std::iota(parent.begin(), parent.end(), 0);
  for (const PoseGraphEdge<Group>& edge : edges) {
    parent[find_root(parent, edge.i)] = find_root(parent, edge.j);
  }
  std::vector<std::uint8_t> component_fixed(vertex_count, 0);
  for (int v = 0; v < n; ++v) {
    if (is_fixed[v]) component_fixed[find_root(parent, v)] = 1;
  }
  for (int v = 0; v < n; ++v) {
    if (!component_fixed[find_root(parent, v)]) {
      return invalid_argument("pose graph: vertex " + std::to_string(v) +
                              " is not connected to a fixed vertex (gauge undetermined)");
    }
  }

  // Free vertices, and the block pattern between them.
  std::vector<int> free_index(vertex_count, -1);
  int free_count = 0;
  for (int v = 0; v < n; ++v) {
    if (!is_fixed[v]) free_index[v] = free_count++;
  }
  if (free_count == 0) return invalid_argument("pose graph: every vertex is fixed, nothing to optimise");
  std::vector<Eigen::Triplet<int>> triplets;
  triplets.reserve(edges.size() * 2 + static_cast<std::size_t>(free_count));
  for (int f = 0; f < free_count; ++f) triplets.emplace_back(f, f, 1);
  for (const PoseGraphEdge<Group>& edge : edges) {
    const int a = free_index[edge.i];
    const int b = free_index[edge.j];
    if (a >= 0 && b >= 0) {
      triplets.emplace_back(a, b, 1);
      triplets.emplace_back(b, a, 1);
    }
  }
  Eigen::SparseMatrix<int, Eigen::ColMajor, int> pattern(free_count, free_count);
  pattern.setFromTriplets(triplets.begin(), triplets.end());
  // AMD on the block graph; perm.indices()[k] is the free vertex eliminated k-th.
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> perm;
  Eigen::AMDOrdering<int> amd;
  amd(pattern, perm);
  std::vector<int> block_of_free(static_cast<std::size_t>(free_count));
  for (int k = 0; k < free_count; ++k) block_of_free[perm.indices()[k]] = k;
  position_.assign(vertex_count, -1);
  for (int v = 0; v < n; ++v) {
    if (free_index[v] >= 0) position_[v] = block_of_free[free_index[v]];
  }

  // Upper block pattern in the ordered positions: for block column b, the sorted block rows
  // a <= b that couple to it.
  std::vector<std::vector<int>> rows_of_column(static_cast<std::size_t>(free_count));
  for (int b = 0; b < free_count; ++b) rows_of_column[b].push_back(b);
  for (const PoseGraphEdge<Group>& edge : edges) {
    const int pi = position_[edge.i];
    const int pj = position_[edge.j];
    if (pi >= 0 && pj >= 0) rows_of_column[std::max(pi, pj)].push_back(std::min(pi, pj));
  }
  for (std::vector<int>& rows : rows_of_column) {
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  }
  // Dense kDim x kDim blocks: column c of block column b holds, for each block row in order,
  // kDim consecutive scalars. (The diagonal blocks' lower halves are stored and ignored.)
  const int dim = free_count * kDim;
  hessian_.resize(dim, dim);
  std::vector<int> block_column_start(static_cast<std::size_t>(free_count) + 1, 0);
  for (int b = 0; b < free_count; ++b) {
    block_column_start[b + 1] =
        block_column_start[b] + static_cast<int>(rows_of_column[b].size()) * kDim * kDim;
  }
  const int nonzeros = block_column_start[free_count];
  hessian_.resizeNonZeros(nonzeros);
  int* outer = hessian_.outerIndexPtr();
  int* inner = hessian_.innerIndexPtr();
  for (int b = 0; b < free_count; ++b) {
    const int rows = static_cast<int>(rows_of_column[b].size());
    for (int c = 0; c < kDim; ++c) {
      const int start = block_column_start[b] + c * rows * kDim;
      outer[b * kDim + c] = start;
      for (int r = 0; r < rows; ++r) {
        for (int q = 0; q < kDim; ++q) inner[start + r * kDim + q] = rows_of_column[b][r] * kDim + q;
      }
    }
  }
  outer[dim] = nonzeros;
  std::fill(hessian_.valuePtr(), hessian_.valuePtr() + nonzeros, 0.0);

  // Slots: the value index of each block's (0, 0) entry and its column stride.
  auto slot_of = [&](int a, int b) {
    const std::vector<int>& rows = rows_of_column[b];
    const int r = static_cast<int>(std::lower_bound(rows.begin(), rows.end(), a) - rows.begin());
    return std::make_pair(block_column_start[b] + r * kDim, static_cast<int>(rows.size()) * kDim);
  };
  slot_base_.clear();
  slot_stride_.clear();
  std::vector<int> diagonal_slot(static_cast<std::size_t>(free_count));
  for (int b = 0; b < free_count; ++b) {
    const auto slot = slot_of(b, b);
    diagonal_slot[b] = static_cast<int>(slot_base_.size());
    slot_base_.push_back(slot.first);
    slot_stride_.push_back(slot.second);
  }
  diagonal_index_.resize(static_cast<std::size_t>(dim));
  for (int b = 0; b < free_count; ++b) {
    for (int q = 0; q < kDim; ++q) {
      diagonal_index_[b * kDim + q] = slot_base_[diagonal_slot[b]] + q * slot_stride_[diagonal_slot[b]] + q;
    }
  }
  const std::size_t m = edges.size();
  slot_ii_.assign(m, -1);
  slot_jj_.assign(m, -1);
  slot_ij_.assign(m, -1);
  ij_transposed_.assign(m, 0);
  for (std::size_t k = 0; k < m; ++k) {
    const int pi = position_[edges[k].i];
    const int pj = position_[edges[k].j];
    if (pi >= 0) slot_ii_[k] = diagonal_slot[pi];
    if (pj >= 0) slot_jj_[k] = diagonal_slot[pj];
    if (pi >= 0 && pj >= 0) {
      const auto slot = slot_of(std::min(pi, pj), std::max(pi, pj));
      slot_ij_[k] = static_cast<int>(slot_base_.size());
      slot_base_.push_back(slot.first);
      slot_stride_.push_back(slot.second);
      ij_transposed_[k] = pi > pj ? 1 : 0;
    }
  }

  gradient_.resize(dim);
  diagonal_.resize(dim);
  step_.resize(dim);
  ldlt_.analyze_ordered(hessian_);
  if (ldlt_.info() != Eigen::Success) return internal_error("pose graph: symbolic factorisation failed");
  saved_poses_.resize(vertex_count);
  fixed_mark_.assign(vertex_count, 0);

  edge_ends_.resize(2 * m);
  for (std::size_t k = 0; k < m; ++k) {
    edge_ends_[2 * k] = edges[k].i;
    edge_ends_[2 * k + 1] = edges[k].j;
  }
  fixed_sorted_ = fixed_vertices;
  std::sort(fixed_sorted_.begin(), fixed_sorted_.end());
  fixed_sorted_.erase(std::unique(fixed_sorted_.begin(), fixed_sorted_.end()), fixed_sorted_.end());
  vertex_count_ = vertex_count;
  return Status::ok_status();
}

template <class Group>
double PoseGraphOptimizer<Group>::linearize(const std::vector<PoseGraphEdge<Group>>& edges,
                                          const std::vector<Group>& poses) {
  std::fill(hessian_.valuePtr(), hessian_.valuePtr() + hessian_.nonZeros(), 0.0);
  gradient_.setZero();
  double* values = hessian_.valuePtr();
  double total = 0.0;
  using BlockMap = Eigen::Map<Block, 0, Eigen::OuterStride<>>;
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge<Group>& edge = edges[k];
    Block d_e_d_i;
    Block d_e_d_j;
    const Tangent e = pose_graph_residual<Group>(edge.T_ij, poses[edge.i], poses[edge.j], &d_e_d_i, &d_e_d_j);
    const Tangent omega_e = edge.information * e;
    double rho = 0.0;
    double rho_prime = 0.0;
    edge.kernel.evaluate(e.dot(omega_e), &rho, &rho_prime);
    total += rho;
    // Gauss-Newton with the kernel's weight (the exact gradient rho' J^T Omega e; the Hessian
    // drops rho'' as most robust LM implementations do).
    const Block w = rho_prime * edge.information;
    const Block w_d_i = w.lazyProduct(d_e_d_i);
    const Block w_d_j = w.lazyProduct(d_e_d_j);
    auto slot = [&](int index) {
      return BlockMap(values + slot_base_[index], kDim, kDim, Eigen::OuterStride<>(slot_stride_[index]));
    };
    const int pi = position_[edge.i];
    const int pj = position_[edge.j];
    if (pi >= 0) {
      slot(slot_ii_[k]) += d_e_d_i.transpose().lazyProduct(w_d_i);
      gradient_.template segment<kDim>(pi * kDim).noalias() += w_d_i.transpose() * e;
    }
    if (pj >= 0) {
      slot(slot_jj_[k]) += d_e_d_j.transpose().lazyProduct(w_d_j);
      gradient_.template segment<kDim>(pj * kDim).noalias() += w_d_j.transpose() * e;
    }
    if (slot_ij_[k] >= 0) {
      // The stored block is (min position, max position) of the upper triangle.
      if (ij_transposed_[k]) {
        slot(slot_ij_[k]) += d_e_d_j.transpose().lazyProduct(w_d_i);
      } else {
        slot(slot_ij_[k]) += d_e_d_i.transpose().lazyProduct(w_d_j);
      }
    }
  }
  for (Eigen::Index q = 0; q < diagonal_.size(); ++q) diagonal_[q] = values[diagonal_index_[q]];
  return 0.5 * total;
}

template <class Group>
bool PoseGraphOptimizer<Group>::solve_damped(const LmController& lm) {
  double* values = hessian_.valuePtr();
  for (Eigen::Index q = 0; q < diagonal_.size(); ++q) {
    values[diagonal_index_[q]] = diagonal_[q] + lm.lambda() * lm.damping_diagonal(diagonal_[q]);
  }
  ldlt_.factorize_ordered(hessian_);
  if (ldlt_.info() != Eigen::Success) return false;
  step_ = ldlt_.solve(gradient_);
  step_ = -step_;
  return step_.allFinite();
}

template <class Group>
double PoseGraphOptimizer<Group>::apply_step(std::vector<Group>* poses) const {
  for (std::size_t v = 0; v < poses->size(); ++v) {
    if (position_[v] < 0) continue;
    (*poses)[v] = Group::exp(step_.template segment<kDim>(position_[v] * kDim)) * (*poses)[v];
  }
  return step_.norm();
}

namespace {

// The parameter norm of Ceres' ambient parametrisation (quaternion, translation[, log scale]),
// for the same relative step test.
double parameter_squared_norm(const SE3& t) { return 1.0 + t.translation().squaredNorm(); }
double parameter_squared_norm(const Sim3& s) {
  const double sigma = geometry::portable_log(s.scale());
  return 1.0 + s.translation().squaredNorm() + sigma * sigma;
}

}  // namespace

template <class Group>
Result<PoseGraphSummary> PoseGraphOptimizer<Group>::optimize(const std::vector<PoseGraphEdge<Group>>& edges,
                                                             const std::vector<int>& fixed_vertices,
                                                             const LmOptions& options, std::vector<Group>* poses) {
  if (poses == nullptr) return invalid_argument("pose graph: no poses");
  ALE_RETURN_IF_ERROR(check_inputs(edges, fixed_vertices, *poses));
  if (!same_structure(edges, fixed_vertices, poses->size())) {
    ALE_RETURN_IF_ERROR(build_structure(edges, fixed_vertices, poses->size()));
  }
  initial_poses_ = *poses;  // same size as the last call: no allocation

  auto fail = [&](Status status) -> Result<PoseGraphSummary> {
    *poses = initial_poses_;
    return status;
  };
  double x_squared_norm = 0.0;
  for (std::size_t v = 0; v < poses->size(); ++v) {
    if (position_[v] >= 0) x_squared_norm += parameter_squared_norm((*poses)[v]);
  }
  LmController lm;
  const double initial_cost = linearize(edges, *poses);
  lm.start(options, initial_cost, gradient_.cwiseAbs().maxCoeff());
  while (!lm.done()) {
    if (!solve_damped(lm)) {
      lm.report_failed_step();
      continue;
    }
    // Linear model's reduction 0.5 dx^T (lambda D dx - g).
    double predicted = 0.0;
    for (Eigen::Index q = 0; q < step_.size(); ++q) {
      predicted += step_[q] * (lm.lambda() * lm.damping_diagonal(diagonal_[q]) * step_[q] - gradient_[q]);
    }
    predicted *= 0.5;
    std::copy(poses->begin(), poses->end(), saved_poses_.begin());
    const double step_norm = apply_step(poses);
    const double new_cost = cost(edges, *poses);
    if (!std::isfinite(new_cost)) {
      std::copy(saved_poses_.begin(), saved_poses_.end(), poses->begin());
      lm.report_failed_step();
      continue;
    }
    if (lm.report_step(new_cost, predicted, step_norm, std::sqrt(x_squared_norm))) {
      x_squared_norm = 0.0;
      for (std::size_t v = 0; v < poses->size(); ++v) {
        if (position_[v] >= 0) x_squared_norm += parameter_squared_norm((*poses)[v]);
      }
      if (!lm.done()) {
        linearize(edges, *poses);
        lm.set_gradient(gradient_.cwiseAbs().maxCoeff());
      }
    } else {
      std::copy(saved_poses_.begin(), saved_poses_.end(), poses->begin());
    }
  }
  PoseGraphSummary summary;
  summary.initial_cost = initial_cost;
  summary.final_cost = lm.cost();
  summary.iterations = lm.iterations();
  summary.accepted_steps = lm.accepted_steps();
  summary.stop = lm.stop();
  if (lm.stop() == LmStop::kNumericalFailure) {
    return fail(invalid_argument("pose graph: cost or gradient is not finite"));
  }
  if (!converged(lm.stop())) {
    return fail(Status(StatusCode::kNotConverged, "pose graph: not converged after " + std::to_string(lm.iterations()) +
                                                 " iterations (" + to_string(lm.stop()) + ", cost " +
                                                 std::to_string(initial_cost) + " -> " +
                                                 std::to_string(lm.cost()) + ")"));
  }
  for (const Group& pose : *poses) {
    if (!finite(pose)) return fail(internal_error("pose graph: a refined pose is not finite"));
  }
  return summary;
}

template class PoseGraphOptimizer<SE3>;
template class PoseGraphOptimizer<Sim3>;
template PoseGraphGroup<SE3>::Tangent pose_graph_residual<SE3>(const SE3&, const SE3&, const SE3&,
                                                               PoseGraphGroup<SE3>::Matrix*,
                                                               PoseGraphGroup<SE3>::Matrix*);
template PoseGraphGroup<Sim3>::Tangent pose_graph_residual<Sim3>(const Sim3&, const Sim3&, const Sim3&,
                                                                 PoseGraphGroup<Sim3>::Matrix*,
                                                                 PoseGraphGroup<Sim3>::Matrix*);

}  // namespace ale::optim
