// Pose-graph optimisation over SE(3) or Sim(3) relative-pose edges (ORB-SLAM's essential graph
// for loop closing is the Sim(3) case).
//
// Vertices are absolute poses T_iw (SE3) or S_iw (Sim3), world to frame i. An edge (i, j)
// carries a measured relative transform T_ij (frame j to frame i; ideally T_iw * T_jw^-1) and
// an information matrix Omega (6x6 or 7x7, symmetric positive definite, in the tangent order
// of core/geometry/lie.h: rho, phi[, sigma]).
//
// Residual (in the tangent space at the identity):
//     e_ij = log(T_ij * T_jw * T_iw^-1)
// It is zero when the measurement agrees with the poses. The cost is the Ceres-style
//     F = 1/2 sum_edges rho(e^T Omega e)
// with rho the identity or the edge's robust kernel (core/optim/robust.h). Robust edges enter
// the normal equations with the weight rho'(s): the gradient is exact, the Hessian drops the
// rho'' term (as g2o does), which changes the path, not the minimum.
//
// Jacobians are taken for the left perturbations T_iw <- exp(d_i) T_iw, T_jw <- exp(d_j) T_jw
// of lie.h. With E = T_ij T_jw T_iw^-1 and e = log(E):
//     T_ij exp(d_j) T_jw T_iw^-1 = exp(Ad(T_ij) d_j) E   ->  d_e_d_j =  Jl^-1(e) Ad(T_ij)
//     T_ij T_jw T_iw^-1 exp(-d_i) = exp(-Ad(E) d_i) E    ->  d_e_d_i = -Jl^-1(e) Ad(E)
// using log(exp(a) exp(e)) = e + Jl^-1(e) a + O(|a|^2). Jl^-1(e) is exact here (lie.h's
// left_jacobian_inverse: the series sum_n ad(e)^n / (n+1)!, inverted), not the usual identity
// approximation. Exact Jacobians keep the Gauss-Newton fixed point at the true minimum even when residuals
// stay large (loop closures against scale drift), which is what the Ceres comparison checks.
//
// Solver: Levenberg-Marquardt (core/optim/lm.h) on the sparse normal equations of the free
// vertices, ordered once per graph structure by AMD on the block graph and factorised by
// Eigen's simplicial LDL^T. All buffers live in the PoseGraphOptimizer object: solving again a
// graph with the same structure (vertex count, edge endpoints, fixed set) allocates nothing
// (as long as the free dimension is below Eigen's stack limit of 16384 scalars, ~2700 SE3
// vertices; above it Eigen's factorisation takes its scratch from the heap).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/base/status.h"
#include "core/geometry/lie.h"
#include "core/optim/lm.h"
#include "core/optim/robust.h"

namespace ale::optim {

// Per-group sizes and types.
template <class Group>
struct PoseGraphGroup;

template <>
struct PoseGraphGroup<geometry::SE3> {
  static constexpr int kDim = 6;
  using Tangent = geometry::Vec6;
  using Matrix = geometry::Mat6;
};

template <>
struct PoseGraphGroup<geometry::Sim3> {
  static constexpr int kDim = 7;
  using Tangent = geometry::Vec7;
  using Matrix = geometry::Mat7;
};

// e = log(T_ij * T_jw * T_iw^-1) and, when the pointers are given, its Jacobians with respect
// to the left perturbations of T_iw and T_jw.
template <class Group>
typename PoseGraphGroup<Group>::Tangent pose_graph_residual(const Group& T_ij, const Group& T_iw, const Group& T_jw,
                                                             typename PoseGraphGroup<Group>::Matrix* d_e_d_i,
                                                             typename PoseGraphGroup<Group>::Matrix* d_e_d_j);

template <class Group>
struct PoseGraphEdge {
  using Information = typename PoseGraphGroup<Group>::Matrix;
  int i = -1;
  int j = -1;
  Group T_ij;  // measured: frame j to frame i
  Information information = Information::Identity();
  RobustKernel kernel;  // on s = e^T Omega e; none by default
};

struct PoseGraphSummary {
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int iterations = 0;  // accepted and rejected LM steps
  int accepted_steps = 0;
  LmStop stop = LmStop::kRunning;
};

template <class Group>
class PoseGraphOptimizer {
 public:
  static constexpr int kDim = PoseGraphGroup<Group>::kDim;

