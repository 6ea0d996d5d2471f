// The local BA with its robust kernel against Ceres (host only: Ceres is the reference), on
// seeded local-BA-shaped scenes (app/tools/lib/ba/synthetic_problem.h: keyframes 0.15 m apart,
// the first two fixed, points at 2-8 m, 1 px noise x 1.2^level, outliers moved 20-100 px), with the
// residual, information and Huber threshold the local mapper uses (sqrt(5.991) on the
// information-weighted residual). Both are run to the same tight tolerances, so that each stops
// at the minimum; their final costs must agree within kRelative.
//   One pass (Huber on every observation), with and without outliers, and plain least squares;
//   two passes as the local mapper runs them: the observations whose chi-square exceeds 5.991
//   after the first pass are dropped, the second pass (Huber again) runs on the rest; Ceres gets
//   the same split computed from its own first-pass result.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "app/tools/ale_ba_bench/ceres_ba.h"
#include "app/tools/lib/ba/synthetic_problem.h"
#include "core/optim/bundle_adjuster.h"
#include "tests/host/support/test_data.h"

namespace ale::optim {
namespace {

constexpr double kFunctionTolerance = 1e-10;
constexpr int kMaxIterations = 500;  // the slowest case here needs 298
constexpr double kHuber = 2.4477;  // sqrt(5.991), the local mapper's
constexpr double kChi2 = 5.991;
// Measured (the printed lines): at most 5e-10 relative where both reach the same minimum; 1e-6
// leaves room for another compiler or Eigen while still catching a wrong kernel, information or
// a lost step (each of those moves the cost by far more).
constexpr double kRelative = 1e-6;

SyntheticScene scene(std::uint64_t seed, double outlier_ratio) {
  SyntheticOptions o;
  o.keyframes = 6;
  o.fixed = 2;  // fixes the gauge, scale included (one fixed pose leaves the scale free)
  o.points = 600;
  o.views_per_point = 5;
  o.outlier_ratio = outlier_ratio;
  o.seed = seed;
  return make_synthetic_scene(o);
}

struct State {
  std::vector<geometry::SE3> T_cw;
  std::vector<geometry::Vec3> points;
};

// Our solver from `start` on the observations `use` marks, with or without Huber; the state it
// ends in goes to `end`.
BaSummary ours(const SyntheticScene& sc, const State& start, const std::vector<bool>& use, bool huber, int passes,
               State* end) {
  BundleAdjuster ba;
  ba.reset(geometry::Camera::create(sc.intrinsics).value());
  for (std::size_t i = 0; i < start.T_cw.size(); ++i) ba.add_pose(start.T_cw[i], sc.pose_fixed[i]);
  for (const geometry::Vec3& p : start.points) ba.add_point(p);
  for (std::size_t k = 0; k < sc.observations.size(); ++k) {
    if (!use[k]) continue;
    const SyntheticObservation& o = sc.observations[k];
    ba.add_observation(o.pose, o.point, o.uv_px, level_information(sc.scale_factor, o.level),
                       huber ? RobustKernel::huber(kHuber) : RobustKernel::none());
  }
  BaOptions options;
  options.passes = passes;
  options.chi2_gate = passes > 1 ? kChi2 : 0.0;
  options.lm.function_tolerance = kFunctionTolerance;
  options.lm.max_iterations = kMaxIterations;
  const BaSummary s = ba.solve(options);
  end->T_cw.resize(start.T_cw.size());
  end->points.resize(start.points.size());
  for (int i = 0; i < ba.num_poses(); ++i) end->T_cw[static_cast<std::size_t>(i)] = ba.pose(i);
  for (int j = 0; j < ba.num_points(); ++j) end->points[static_cast<std::size_t>(j)] = ba.point(j);
  return s;
}

ceres_ref::Result ceres(const SyntheticScene& sc, const State& start, const std::vector<bool>& use, bool huber,
                        State* end) {
  std::vector<ceres_ref::Observation> obs;
  for (std::size_t k = 0; k < sc.observations.size(); ++k) {
    if (!use[k]) continue;
    const SyntheticObservation& o = sc.observations[k];
    obs.push_back({o.pose, o.point, o.uv_px, level_information(sc.scale_factor, o.level)});
  }
  ceres_ref::Options options;
  options.function_tolerance = kFunctionTolerance;
  options.max_iterations = kMaxIterations;
  options.huber_delta = huber ? kHuber : 0.0;
  *end = start;
  return ceres_ref::solve_ba(sc.intrinsics, &end->T_cw, sc.pose_fixed, &end->points, obs, options);
}

State initial(const SyntheticScene& sc) { return {sc.T_cw_init, sc.points_init}; }

void expect_same_cost(double ours_cost, double ceres_cost, const char* what, std::uint64_t seed) {
  EXPECT_NEAR(ours_cost, ceres_cost, kRelative * ceres_cost) << what << " seed " << seed;
  std::printf("%s seed %llu: ours %.10g ceres %.10g relative %.2e\n", what, static_cast<unsigned long long>(seed),
              ours_cost, ceres_cost, (ours_cost - ceres_cost) / ceres_cost);
}

// With outliers the robust cost has several minima, and the two solvers, whose steps differ in
// their last bits, can end in different ones: measured on seed 3 with 10 % outliers, ours at
// 25463.07 after 186 iterations, Ceres at 25626.24 after 178 (0.64 % higher). There the test only
// requires ours to be no worse; everywhere else the same cost.
struct Case {
  std::uint64_t seed;
  double outliers;
  bool same_minimum;
};

// Under the sanitizers (ALE_TEST_REDUCED=1) the tests run seed 1 only: every kind of case, a
// third of the work (the full form took 97 s there on the loaded 2-core machine).
std::uint64_t last_seed(std::uint64_t full) {
  if (!test::reduced_run()) return full;
  std::printf("reduced form (ALE_TEST_REDUCED=1): seed 1 only\n");
  return 1;
}

TEST(LocalBaAgainstCeres, OnePassWithHuberReachesTheSameCost) {
  const Case cases[] = {{1, 0.0, true},  {2, 0.0, true},  {3, 0.0, true},  {1, 0.05, true}, {2, 0.05, true},
                        {3, 0.05, true}, {1, 0.10, true}, {2, 0.10, true}, {3, 0.10, false}};
  const std::uint64_t last = last_seed(3);
  for (const Case& k : cases) {
    if (k.seed > last) continue;
    const SyntheticScene sc = scene(k.seed, k.outliers);
    const std::vector<bool> all(sc.observations.size(), true);
    State a, b;
    const BaSummary s = ours(sc, initial(sc), all, true, 1, &a);
    const ceres_ref::Result c = ceres(sc, initial(sc), all, true, &b);
    ASSERT_TRUE(s.status.ok()) << s.status.to_string();
    ASSERT_TRUE(c.usable && c.converged) << "seed " << k.seed << ": " << c.iterations << " iterations";
    EXPECT_NEAR(s.initial_cost, c.initial_cost, 1e-9 * c.initial_cost) << "the same robust cost at the start";
    EXPECT_LT(s.final_cost, s.initial_cost);
    char what[128];
    std::snprintf(what, sizeof what, "huber, %.0f %% outliers (ours %d it, ceres %d it)", 100.0 * k.outliers,
                  s.iterations, c.iterations);
    if (k.same_minimum) {
      expect_same_cost(s.final_cost, c.final_cost, what, k.seed);
    } else {
      EXPECT_LT(s.final_cost, c.final_cost * (1.0 + kRelative)) << what << " seed " << k.seed;
      std::printf("%s seed %llu: ours %.10g ceres %.10g (another minimum)\n", what,
                  static_cast<unsigned long long>(k.seed), s.final_cost, c.final_cost);
    }
  }
}

TEST(LocalBaAgainstCeres, LeastSquaresWithoutOutliersReachesTheSameCost) {
  const std::uint64_t last = last_seed(2);
  for (std::uint64_t seed = 1; seed <= last; ++seed) {
    const SyntheticScene sc = scene(seed, 0.0);
    const std::vector<bool> all(sc.observations.size(), true);
    State a, b;
    const BaSummary s = ours(sc, initial(sc), all, false, 1, &a);
    const ceres_ref::Result c = ceres(sc, initial(sc), all, false, &b);
    ASSERT_TRUE(s.status.ok()) << s.status.to_string();
    ASSERT_TRUE(c.usable && c.converged);
    expect_same_cost(s.final_cost, c.final_cost, "least squares", seed);
  }
}

// chi-square of each observation at `state`; behind the camera counts as an outlier.
std::vector<bool> inliers_at(const SyntheticScene& sc, const State& state) {
  const geometry::Camera cam = geometry::Camera::create(sc.intrinsics).value();
  std::vector<bool> in(sc.observations.size(), false);
  for (std::size_t k = 0; k < sc.observations.size(); ++k) {
    const SyntheticObservation& o = sc.observations[k];
    geometry::Vec2 uv;
    if (!cam.project(state.T_cw[static_cast<std::size_t>(o.pose)] * state.points[static_cast<std::size_t>(o.point)], &uv))
      continue;
    in[k] = level_information(sc.scale_factor, o.level) * (uv - o.uv_px).squaredNorm() <= kChi2;
  }
  return in;
}

TEST(LocalBaAgainstCeres, TwoPassesWithOutlierRemovalReachTheSameCost) {
  const std::uint64_t last = last_seed(3);
  for (std::uint64_t seed = 1; seed <= last; ++seed) {
    const SyntheticScene sc = scene(seed, 0.05);
    const std::vector<bool> all(sc.observations.size(), true);
    State a, b1, b2;
    const BaSummary s = ours(sc, initial(sc), all, true, 2, &a);
    ASSERT_TRUE(s.status.ok()) << s.status.to_string();
    EXPECT_EQ(s.passes, 2);
    const ceres_ref::Result first = ceres(sc, initial(sc), all, true, &b1);
    ASSERT_TRUE(first.usable && first.converged);
    const std::vector<bool> in = inliers_at(sc, b1);
    int outliers = 0, true_outliers_caught = 0, true_outliers = 0;
    for (std::size_t k = 0; k < in.size(); ++k) {
      outliers += !in[k];
      true_outliers += sc.observations[k].outlier;
      true_outliers_caught += !in[k] && sc.observations[k].outlier;
    }
    EXPECT_GT(outliers, 0);
    EXPECT_GE(true_outliers_caught, 0.9 * true_outliers) << outliers << " removed";
    const ceres_ref::Result second = ceres(sc, b1, in, true, &b2);
    ASSERT_TRUE(second.usable && second.converged) << second.iterations << " iterations, cost " << second.final_cost
                                                   << ", ours " << s.final_cost << " in " << s.iterations;
    expect_same_cost(s.final_cost, second.final_cost, "two passes", seed);
  }
}

}  // namespace
}  // namespace ale::optim
