// The pose-graph problem of core/optim/pose_graph.h in Ceres (host-only reference).
//
// Each vertex is a parameter block of ambient coordinates (qx, qy, qz, qw, tx, ty, tz[, log s])
// with a Manifold whose Plus is lie.h's left perturbation exp(delta) * T, so Ceres steps in the
// same tangent as ours. The residual is r = L^T e with Omega = L L^T, e = log(T_ij T_jw T_iw^-1),
// so 1/2 |r|^2 = 1/2 e^T Omega e; the edge's kernel becomes the same Ceres loss.
// Two Jacobian sources:
// - kNumeric: central differences of the residual in the ambient coordinates, times the
//   manifold's analytic PlusJacobian (checked against differences of Plus in the test). Shares
//   no Jacobian code with ours, so agreeing final costs test our Jacobians and solver.
// - kAnalytic: our analytic tangent Jacobians, returned in the first kDim ambient columns with
//   PlusJacobian = [I; 0] (the usual trick for a left-perturbation manifold); the benchmark uses
//   it so Ceres is timed with Jacobians as cheap as ours.
#pragma once

#include <memory>
#include <vector>

#include <ceres/ceres.h>

#include "core/geometry/lie.h"
#include "core/optim/pose_graph.h"

namespace ale::optim::test {

enum class CeresJacobians { kNumeric, kAnalytic };

// Rotation and translation of either group to and from x[0..6].
template <class Group>
void rigid_to_ambient(const Group& t, double* x) {
  const Eigen::Quaterniond& q = t.so3().quaternion();
  x[0] = q.x(), x[1] = q.y(), x[2] = q.z(), x[3] = q.w();
  for (int r = 0; r < 3; ++r) x[4 + r] = t.translation()[r];
}
inline geometry::SO3 rotation_from_ambient(const double* x) {
  return geometry::SO3(Eigen::Quaterniond(x[3], x[0], x[1], x[2]));
}

template <class Group>
struct Ambient;

template <>
struct Ambient<geometry::SE3> {
  static constexpr int kSize = 7;
  static void to(const geometry::SE3& t, double* x) { rigid_to_ambient(t, x); }
  static geometry::SE3 from(const double* x) {
    return geometry::SE3(rotation_from_ambient(x), geometry::Vec3(x[4], x[5], x[6]));
  }
};

template <>
struct Ambient<geometry::Sim3> {
  static constexpr int kSize = 8;
  static void to(const geometry::Sim3& s, double* x) {
    rigid_to_ambient(s, x);
    x[7] = std::log(s.scale());
  }
  static geometry::Sim3 from(const double* x) {
    return geometry::Sim3(rotation_from_ambient(x), geometry::Vec3(x[4], x[5], x[6]), std::exp(x[7]));
  }
};

template <class Group>
class LeftPerturbationManifold : public ceres::Manifold {
 public:
  static constexpr int kDim = PoseGraphGroup<Group>::kDim;
  static constexpr int kAmbient = Ambient<Group>::kSize;
  using PlusMatrix = Eigen::Matrix<double, kAmbient, kDim, Eigen::RowMajor>;

  explicit LeftPerturbationManifold(CeresJacobians jacobians) : jacobians_(jacobians) {}
  int AmbientSize() const override { return kAmbient; }
  int TangentSize() const override { return kDim; }

  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Eigen::Map<const typename PoseGraphGroup<Group>::Tangent> d(delta);
    Ambient<Group>::to(Group::exp(d) * Ambient<Group>::from(x), x_plus_delta);
    return true;
  }