  // Refines poses[v] for every vertex not in fixed_vertices. On any failure the poses are left
  // as they were given. Errors: no edges, an edge naming a missing vertex or itself, a
  // non-finite pose or measurement, an information matrix that is not symmetric positive
  // definite, a vertex not connected to a fixed one (no gauge), a non-finite cost or step, no
  // convergence within options.max_iterations (kNotConverged).
  Result<PoseGraphSummary> optimize(const std::vector<PoseGraphEdge<Group>>& edges,
                                    const std::vector<int>& fixed_vertices, const LmOptions& options,
                                    std::vector<Group>* poses);

  // 1/2 sum rho(e^T Omega e) at the given poses (no validation beyond the indices).
  static double cost(const std::vector<PoseGraphEdge<Group>>& edges, const std::vector<Group>& poses);

 private:
  using Block = typename PoseGraphGroup<Group>::Matrix;
  using Tangent = typename PoseGraphGroup<Group>::Tangent;

  Status check_inputs(const std::vector<PoseGraphEdge<Group>>& edges, const std::vector<int>& fixed_vertices,
                      const std::vector<Group>& poses) const;
  bool same_structure(const std::vector<PoseGraphEdge<Group>>& edges, const std::vector<int>& fixed_vertices,
                      std::size_t vertex_count) const;
  Status build_structure(const std::vector<PoseGraphEdge<Group>>& edges, const std::vector<int>& fixed_vertices,
                         std::size_t vertex_count);
  // Fills hessian_, gradient_ and diagonal_ at the poses; returns the cost.
  double linearize(const std::vector<PoseGraphEdge<Group>>& edges, const std::vector<Group>& poses);
  // step_ = -(H + lambda D)^-1 g; false when the factorisation fails or the step is not finite.
  bool solve_damped(const LmController& lm);
  // poses[v] <- exp(step_v) poses[v] for the free vertices; returns |step|.
  double apply_step(std::vector<Group>* poses) const;

  // Structure (rebuilt only when the graph's structure changes).
  std::size_t vertex_count_ = 0;
  std::vector<int> edge_ends_;       // i, j per edge, to detect a structure change
  std::vector<int> fixed_sorted_;    // the fixed set, sorted and unique
  mutable std::vector<std::uint8_t> fixed_mark_;  // scratch of same_structure, all 0 between calls
  std::vector<int> position_;        // vertex -> block position in the ordered system, -1 fixed
  std::vector<int> slot_ii_, slot_jj_, slot_ij_;  // per edge, -1 when a vertex is fixed
  std::vector<std::uint8_t> ij_transposed_;       // block (pos i, pos j) stored as its transpose
  std::vector<int> slot_base_, slot_stride_;      // per slot: value index of (0, 0), column stride
  std::vector<int> diagonal_index_;               // value index of each diagonal scalar

  // Eigen's LDL^T with its factorisation entry points that neither order nor copy the input
  // (the matrix is built already ordered, upper triangle, so Eigen's factorize() would only
  // add a temporary SparseMatrix per call).
  using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  class Ldlt : public Eigen::SimplicialLDLT<SparseMatrix, Eigen::Upper, Eigen::NaturalOrdering<int>> {
   public:
    void analyze_ordered(const SparseMatrix& a) { analyzePattern_preordered(a, true); }
    void factorize_ordered(const SparseMatrix& a) { factorize_preordered<true>(a); }
  };

  // Numeric buffers, sized by build_structure.
  SparseMatrix hessian_;          // upper block triangle of J^T W J, ordered
  Eigen::VectorXd gradient_;      // J^T W e
  Eigen::VectorXd diagonal_;      // the undamped diagonal of hessian_
  Eigen::VectorXd step_;
  Ldlt ldlt_;
  std::vector<Group> initial_poses_;  // restored on failure
  std::vector<Group> saved_poses_;    // before a trial step
};

}  // namespace ale::optim
