// Bundle adjustment over camera poses T_cw and points p_w with the reprojection residual
// (core/optim/reprojection.h), Levenberg-Marquardt (core/optim/lm.h) and the Schur complement
// (core/optim/schur.h).
//
// - Any subset of poses (and points) may be fixed, or none: without a fixed pose the problem
//   has a 7-dof gauge freedom and the Marquardt damping keeps every step well defined (the
//   cost, not the gauge, is what converges).
// - Each observation has its own information (1/sigma^2, sigma by pyramid level: see
//   level_information) and robust kernel. With passes > 1, observations whose chi-square
//   (information * |r|^2) exceeds chi2_gate, or whose point is behind the camera, are removed
//   between passes (ORB-SLAM's local BA: passes = 2, robust_after_first_pass = false).
// - Which side the Schur complement eliminates: kPoints (3x3 blocks), kPoses, or kAuto (the
//   default, points whenever there are at least twice as many points as free poses), which
//   eliminates the side that leaves the smaller reduced system (film tracking: hundreds of
//   cameras, tens of points -> poses). The reduced system is factorised densely up to
//   dense_max_dim (256: a dense LLT of 256 is ~5.6 MFlop, cheaper than a sparse factorisation
//   of the usually dense camera system of a local BA) and sparsely beyond, unless more than 30 %
//   of its blocks are nonzero (then densely at any size).
// - Buffers are reused and only grow (core/base/grow.h): after a first solve() of a problem,
//   building and solving a problem of the same structure allocates nothing, dense or sparse, and
//   on the dense path neither does any problem no larger than the largest so far, or than
//   reserve() made room for (tested by counting malloc and operator new). A new structure is
//   analysed once; a sparse analysis allocates.
// - Failure is a status, never an exception: invalid input or too few observations
//   (kInvalidArgument), not converged within max_iterations on the last pass (kNotConverged, the
//   state is the best one reached), numerical failure (kInternal). Poses and points stay finite:
//   a step that is not finite or not solvable is rejected.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/grow.h"
#include "core/base/status.h"
#include "core/geometry/camera.h"
#include "core/geometry/chi_square.h"
#include "core/geometry/lie.h"
#include "core/optim/lm.h"
#include "core/optim/robust.h"
#include "core/optim/schur.h"

namespace ale::optim {

// 1/sigma^2 for a keypoint of pyramid level `level`: sigma = scale_factor^level pixels.
double level_information(double scale_factor, int level);

enum class SchurElimination { kPoints, kPoses, kAuto };

struct BaOptions {
  LmOptions lm;  // per pass
  int passes = 1;
  // > 0 with passes > 1: the first pass, which only has to separate the outliers, stops after
  // this many iterations (ORB-SLAM's local BA: 5, then 10); its stop is not a failure.
  int first_pass_iterations = 0;
  // > 0 with passes > 1: the first pass also stops when an accepted step lowers the cost by less
  // than this share (lm.function_tolerance when that is larger).
  double first_pass_function_tolerance = 0.0;
  double chi2_gate = geometry::kChi2TwoDof95;  // chi-square 95 % for 2 dof; <= 0: no classification at all
  bool robust_after_first_pass = true;
  SchurElimination elimination = SchurElimination::kAuto;
  int dense_max_dim = 256;  // < 0: always sparse (tests)
};

struct BaSummary {
  Status status;
  LmStop stop = LmStop::kRunning;  // of the last pass
  int iterations = 0;              // LM iterations over all passes (rejected steps count)
  int passes = 0;
  double initial_cost = 0.0;  // 0.5 * sum rho(chi2) at the start of the first pass
  double final_cost = 0.0;    // at the end of the last pass, over that pass's observations
  int inliers = 0, outliers = 0;
  bool points_eliminated = true;
  bool sparse = false;
  int reduced_dim = 0;
};

class BundleAdjuster {
 public:
  // Clears the problem (every buffer keeps its capacity) and sets the camera.
  void reset(const geometry::Camera& camera);
  int add_pose(const geometry::SE3& T_cw, bool fixed);
  int add_point(const geometry::Vec3& p_w, bool fixed = false);
  // information = 1/sigma^2 of the (isotropic) pixel noise. Returns the observation's index.
  int add_observation(int pose, int point, const geometry::Vec2& uv_px, double information = 1.0,
                      const RobustKernel& kernel = RobustKernel());

  // A point on a plane fixed in a pose's camera frame: the residual n_c . p_c + offset (metres
  // or map units) with p_c = T_cw p_w, for example a landmark on the floor, whose height below the
  // camera along the floor's normal n_c (unit, camera frame) is the camera's height `offset`.
  // Handled as an observation (its second residual row is zero): weighted by information and the
  // kernel, classified against chi2_gate like a reprojection, counted in num_observations().
  int add_plane_observation(int pose, int point, const geometry::Vec3& normal_c, double offset, double information,
                            const RobustKernel& kernel = RobustKernel());