  // d Plus(x, delta) / d delta at 0, analytic: q' = q(phi) q gives dq'/dphi_k = 1/2 (e_k, 0) q;
  // t' = s(sigma) R(phi) t + W rho gives dt'/drho = I, dt'/dphi = -hat(t), dt'/dsigma = t;
  // log s' = sigma + log s.
  static PlusMatrix plus_jacobian(const double* x) {
    PlusMatrix j = PlusMatrix::Zero();
    const double qx = x[0], qy = x[1], qz = x[2], qw = x[3];
    // (0, e) * (qw, qv) = (-e . qv, qw e + e x qv), halved; rows x y z w.
    j.template block<4, 3>(0, 3) << 0.5 * qw, 0.5 * qz, -0.5 * qy,  //
        -0.5 * qz, 0.5 * qw, 0.5 * qx,                               //
        0.5 * qy, -0.5 * qx, 0.5 * qw,                               //
        -0.5 * qx, -0.5 * qy, -0.5 * qz;
    const geometry::Vec3 t(x[4], x[5], x[6]);
    j.template block<3, 3>(4, 0).setIdentity();
    j.template block<3, 3>(4, 3) = -geometry::hat(t);
    if constexpr (kDim == 7) {
      j.template block<3, 1>(4, 6) = t;
      j(7, 6) = 1.0;
    }
    return j;
  }

  bool PlusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<PlusMatrix> j(jacobian);
    if (jacobians_ == CeresJacobians::kAnalytic) {
      j.setZero();
      j.template topRows<kDim>().setIdentity();
    } else {
      j = plus_jacobian(x);
    }
    return true;
  }

  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    Eigen::Map<typename PoseGraphGroup<Group>::Tangent> d(y_minus_x);
    d = (Ambient<Group>::from(y) * Ambient<Group>::from(x).inverse()).log();
    return true;
  }

  // A left inverse of PlusJacobian (Ceres' solver does not use MinusJacobian).
  bool MinusJacobian(const double* x, double* jacobian) const override {
    PlusMatrix pj;
    PlusJacobian(x, pj.data());
    Eigen::Map<Eigen::Matrix<double, kDim, kAmbient, Eigen::RowMajor>> m(jacobian);
    m = (pj.transpose() * pj).inverse() * pj.transpose();
    return true;
  }

 private:
  CeresJacobians jacobians_;
};

template <class Group>
struct EdgeResidual {
  static constexpr int kDim = PoseGraphGroup<Group>::kDim;
  using Matrix = typename PoseGraphGroup<Group>::Matrix;
  Group T_ij;
  Matrix sqrt_information_t;  // L^T

  bool operator()(const double* x_i, const double* x_j, double* r) const {
    const typename PoseGraphGroup<Group>::Tangent e =
        pose_graph_residual<Group>(T_ij, Ambient<Group>::from(x_i), Ambient<Group>::from(x_j), nullptr, nullptr);
    Eigen::Map<typename PoseGraphGroup<Group>::Tangent> residual(r);
    residual = sqrt_information_t * e;
    return true;
  }
};

template <class Group>
class AnalyticEdgeCost
    : public ceres::SizedCostFunction<PoseGraphGroup<Group>::kDim, Ambient<Group>::kSize, Ambient<Group>::kSize> {
 public:
  static constexpr int kDim = PoseGraphGroup<Group>::kDim;
  static constexpr int kAmbient = Ambient<Group>::kSize;
  explicit AnalyticEdgeCost(const EdgeResidual<Group>& residual) : r_(residual) {}

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    typename PoseGraphGroup<Group>::Matrix d_e_d_i, d_e_d_j;
    const typename PoseGraphGroup<Group>::Tangent e =
        pose_graph_residual<Group>(r_.T_ij, Ambient<Group>::from(parameters[0]), Ambient<Group>::from(parameters[1]),
                                   &d_e_d_i, &d_e_d_j);
    Eigen::Map<typename PoseGraphGroup<Group>::Tangent> residual(residuals);
    residual = r_.sqrt_information_t * e;
    using Jacobian = Eigen::Matrix<double, kDim, kAmbient, Eigen::RowMajor>;
    const typename PoseGraphGroup<Group>::Matrix* d[2] = {&d_e_d_i, &d_e_d_j};
    for (int b = 0; b < 2; ++b) {
      if (jacobians == nullptr || jacobians[b] == nullptr) continue;
      Eigen::Map<Jacobian> j(jacobians[b]);
      j.setZero();
      j.template leftCols<kDim>() = r_.sqrt_information_t * *d[b];
    }
    return true;
  }

 private:
  EdgeResidual<Group> r_;
};

