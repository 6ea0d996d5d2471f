// The reference solver for ale-slam's bundle adjuster (host only; never linked into the
// daemon): the same reprojection residual (radial-tangential pinhole, intrinsics fixed) in
// Ceres with automatic derivatives, poses as angle-axis + translation (x_c = R x_w + t),
// points as 3-vectors. Used by ale_ba_bench, the libmv comparison tests and the benchmarks.
#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry/camera.h"
#include "core/geometry/lie.h"
#include "app/tools/lib/ba/libmv_problem.h"
#include "core/optim/motion_only.h"

namespace ale::ceres_ref {

enum class Solver { kSparseSchur, kDenseSchur, kDenseQr };

struct Options {
  Solver solver = Solver::kSparseSchur;
  int max_iterations = 50;
  double function_tolerance = 1e-6;   // Ceres' defaults
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  double huber_delta = 0.0;  // > 0: Huber on every residual block
};

struct Result {
  bool usable = false;  // Ceres' summary.IsSolutionUsable()
  double initial_cost = 0.0, final_cost = 0.0;
  int iterations = 0;  // successful + unsuccessful steps
  double time_ms = 0.0;
  bool converged = false;
};

struct Observation {
  int pose = 0, point = 0;
  geometry::Vec2 uv_px = geometry::Vec2::Zero();
  double information = 1.0;
};

// Refines poses (those not fixed) and points in place. One thread.
Result solve_ba(const geometry::CameraIntrinsics& k, std::vector<geometry::SE3>* T_cw,
                const std::vector<bool>& pose_fixed, std::vector<geometry::Vec3>* points_w,
                const std::vector<Observation>& observations, const Options& options);

// The libmv problem as above (no pose fixed: the gauge is free, as in Ceres' libmv example).
Result solve_libmv(optim::LibmvProblem* problem, const Options& options);

// ORB-SLAM's motion-only rounds with Ceres doing each round's optimisation (DENSE_QR, Huber on
// the first robust_rounds, at most `iterations` per round); classification as ours.
optim::MotionOnlyResult optimize_pose(const geometry::CameraIntrinsics& k, const geometry::SE3& T_cw_init,
                                      const optim::PoseObservation* observations, int n,
                                      const optim::MotionOnlyOptions& options, std::uint8_t* inlier);

}  // namespace ale::ceres_ref
