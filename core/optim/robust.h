// Robust kernels on squared residuals, in Ceres' convention: for s = squared (whitened)
// residual norm, the cost of one residual is 0.5 * rho(s), rho(s) = s for small s, and
// rho'(s) is the weight an iteratively reweighted Gauss-Newton step gives that residual
// (same gradient as the robust cost: d(0.5 rho(|r|^2)) / dr = rho'(s) r).
//
// The threshold `delta` is in residual units (not squared): Huber with delta = sqrt(5.991) is
// ORB-SLAM's monocular kernel. Tukey's rho is scaled so that rho'(0) = 1 like the others.
#pragma once

namespace ale::optim {

enum class RobustKind { kNone, kHuber, kCauchy, kTukey };

struct RobustKernel {
  RobustKind kind = RobustKind::kNone;
  double delta = 1.0;  // residual-unit threshold (> 0; ignored by kNone)

  static RobustKernel none() { return {}; }
  static RobustKernel huber(double d) { return {RobustKind::kHuber, d}; }
  static RobustKernel cauchy(double d) { return {RobustKind::kCauchy, d}; }
  static RobustKernel tukey(double d) { return {RobustKind::kTukey, d}; }

  // rho(s) for s >= 0.
  double rho(double s) const;
  // rho'(s) = the IRLS weight; in [0, 1], 1 at s = 0.
  double d_rho(double s) const;
  // Both at once (the optimisers need the cost and the weight of every residual).
  void evaluate(double s, double* rho_s, double* weight) const;
  double weight(double s) const { return d_rho(s); }
};

}  // namespace ale::optim