inline ceres::LossFunction* ceres_loss(const RobustKernel& kernel) {
  switch (kernel.kind) {
    case RobustKind::kNone: return nullptr;
    case RobustKind::kHuber: return new ceres::HuberLoss(kernel.delta);
    case RobustKind::kCauchy: return new ceres::CauchyLoss(kernel.delta);
    case RobustKind::kTukey: return nullptr;  // Ceres' Tukey has rho'(0) = 1/2: not the same cost
  }
  return nullptr;
}

// The problem over params (one ambient block per vertex, filled from poses).
template <class Group>
class CeresPoseGraph {
 public:
  static constexpr int kDim = PoseGraphGroup<Group>::kDim;
  static constexpr int kAmbient = Ambient<Group>::kSize;

  CeresPoseGraph(const std::vector<PoseGraphEdge<Group>>& edges, const std::vector<int>& fixed,
                 const std::vector<Group>& poses, CeresJacobians jacobians)
      : params_(poses.size() * kAmbient) {
    for (std::size_t v = 0; v < poses.size(); ++v) Ambient<Group>::to(poses[v], block(static_cast<int>(v)));
    for (const PoseGraphEdge<Group>& edge : edges) {
      EdgeResidual<Group> residual{edge.T_ij, Eigen::LLT<typename PoseGraphGroup<Group>::Matrix>(edge.information)
                                                  .matrixL()
                                                  .transpose()};
      ceres::CostFunction* cost = nullptr;
      if (jacobians == CeresJacobians::kAnalytic) {
        cost = new AnalyticEdgeCost<Group>(residual);
      } else {
        cost = new ceres::NumericDiffCostFunction<EdgeResidual<Group>, ceres::CENTRAL, kDim, kAmbient, kAmbient>(
            new EdgeResidual<Group>(residual));
      }
      problem_.AddResidualBlock(cost, ceres_loss(edge.kernel), block(edge.i), block(edge.j));
    }
    for (std::size_t v = 0; v < poses.size(); ++v) {
      double* b = block(static_cast<int>(v));
      if (!problem_.HasParameterBlock(b)) continue;
      problem_.SetManifold(b, new LeftPerturbationManifold<Group>(jacobians));
    }
    for (int v : fixed) {
      if (problem_.HasParameterBlock(block(v))) problem_.SetParameterBlockConstant(block(v));
    }
  }

  double* block(int v) { return params_.data() + static_cast<std::size_t>(v) * kAmbient; }
  ceres::Problem& problem() { return problem_; }

  double cost() {
    double c = 0.0;
    problem_.Evaluate(ceres::Problem::EvaluateOptions(), &c, nullptr, nullptr, nullptr);
    return c;
  }

  // The solver settings of the comparisons: LM, sparse normal Cholesky, one thread, and
  // tolerances tight enough that both solvers stop at the minimum.
  static ceres::Solver::Options options(int max_iterations = 200) {
    ceres::Solver::Options o;
    o.minimizer_type = ceres::TRUST_REGION;
    o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    o.num_threads = 1;
    o.max_num_iterations = max_iterations;
    o.function_tolerance = 1e-12;
    o.parameter_tolerance = 1e-12;
    o.gradient_tolerance = 1e-14;
    o.logging_type = ceres::SILENT;
    return o;
  }

  ceres::Solver::Summary solve(const ceres::Solver::Options& o) {
    ceres::Solver::Summary summary;
    ceres::Solve(o, &problem_, &summary);
    return summary;
  }

  Group pose(int v) { return Ambient<Group>::from(block(v)); }

 private:
  std::vector<double> params_;
  ceres::Problem problem_;
};

}  // namespace ale::optim::test