  // A soft prior on a pose's camera centre (T_cw.inverse().translation()): the cost gains
  // 0.5 rho(|c - centre_w|^2 / sigma^2) with the kernel (none: quadratic); never classified as
  // an outlier. sigma > 0.
  void add_centre_prior(int pose, const geometry::Vec3& centre_w, double sigma,
                        const RobustKernel& kernel = RobustKernel());
  // A soft prior on a pose's rotation: the cost gains 0.5 rho(|log(R_cw R_target^T)|^2 / sigma^2)
  // (sigma in radians, isotropic) with the kernel; never classified as an outlier. sigma > 0.
  void add_rotation_prior(int pose, const geometry::Mat3& R_cw_target, double sigma_rad,
                          const RobustKernel& kernel = RobustKernel());

  BaSummary solve(const BaOptions& options);
  // Room for problems up to this size (points eliminated, a reduced system up to dense_max_dim
  // dense) without allocating in add_*() and solve(); larger ones grow the buffers.
  void reserve(int poses, int points, int observations, int dense_max_dim = BaOptions().dense_max_dim);

  int num_poses() const { return static_cast<int>(poses_.size()); }
  int num_points() const { return static_cast<int>(points_.size()); }
  int num_observations() const { return static_cast<int>(obs_.size()); }
  const geometry::SE3& pose(int i) const { return poses_[i]; }
  const geometry::Vec3& point(int j) const { return points_[j]; }
  // After solve(): false for observations classified as outliers (or not projectable).
  bool is_inlier(int k) const { return inlier_[k] != 0; }

 private:
  struct Observation {
    int pose, point;
    geometry::Vec2 uv_px;
    double information;
    RobustKernel kernel;
    bool plane = false;  // add_plane_observation: normal and offset instead of uv_px
    geometry::Vec3 normal = geometry::Vec3::Zero();
    double offset = 0.0;
  };
  // The observation's residual at pose (R_cw, t_cw) and point p_w with its Jacobians (may be
  // null); false when the point is not in front of the camera (or does not project).
  bool residual(const Observation& o, const geometry::Mat3& R_cw, const geometry::Vec3& t_cw, const geometry::Vec3& p_w,
                geometry::Vec2* r, geometry::Mat26* jc, geometry::Mat23* jl) const;
  // One linearisation: residual, Jacobians and IRLS weight (information * rho') per observation.
  struct Linearisation {
    std::vector<geometry::Vec2> r;
    std::vector<geometry::Mat26> jc;
    std::vector<geometry::Mat23> jl;
    std::vector<double> w;
    void resize(std::size_t n) {
      grow_resize(r, n);
      grow_resize(jc, n);
      grow_resize(jl, n);
      grow_resize(w, n);
    }
    void swap(Linearisation& o) {
      r.swap(o.r);
      jc.swap(o.jc);
      jl.swap(o.jl);
      w.swap(o.w);
    }
  };

  Status validate() const;
  double evaluate(const std::vector<geometry::SE3>& poses, const std::vector<geometry::Vec3>& points,
                  bool use_kernel, Linearisation* lin);
  int classify(double chi2_gate);
  template <int E, int K>
  void accumulate(internal::SchurSystem<E, K>* s) const;
  template <int E, int K>
  BaSummary run(internal::SchurSystem<E, K>* s, const BaOptions& options);
  template <int E, int K>
  void apply_step(const std::vector<Eigen::Matrix<double, E, 1>>& dxe,
                  const std::vector<Eigen::Matrix<double, K, 1>>& dxk, double* step_norm);
  double state_norm() const;

  geometry::Camera camera_;
  std::vector<geometry::SE3> poses_, poses_candidate_;
  std::vector<geometry::Vec3> points_, points_candidate_;
  std::vector<std::uint8_t> pose_fixed_, point_fixed_;
  std::vector<Observation> obs_;
  struct CentrePriorTerm {
    int pose;
    geometry::Vec3 centre_w;
    double information;
    RobustKernel kernel;
  };
  std::vector<CentrePriorTerm> priors_;
  struct RotationPriorTerm {
    int pose;
    geometry::Mat3 R_target;
    double information;
    RobustKernel kernel;
  };
  std::vector<RotationPriorTerm> rotation_priors_;
  std::vector<std::uint8_t> inlier_;
  std::vector<int> free_pose_, free_point_;
  int n_free_poses_ = 0, n_free_points_ = 0;
  std::vector<geometry::Mat3> rotation_;  // per pose, refreshed by evaluate()
  Linearisation lin_, lin_candidate_;
  int first_bad_observation_ = -1;
  bool bad_prior_ = false;

  // Structure the Schur systems were analysed for (re-analysed only when it changes).
  std::vector<int> term_elim_, term_keep_;
  std::vector<int> analysed_elim_, analysed_keep_;
  int analysed_kind_ = -1, analysed_dense_max_dim_ = -1, analysed_n_elim_ = -1, analysed_n_keep_ = -1;
  internal::SchurSystem<3, 6> points_eliminated_;
  internal::SchurSystem<6, 3> poses_eliminated_;
  std::vector<Eigen::Matrix<double, 3, 1>> dx3_;
  std::vector<Eigen::Matrix<double, 6, 1>> dx6_;
};

}  // namespace ale::optim
