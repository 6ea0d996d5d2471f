// Bundle adjustment: analytic Jacobians vs numeric, synthetic scenes with noise and outliers
// converging to the truth, fixed poses respected, dense/sparse and both eliminations agreeing,
// statuses for bad input, and no allocation once the buffers are warm.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "core/optim/bundle_adjuster.h"
#include "core/optim/reprojection.h"
#include "app/tools/lib/ba/synthetic_problem.h"
#include "tests/host/core/optim/alloc_counter.h"

namespace ale::optim {
namespace {

using geometry::Camera;
using geometry::CameraIntrinsics;
using geometry::CameraModel;
using geometry::Mat23;
using geometry::Mat26;
using geometry::SE3;
using geometry::SO3;
using geometry::Vec2;
using geometry::Vec3;
using geometry::Vec6;

Camera camera_of(const CameraIntrinsics& k) { return Camera::create(k).value(); }

CameraIntrinsics equidistant() {
  CameraIntrinsics k;
  k.model = CameraModel::kEquidistant;
  k.fx = 380;
  k.fy = 381;
  k.cx = 320;
  k.cy = 240;
  k.distortion = {0.01, -0.005, 0.002, -0.0005, 0.0};
  return k;
}

TEST(Reprojection, JacobiansMatchNumericDifferences) {
  const SyntheticScene scene = make_synthetic_scene({});
  for (const CameraIntrinsics& k : {scene.intrinsics, equidistant()}) {
    const Camera cam = camera_of(k);
    const SE3 T_cw(SO3::exp(Vec3(0.1, -0.2, 0.3)), Vec3(0.2, -0.1, 0.5));
    for (const Vec3& p_c : {Vec3(0.3, -0.2, 2.0), Vec3(-1.0, 0.7, 3.0), Vec3(0.01, 0.02, 1.0)}) {
      const Vec3 p_w = T_cw.inverse() * p_c;
      const Vec2 obs(300, 200);
      Vec2 r;
      Mat26 jp;
      Mat23 jl;
      ASSERT_TRUE(reprojection_residual(cam, T_cw, p_w, obs, &r, &jp, &jl));
      const double h = 1e-6;
      for (int d = 0; d < 6; ++d) {
        Vec6 xi = Vec6::Zero();
        xi[d] = h;
        Vec2 rp, rm;
        ASSERT_TRUE(reprojection_residual(cam, SE3::exp(xi) * T_cw, p_w, obs, &rp));
        ASSERT_TRUE(reprojection_residual(cam, SE3::exp(-xi) * T_cw, p_w, obs, &rm));
        const Vec2 numeric = (rp - rm) / (2 * h);
        EXPECT_LT((numeric - jp.col(d)).norm(), 1e-5 * (1.0 + jp.col(d).norm())) << "pose dim " << d;
      }
      for (int d = 0; d < 3; ++d) {
        Vec3 dp = Vec3::Zero();
        dp[d] = h;
        Vec2 rp, rm;
        ASSERT_TRUE(reprojection_residual(cam, T_cw, p_w + dp, obs, &rp));
        ASSERT_TRUE(reprojection_residual(cam, T_cw, p_w - dp, obs, &rm));
        const Vec2 numeric = (rp - rm) / (2 * h);
        EXPECT_LT((numeric - jl.col(d)).norm(), 1e-5 * (1.0 + jl.col(d).norm())) << "point dim " << d;
      }
    }
    Vec2 r;
    EXPECT_FALSE(reprojection_residual(cam, SE3(), Vec3(0, 0, -1), Vec2(0, 0), &r));
  }
}

void load(const SyntheticScene& s, bool robust, BundleAdjuster* ba, const std::vector<bool>* fixed = nullptr) {
  ba->reset(camera_of(s.intrinsics));
  for (std::size_t i = 0; i < s.T_cw_init.size(); ++i) {
    const bool f = fixed ? (*fixed)[i] : s.pose_fixed[i];
    ba->add_pose(f ? s.T_cw_true[i] : s.T_cw_init[i], f);
  }
  for (const Vec3& p : s.points_init) ba->add_point(p);
  for (const SyntheticObservation& o : s.observations) {
    ba->add_observation(o.pose, o.point, o.uv_px, level_information(s.scale_factor, o.level),
                        robust ? RobustKernel::huber(std::sqrt(5.991)) : RobustKernel());
  }
}

double rotation_error_deg(const SE3& a, const SE3& b) {
  return (a.so3() * b.so3().inverse()).log().norm() * 180.0 / M_PI;
}

// Median over points of |p - p_true| / depth-ish scale, and the worst pose errors.
struct Errors {
  double median_point_m = 0, max_rot_deg = 0, max_centre_m = 0;
};
Errors errors(const SyntheticScene& s, const BundleAdjuster& ba) {
  Errors e;
  std::vector<double> d;
  for (int j = 0; j < ba.num_points(); ++j) d.push_back((ba.point(j) - s.points_true[j]).norm());
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  e.median_point_m = d[d.size() / 2];
  for (int i = 0; i < ba.num_poses(); ++i) {
    e.max_rot_deg = std::max(e.max_rot_deg, rotation_error_deg(ba.pose(i), s.T_cw_true[i]));
    e.max_centre_m = std::max(e.max_centre_m, (ba.pose(i).inverse().translation() - s.T_cw_true[i].inverse().translation()).norm());
  }
  return e;
}

// 300 points without noise or outliers.
SyntheticScene noise_free_scene() {
  SyntheticOptions so;
  so.points = 300;
  so.outlier_ratio = 0.0;
  so.noise_px = 0.0;
  return make_synthetic_scene(so);
}

TEST(BundleAdjuster, NoiseFreeConvergesExactly) {
  const SyntheticScene s = noise_free_scene();
  BundleAdjuster ba;
  load(s, false, &ba);
  BaOptions o;
  o.lm.function_tolerance = 1e-14;
  o.lm.max_iterations = 100;
  const BaSummary sum = ba.solve(o);
  ASSERT_TRUE(sum.status.ok()) << sum.status.to_string();
  const Errors e = errors(s, ba);
  EXPECT_LT(e.median_point_m, 1e-6);
  EXPECT_LT(e.max_rot_deg, 1e-6);
  EXPECT_LT(e.max_centre_m, 1e-7);
  EXPECT_LT(sum.final_cost, 1e-12);
}

TEST(BundleAdjuster, SyntheticNoiseConvergesToTruth) {
  SyntheticOptions so;
  so.points = 600;
  so.views_per_point = 8;  // a rigid block: every keyframe shares points with most others
  so.outlier_ratio = 0.0;
  const SyntheticScene s = make_synthetic_scene(so);
  // the gauge fixed by the two end keyframes (1.35 m apart): the scale is well determined
  std::vector<bool> ends(s.T_cw_init.size(), false);
  ends.front() = ends.back() = true;
  BundleAdjuster ba;
  load(s, false, &ba, &ends);
  const Errors before = errors(s, ba);
  BaOptions o;
  o.lm.function_tolerance = 1e-10;
  o.lm.max_iterations = 100;
  const BaSummary sum = ba.solve(o);
  ASSERT_TRUE(sum.status.ok()) << sum.status.to_string();
  const Errors after = errors(s, ba);
  // The minimum reached from the noisy start is the one reached from the truth.
  {
    SyntheticScene t = s;
    t.T_cw_init = t.T_cw_true;
    t.points_init = t.points_true;
    BundleAdjuster from_truth;
    load(t, false, &from_truth, &ends);
    const BaSummary st = from_truth.solve(o);
    ASSERT_TRUE(st.status.ok()) << st.status.to_string();
    EXPECT_NEAR(st.final_cost, sum.final_cost, 1e-9 * sum.final_cost);
    for (int i = 0; i < ba.num_poses(); ++i) {
      EXPECT_LT(rotation_error_deg(ba.pose(i), from_truth.pose(i)), 1e-5);
      EXPECT_LT((ba.pose(i).translation() - from_truth.pose(i).translation()).norm(), 1e-6);
    }
  }
  // Distance of that minimum from the truth: 1 px noise (x1.2^level, mean sigma ~2 px) with
  // f = 458 px and 1.35 m of baseline (measured: median point 0.062 m, rotation 0.16 deg,
  // centre 0.012 m; the start was 0.08 m, 0.94 deg, 0.05 m).
  EXPECT_LT(after.median_point_m, 0.08) << before.median_point_m;
  EXPECT_LT(after.max_rot_deg, 0.2) << before.max_rot_deg;
  EXPECT_LT(after.max_centre_m, 0.015) << before.max_centre_m;
  // chi-square per residual ~ 1 at the optimum: cost ~ 0.5 * (2N - params)
  const double dof = 2.0 * ba.num_observations() - 6 * 8 - 3 * ba.num_points();
  EXPECT_NEAR(sum.final_cost / (0.5 * dof), 1.0, 0.15);
  EXPECT_GT(sum.inliers, ba.num_observations() * 9 / 10);
}

// 1000 points seen 8 times, 20 % outlier observations, both end poses fixed: solved with
// ORB-SLAM's two passes (no kernel in the second), outliers counted against the truth.
struct OutlierRun {
  BaSummary summary;
  int true_out = 0, caught = 0, false_flags = 0, true_in = 0;
  Errors errors;
};

OutlierRun solve_outlier_scene(int first_pass_iterations) {
  SyntheticOptions so;
  so.points = 1000;
  so.views_per_point = 8;
  so.outlier_ratio = 0.2;
  so.seed = 7;
  const SyntheticScene s = make_synthetic_scene(so);
  std::vector<bool> ends(s.T_cw_init.size(), false);
  ends.front() = ends.back() = true;
  BundleAdjuster ba;
  load(s, true, &ba, &ends);
  BaOptions o;
  o.passes = 2;
  o.robust_after_first_pass = false;
  o.lm.max_iterations = 50;
  o.lm.function_tolerance = 1e-8;
  o.first_pass_iterations = first_pass_iterations;
  OutlierRun run;
  run.summary = ba.solve(o);
  for (int k = 0; k < ba.num_observations(); ++k) {
    const bool out = s.observations[k].outlier;
    run.true_out += out;
    run.true_in += !out;
    run.caught += out && !ba.is_inlier(k);
    run.false_flags += !out && !ba.is_inlier(k);
  }
  run.errors = errors(s, ba);
  std::printf("first pass at most %d: iterations %d, final cost %.6g, outliers caught %d of %d, good observations "
              "flagged %d of %d\n",
              first_pass_iterations, run.summary.iterations, run.summary.final_cost, run.caught, run.true_out,
              run.false_flags, run.true_in);
  return run;
}

void expect_outliers_removed_and_truth_recovered(const OutlierRun& run) {
  ASSERT_TRUE(run.summary.status.ok()) << run.summary.status.to_string();
  EXPECT_GE(run.caught, run.true_out * 96 / 100);
  // the 95 % chi-square gate rejects ~5 % of good observations, more where outliers bent a point
  EXPECT_LE(run.false_flags, run.true_in * 12 / 100);
  // as close to the truth as the outlier-free scene's minimum (test above): measured 0.087 m,
  // 0.15 deg, 0.011 m with 20 % outliers
  EXPECT_LT(run.errors.median_point_m, 0.1);
  EXPECT_LT(run.errors.max_rot_deg, 0.2);
  EXPECT_LT(run.errors.max_centre_m, 0.015);
}

TEST(BundleAdjuster, OutliersAreRemovedAndTruthRecovered) {
  expect_outliers_removed_and_truth_recovered(solve_outlier_scene(0));
}

// ORB-SLAM's local BA shape: a short first pass to separate the outliers, then a full one. The
// first pass stops at its own limit (not a failure); the result meets the same bounds.
TEST(BundleAdjuster, AShortFirstPassStillFindsTheOutliersAndConverges) {
  const OutlierRun full = solve_outlier_scene(0);
  const OutlierRun short_first = solve_outlier_scene(3);
  expect_outliers_removed_and_truth_recovered(short_first);
  EXPECT_EQ(short_first.summary.passes, 2);
  EXPECT_LT(short_first.summary.iterations, full.summary.iterations);
}

TEST(BundleAdjuster, FixedPosesStayPutAndGaugeFreeConverges) {
  SyntheticOptions so;
  so.points = 400;
  so.outlier_ratio = 0.0;
  so.fixed = 0;
  const SyntheticScene s = make_synthetic_scene(so);
  std::vector<bool> fixed(s.T_cw_init.size(), false);
  fixed[1] = fixed[4] = fixed[8] = true;
  BundleAdjuster ba;
  load(s, false, &ba, &fixed);
  BaOptions o;
  o.lm.max_iterations = 100;
  o.lm.function_tolerance = 1e-10;
  const BaSummary fixed_sum = ba.solve(o);
  ASSERT_TRUE(fixed_sum.status.ok()) << fixed_sum.status.to_string();
  for (int i = 0; i < ba.num_poses(); ++i) {
    if (fixed[i]) {
      EXPECT_EQ(ba.pose(i).translation(), s.T_cw_true[i].translation());  // load() fixes true poses
      EXPECT_EQ(ba.pose(i).so3().quaternion().coeffs(), s.T_cw_true[i].so3().quaternion().coeffs());
    } else {
      EXPECT_NE(ba.pose(i).translation(), s.T_cw_init[i].translation());
    }
  }
  // no pose fixed at all: the gauge is free, the damping keeps the steps finite and the cost
  // can only go lower than with three fixed (noisy) poses
  std::vector<bool> none(s.T_cw_init.size(), false);
  load(s, false, &ba, &none);
  const BaSummary free_sum = ba.solve(o);
  ASSERT_TRUE(free_sum.status.ok()) << free_sum.status.to_string();
  EXPECT_LE(free_sum.final_cost, fixed_sum.final_cost * (1 + 1e-9));
  for (int i = 0; i < ba.num_poses(); ++i) EXPECT_TRUE(ba.pose(i).translation().allFinite());
}

// The noise-free scene's poses and points at `scale` of the truth, with every observation.
void load_scaled(const SyntheticScene& s, double scale, BundleAdjuster* ba) {
  ba->reset(camera_of(s.intrinsics));
  for (const SE3& T : s.T_cw_true) ba->add_pose(SE3(T.so3(), scale * T.translation()), false);
  for (const Vec3& p : s.points_true) ba->add_point(scale * p);
  for (const SyntheticObservation& o : s.observations) {
    ba->add_observation(o.pose, o.point, o.uv_px, level_information(s.scale_factor, o.level));
  }
}

// Options that run the LM to convergence on a small noise-free scene, with this elimination.
BaOptions converged_options(SchurElimination elimination) {
  BaOptions o;
  o.lm.max_iterations = 100;
  o.lm.function_tolerance = 1e-14;
  o.elimination = elimination;
  return o;
}

// A noise-free scene given to the BA at 0.8 of its true scale, nothing fixed: the reprojections
// are exact at any scale, so without priors the BA stays there; centre priors at the true camera
// centres (wheel odometry's role in the local BA) bring it back to the true scale, with either
// side eliminated.
TEST(BundleAdjuster, CentrePriorsFixTheScaleTheViewsLeaveFree) {
  const SyntheticScene s = noise_free_scene();
  constexpr double kScale = 0.8;
  auto solve = [&](bool priors, SchurElimination elimination) {
    BundleAdjuster ba;
    load_scaled(s, kScale, &ba);
    if (priors) {
      for (int i = 0; i < ba.num_poses(); ++i) ba.add_centre_prior(i, s.T_cw_true[i].inverse().translation(), 0.01);
    }
    const BaSummary sum = ba.solve(converged_options(elimination));
    EXPECT_TRUE(sum.status.ok()) << sum.status.to_string();
    return errors(s, ba);
  };
  const Errors without = solve(false, SchurElimination::kAuto);
  EXPECT_GT(without.max_centre_m, 0.05) << "the views alone do not fix the scale";
  for (SchurElimination e : {SchurElimination::kPoints, SchurElimination::kPoses}) {
    const Errors with = solve(true, e);
    EXPECT_LT(with.max_centre_m, 1e-5);
    EXPECT_LT(with.median_point_m, 1e-5);
    EXPECT_LT(with.max_rot_deg, 1e-5);
  }
  // a prior on an unknown pose or with sigma <= 0 is refused by solve()
  BundleAdjuster bad;
  bad.reset(camera_of(s.intrinsics));
  bad.add_pose(SE3(), false);
  bad.add_centre_prior(3, Vec3::Zero(), 0.01);
  EXPECT_EQ(bad.solve(BaOptions{}).status.code(), StatusCode::kInvalidArgument);
}

// Rotation priors (the gyro's role in the local BA): the views of a noise-free scene hold every
// pose at the truth, so a prior whose target is the truth changes nothing, and a stiff prior 1 deg
// off pulls its pose there (the prior's direction and weight are right), with either side
// eliminated. Its linearisation, e + phi for a small left rotation phi, matches numeric
// differences to first order in e; a prior on an unknown pose or with sigma <= 0 is refused by solve().
TEST(BundleAdjuster, RotationPriorsPullTheirPoseToTheTarget) {
  const SyntheticScene s = noise_free_scene();
  const SO3 off = SO3::exp(Vec3(0.0, 1.0 * M_PI / 180.0, 0.0));
  auto solve = [&](const SO3& target_offset, double sigma_rad, SchurElimination elimination) {
    BundleAdjuster ba;
    load_scaled(s, 1.0, &ba);
    ba.add_rotation_prior(2, (target_offset * s.T_cw_true[2].so3()).matrix(), sigma_rad);
    const BaSummary sum = ba.solve(converged_options(elimination));
    EXPECT_TRUE(sum.status.ok()) << sum.status.to_string();
    return ba.pose(2);
  };
  for (SchurElimination e : {SchurElimination::kPoints, SchurElimination::kPoses}) {
    EXPECT_LT(rotation_error_deg(solve(SO3(), 1e-3, e), s.T_cw_true[2]), 1e-6);
    const SE3 pulled = solve(off, 1e-7, e);
    EXPECT_LT(rotation_error_deg(pulled, SE3(off * s.T_cw_true[2].so3(), Vec3::Zero())), 0.01);
    EXPECT_GT(rotation_error_deg(pulled, s.T_cw_true[2]), 0.99);
  }
  const geometry::Mat3 R = SO3::exp(Vec3(0.2, -0.1, 0.3)).matrix();
  const geometry::Mat3 target = (SO3::exp(Vec3(0.001, 0.002, -0.001)) * SO3::from_matrix(R)).matrix();
  const Vec3 e0 = rotation_residual(R, target);
  for (int d = 0; d < 3; ++d) {
    Vec3 phi = Vec3::Zero();
    phi[d] = 1e-6;
    const Vec3 de = (rotation_residual(SO3::exp(phi).matrix() * R, target) - e0) / 1e-6;
    // the identity the normal equations take, within J_l(e)^-1's first-order term |e| / 2
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(de[k], k == d ? 1.0 : 0.0, 0.5 * e0.norm() + 1e-5) << d << " " << k;
  }
  BundleAdjuster bad;
  bad.reset(camera_of(s.intrinsics));
  bad.add_pose(SE3(), false);
  bad.add_rotation_prior(3, geometry::Mat3::Identity(), 0.01);
  EXPECT_EQ(bad.solve(BaOptions{}).status.code(), StatusCode::kInvalidArgument);
  bad.reset(camera_of(s.intrinsics));
  bad.add_pose(SE3(), false);
  bad.add_rotation_prior(0, geometry::Mat3::Identity(), 0.0);
  EXPECT_EQ(bad.solve(BaOptions{}).status.code(), StatusCode::kInvalidArgument);
}

TEST(PlaneResidual, JacobiansMatchNumericDifferences) {
  const SE3 T_cw(SO3::exp(Vec3(0.1, -0.2, 0.3)), Vec3(0.2, -0.1, 0.5));
  const Vec3 n = Vec3(0.1, -0.95, 0.2).normalized();
  for (const Vec3& p_c : {Vec3(0.3, 0.09, 2.0), Vec3(-1.0, 0.7, 3.0), Vec3(0.01, 0.02, 0.4)}) {
    const Vec3 p_w = T_cw.inverse() * p_c;
    double r = 0.0;
    Eigen::Matrix<double, 1, 6> jp;
    Eigen::Matrix<double, 1, 3> jl;
    ASSERT_TRUE(plane_residual(T_cw.rotation(), T_cw.translation(), p_w, n, 0.09, &r, &jp, &jl));
    EXPECT_NEAR(r, n.dot(p_c) + 0.09, 1e-12);
    const double h = 1e-6;
    for (int d = 0; d < 6; ++d) {
      Vec6 xi = Vec6::Zero();
      xi[d] = h;
      double rp = 0.0, rm = 0.0;
      const SE3 Tp = SE3::exp(xi) * T_cw, Tm = SE3::exp(-xi) * T_cw;
      ASSERT_TRUE(plane_residual(Tp.rotation(), Tp.translation(), p_w, n, 0.09, &rp, nullptr, nullptr));
      ASSERT_TRUE(plane_residual(Tm.rotation(), Tm.translation(), p_w, n, 0.09, &rm, nullptr, nullptr));
      EXPECT_NEAR((rp - rm) / (2 * h), jp[d], 1e-6 * (1.0 + std::abs(jp[d]))) << "pose dim " << d;
    }
    for (int d = 0; d < 3; ++d) {
      Vec3 dp = Vec3::Zero();
      dp[d] = h;
      double rp = 0.0, rm = 0.0;
      ASSERT_TRUE(plane_residual(T_cw.rotation(), T_cw.translation(), p_w + dp, n, 0.09, &rp, nullptr, nullptr));
      ASSERT_TRUE(plane_residual(T_cw.rotation(), T_cw.translation(), p_w - dp, n, 0.09, &rm, nullptr, nullptr));
      EXPECT_NEAR((rp - rm) / (2 * h), jl[d], 1e-6 * (1.0 + std::abs(jl[d]))) << "point dim " << d;
    }
  }
  double r = 0.0;
  EXPECT_FALSE(plane_residual(geometry::Mat3::Identity(), Vec3::Zero(), Vec3(0, 0, -1), n, 0.09, &r, nullptr, nullptr));
}

// The same scene at 0.8 of its true scale: plane observations telling each of a third of the
// points its true distance along a normal in its first camera (a floor landmark's height below
// that camera) bring the whole scene back to the true scale, with either side eliminated; a
// plane observation with a non-finite normal is refused.
TEST(BundleAdjuster, PlaneObservationsFixTheScaleTheViewsLeaveFree) {
  const SyntheticScene s = noise_free_scene();
  constexpr double kScale = 0.8;
  const Vec3 n = Vec3(0.05, -0.98, 0.2).normalized();
  auto scale_of = [&](const BundleAdjuster& ba) {  // the solution's scale against the truth
    const Vec3 a = ba.pose(0).inverse().translation(), b = ba.pose(ba.num_poses() - 1).inverse().translation();
    const Vec3 ta = s.T_cw_true[0].inverse().translation(), tb = s.T_cw_true.back().inverse().translation();
    return (a - b).norm() / (ta - tb).norm();
  };
  auto solve = [&](bool planes, SchurElimination elimination) {
    BundleAdjuster ba;
    load_scaled(s, kScale, &ba);
    std::vector<int> first_pose(s.points_true.size(), -1);
    for (const SyntheticObservation& o : s.observations) {
      if (first_pose[static_cast<std::size_t>(o.point)] < 0) first_pose[static_cast<std::size_t>(o.point)] = o.pose;
    }
    int added = 0;
    for (std::size_t j = 0; planes && j < first_pose.size(); j += 3) {
      if (first_pose[j] < 0) continue;
      const Vec3 p_c = s.T_cw_true[static_cast<std::size_t>(first_pose[j])] * s.points_true[j];
      ba.add_plane_observation(first_pose[j], static_cast<int>(j), n, -n.dot(p_c), 1.0 / (0.005 * 0.005));
      ++added;
    }
    if (planes) {
      EXPECT_GT(added, 50);
    }
    BaOptions o;
    o.lm.max_iterations = 100;
    o.lm.function_tolerance = 1e-14;
    o.elimination = elimination;
    const BaSummary sum = ba.solve(o);
    EXPECT_TRUE(sum.status.ok()) << sum.status.to_string();
    EXPECT_EQ(sum.outliers, 0);
    return scale_of(ba);
  };
  EXPECT_NEAR(solve(false, SchurElimination::kAuto), kScale, 1e-6) << "the views alone keep any scale";
  for (SchurElimination e : {SchurElimination::kPoints, SchurElimination::kPoses}) {
    EXPECT_NEAR(solve(true, e), 1.0, 1e-6);
  }
  BundleAdjuster bad;
  bad.reset(camera_of(s.intrinsics));
  bad.add_pose(SE3(), false);
  bad.add_point(Vec3(0, 0, 1));
  bad.add_plane_observation(0, 0, Vec3(0, std::nan(""), 0), 0.1, 1.0);
  EXPECT_EQ(bad.solve(BaOptions{}).status.code(), StatusCode::kInvalidArgument);
}

TEST(BundleAdjuster, DenseSparseAndBothEliminationsAgree) {
  SyntheticOptions so;
  so.keyframes = 12;
  so.points = 80;
  so.outlier_ratio = 0.05;
  const SyntheticScene s = make_synthetic_scene(so);
  double reference = -1;
  for (SchurElimination elim : {SchurElimination::kPoints, SchurElimination::kPoses}) {
    for (int dense_max : {10000, -1}) {
      BundleAdjuster ba;
      load(s, true, &ba);
      BaOptions o;
      o.elimination = elim;
      o.dense_max_dim = dense_max;
      o.lm.function_tolerance = 1e-12;
      o.lm.max_iterations = 200;
      o.chi2_gate = 0;
      const BaSummary sum = ba.solve(o);
      ASSERT_TRUE(sum.status.ok()) << sum.status.to_string();
      EXPECT_EQ(sum.sparse, dense_max < 0);
      EXPECT_EQ(sum.points_eliminated, elim == SchurElimination::kPoints);
      if (reference < 0) reference = sum.final_cost;
      EXPECT_NEAR(sum.final_cost, reference, 1e-9 * reference);
    }
  }
}

TEST(BundleAdjuster, BadInputIsAStatus) {
  const SyntheticScene s = make_synthetic_scene({});
  BundleAdjuster ba;
  BaOptions o;
  ba.reset(Camera());
  ba.add_pose(SE3(), false);
  EXPECT_EQ(ba.solve(o).status.code(), StatusCode::kInvalidArgument);  // no camera
  ba.reset(camera_of(s.intrinsics));
  ba.add_pose(SE3(), false);
  ba.add_point(Vec3(0, 0, 3));
  ba.add_observation(0, 5, Vec2(1, 1));
  EXPECT_EQ(ba.solve(o).status.code(), StatusCode::kInvalidArgument);  // unknown point
  ba.reset(camera_of(s.intrinsics));
  ba.add_pose(SE3(), false);
  ba.add_point(Vec3(0, 0, 3));
  ba.add_observation(0, 0, Vec2(320, 240));
  const BaSummary few = ba.solve(o);
  EXPECT_EQ(few.status.code(), StatusCode::kInvalidArgument);  // 2 residuals, 9 parameters
  EXPECT_NE(few.status.message().find("too few"), std::string::npos);
  ba.reset(camera_of(s.intrinsics));
  ba.add_pose(SE3(SO3(), Vec3(NAN, 0, 0)), false);
  ba.add_point(Vec3(0, 0, 3));
  EXPECT_EQ(ba.solve(o).status.code(), StatusCode::kInvalidArgument);
  // not converged is a status, and the state is still finite
  load(s, true, &ba);
  o.lm.max_iterations = 2;
  o.lm.function_tolerance = 0;
  const BaSummary nc = ba.solve(o);
  EXPECT_EQ(nc.status.code(), StatusCode::kNotConverged);
  EXPECT_LT(nc.final_cost, nc.initial_cost);
  for (int i = 0; i < ba.num_poses(); ++i) EXPECT_TRUE(ba.pose(i).translation().allFinite());
}

TEST(BundleAdjuster, NoAllocationAfterTheFirstSolve) {
  SyntheticOptions so;
  so.points = 60;  // poses eliminated: a 180-dim dense reduced system
  const SyntheticScene s = make_synthetic_scene(so);
  BundleAdjuster ba;
  BaOptions o;
  o.passes = 2;
  o.lm.max_iterations = 10;
  for (SchurElimination elim : {SchurElimination::kPoints, SchurElimination::kPoses}) {
    for (int dense_max : {256, -1}) {  // dense and sparse reduced systems
      o.elimination = elim;
      o.dense_max_dim = dense_max;
      load(s, true, &ba);
      (void)ba.solve(o);  // warm-up: buffers grow to this problem's size
      load(s, true, &ba);
      test::AllocationCounter counter;
      const BaSummary sum = ba.solve(o);
      EXPECT_EQ(counter.count(), 0) << "allocations in a warm solve, sparse " << sum.sparse;
      EXPECT_EQ(sum.sparse, dense_max < 0);
      EXPECT_GT(sum.iterations, 5);
    }
  }
}

// The buffers keep their largest size: after a larger problem, a smaller one of another structure
// (other keyframes, points and observations: a local BA's next window) is solved without
// allocating, and reserve() makes room before the first solve (the dense, points-eliminated
// reduced system of a local BA).
TEST(BundleAdjuster, NoAllocationForASmallerProblemOrAfterReserve) {
  SyntheticOptions big_options;
  big_options.points = 800;
  SyntheticOptions small_options = big_options;
  small_options.keyframes = 7;
  small_options.points = 500;
  small_options.views_per_point = 4;
  small_options.seed = 2;
  const SyntheticScene big = make_synthetic_scene(big_options), small = make_synthetic_scene(small_options);
  BaOptions o;
  o.passes = 2;
  o.lm.max_iterations = 10;
  o.elimination = SchurElimination::kPoints;
  BundleAdjuster ba;
  load(big, true, &ba);
  EXPECT_TRUE(ba.solve(o).status.ok());
  load(small, true, &ba);
  {
    test::AllocationCounter counter;
    const BaSummary sum = ba.solve(o);
    EXPECT_EQ(counter.count(), 0) << "allocations in a smaller problem's solve";
    EXPECT_TRUE(sum.status.ok()) << sum.status.to_string();
    EXPECT_FALSE(sum.sparse);
  }
  BundleAdjuster reserved;
  reserved.reserve(static_cast<int>(big.T_cw_init.size()), static_cast<int>(big.points_init.size()),
                   static_cast<int>(big.observations.size()));
  test::AllocationCounter counter;
  load(big, true, &reserved);
  const BaSummary sum = reserved.solve(o);
  EXPECT_EQ(counter.count(), 0) << "allocations in a reserved problem's first build and solve";
  EXPECT_TRUE(sum.status.ok()) << sum.status.to_string();
}

// The Schur complement's written-out block product: s -= a^T b with each dot product summed left
// to right on every platform (Eigen's order differs between x86 and ARM; the host and the armhf
// build must give the same bits), on a block of a larger column-major matrix (the dense reduced
// system's outer stride), all of it or its upper triangle, leaving the rest of the matrix alone;
// and within rounding of Eigen's product.
TEST(SchurSystem, SubtractGramSumsLeftToRightOnItsBlock) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Matrix<double, 3, 6> a, b;
    for (int i = 0; i < 18; ++i) {
      a.data()[i] = u(rng) * std::pow(10.0, trial % 7 - 3);
      b.data()[i] = u(rng);
    }
    Eigen::MatrixXd big(14, 9);
    for (int i = 0; i < big.size(); ++i) big.data()[i] = u(rng);
    for (bool upper : {false, true}) {
      Eigen::MatrixXd got = big, ref = big, eigen = big;
      internal::subtract_gram(Eigen::Map<Eigen::Matrix<double, 6, 6>, 0, Eigen::OuterStride<>>(
                                  got.data() + 3 + 14 * 2, Eigen::OuterStride<>(14)),
                              a, b, upper);
      for (int c = 0; c < 6; ++c) {
        for (int r = 0; r < (upper ? c + 1 : 6); ++r) {
          const double dot = a(0, r) * b(0, c) + a(1, r) * b(1, c);
          ref(3 + r, 2 + c) -= dot + a(2, r) * b(2, c);
          eigen(3 + r, 2 + c) -= a.col(r).dot(b.col(c));
        }
      }
      EXPECT_EQ(std::memcmp(got.data(), ref.data(), sizeof(double) * 14 * 9), 0)
          << "trial " << trial << (upper ? " upper" : " full");
      EXPECT_LE((got - eigen).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + eigen.cwiseAbs().maxCoeff()));
    }
  }
}

TEST(AllocationCounter, SeesNewAndEigen) {
  test::AllocationCounter counter;
  std::vector<int> v(10);
  Eigen::VectorXd x(100);
  EXPECT_EQ(counter.count(), 2);
}

}  // namespace
}  // namespace ale::optim
