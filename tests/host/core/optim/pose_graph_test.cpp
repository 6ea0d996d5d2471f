// Pose-graph optimisation: Jacobians against differences, synthetic loops (SE3 and Sim3 with
// scale drift), gauge and fixed vertices, bad inputs, buffer reuse; on the host, the same
// problems in Ceres reach the same final cost.
#include "core/optim/pose_graph.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "core/base/rng.h"
#include "tests/host/core/optim/alloc_counter.h"
#include "tests/host/core/optim/pose_graph_scenes.h"
#if ALE_HAVE_CERES
#include "tests/host/core/optim/pose_graph_ceres.h"
#endif

namespace ale::optim {
namespace {

using geometry::Sim3;
using geometry::SE3;
using test::CircleSceneSpec;
using test::PoseGraphScene;

template <class Group>
typename PoseGraphGroup<Group>::Tangent random_tangent(SplitMix64& rng, double translation, double rotation,
                                                        double scale) {
  typename PoseGraphGroup<Group>::Tangent x;
  auto uniform = [&]() { return 2.0 * rng.uniform_double() - 1.0; };
  for (int r = 0; r < 3; ++r) x[r] = translation * uniform();
  // A rotation vector of norm up to `rotation` in a random direction.
  geometry::Vec3 axis(uniform(), uniform(), uniform());
  axis.normalize();
  x.template segment<3>(3) = rotation * rng.uniform_double() * axis;
  for (int r = 6; r < PoseGraphGroup<Group>::kDim; ++r) x[r] = scale * uniform();
  return x;
}

// Analytic Jacobians of e = log(T_ij T_jw T_iw^-1) against central differences of the left
// perturbations, at random poses, for residual rotations up to residual_rotation (rad).
template <class Group>
void check_residual_jacobians(std::uint64_t seed, double residual_rotation) {
  constexpr int kDim = PoseGraphGroup<Group>::kDim;
  using Tangent = typename PoseGraphGroup<Group>::Tangent;
  using Matrix = typename PoseGraphGroup<Group>::Matrix;
  SplitMix64 rng(seed);
  for (int trial = 0; trial < 50; ++trial) {
    const Group T_iw = Group::exp(random_tangent<Group>(rng, 3.0, 3.0, 0.7));
    const Group T_jw = Group::exp(random_tangent<Group>(rng, 3.0, 3.0, 0.7));
    // Chosen so that the residual is exactly e_true (|phi| < pi keeps log unambiguous).
    const Tangent e_true = random_tangent<Group>(rng, 1.0, residual_rotation, 0.3 * residual_rotation);
    const Group T_ij = Group::exp(e_true) * T_iw * T_jw.inverse();
    Matrix d_e_d_i;
    Matrix d_e_d_j;
    const Tangent e = pose_graph_residual<Group>(T_ij, T_iw, T_jw, &d_e_d_i, &d_e_d_j);
    ASSERT_LT((e - e_true).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial;
    Matrix numeric_i;
    Matrix numeric_j;
    const double h = 1e-6;
    for (int k = 0; k < kDim; ++k) {
      const Tangent d = h * Tangent::Unit(k);
      numeric_i.col(k) = (pose_graph_residual<Group>(T_ij, Group::exp(d) * T_iw, T_jw, nullptr, nullptr) -
                          pose_graph_residual<Group>(T_ij, Group::exp(-d) * T_iw, T_jw, nullptr, nullptr)) /
                         (2.0 * h);
      numeric_j.col(k) = (pose_graph_residual<Group>(T_ij, T_iw, Group::exp(d) * T_jw, nullptr, nullptr) -
                          pose_graph_residual<Group>(T_ij, T_iw, Group::exp(-d) * T_jw, nullptr, nullptr)) /
                         (2.0 * h);
    }
    const double tol_i = 1e-6 * std::max(1.0, d_e_d_i.cwiseAbs().maxCoeff());
    const double tol_j = 1e-6 * std::max(1.0, d_e_d_j.cwiseAbs().maxCoeff());
    EXPECT_LT((d_e_d_i - numeric_i).cwiseAbs().maxCoeff(), tol_i) << "trial " << trial << "\n" << d_e_d_i << "\n\n"
                                                                 << numeric_i;
    EXPECT_LT((d_e_d_j - numeric_j).cwiseAbs().maxCoeff(), tol_j) << "trial " << trial << "\n" << d_e_d_j << "\n\n"
                                                                 << numeric_j;
  }
}

TEST(PoseGraphJacobians, Se3SmallResiduals) { check_residual_jacobians<SE3>(11, 0.05); }
TEST(PoseGraphJacobians, Se3LargeResiduals) { check_residual_jacobians<SE3>(12, 2.8); }
TEST(PoseGraphJacobians, Sim3SmallResiduals) { check_residual_jacobians<Sim3>(13, 0.05); }
TEST(PoseGraphJacobians, Sim3LargeResiduals) { check_residual_jacobians<Sim3>(14, 2.8); }

template <class Group>
struct Solved {
  std::vector<Group> poses;
  PoseGraphSummary summary;
};

template <class Group>
Solved<Group> solve_scene(const PoseGraphScene<Group>& scene, const std::vector<int>& fixed,
                          const LmOptions& options = LmOptions()) {
  Solved<Group> out{scene.initial, {}};
  PoseGraphOptimizer<Group> optimizer;
  Result<PoseGraphSummary> r = optimizer.optimize(scene.edges, fixed, options, &out.poses);
  EXPECT_TRUE(r.ok()) << r.status().to_string();
  if (r.ok()) out.summary = *r;
  return out;
}

template <class Group>
void check_circle(const CircleSceneSpec& spec) {
  const PoseGraphScene<Group> scene = test::make_circle_scene<Group>(spec);
  const Solved<Group> solved = solve_scene(scene, {0}, test::tight_lm_options());
  const double truth_cost = PoseGraphOptimizer<Group>::cost(scene.edges, scene.truth);
  const double chain_rms = test::position_rms_m(scene.initial, scene.truth);
  const double solved_rms = test::position_rms_m(solved.poses, scene.truth);
  // Degrees of freedom of the residual at the minimum: (edges - free vertices) * kDim.
  const int dof = (static_cast<int>(scene.edges.size()) - (spec.poses - 1)) * PoseGraphGroup<Group>::kDim;
  std::printf("circle %d poses, %zu edges: cost %.3f -> %.3f (truth %.3f, dof/2 %.1f) in %d iterations; "
              "position rms %.4f m (chain) -> %.4f m\n",
              spec.poses, scene.edges.size(), solved.summary.initial_cost, solved.summary.final_cost, truth_cost,
              0.5 * dof, solved.summary.iterations, chain_rms, solved_rms);
  EXPECT_LT(solved.summary.final_cost, solved.summary.initial_cost);
  // The minimum is no worse than the truth, which is one admissible point of the same gauge.
  EXPECT_LE(solved.summary.final_cost, truth_cost);
  EXPECT_NEAR(solved.summary.final_cost, PoseGraphOptimizer<Group>::cost(scene.edges, solved.poses), 1e-9);
  // A chi-square with dof degrees of freedom: mean dof, sd sqrt(2 dof); 2 F within 4 sd.
  EXPECT_NEAR(2.0 * solved.summary.final_cost, dof, 4.0 * std::sqrt(2.0 * dof));
  EXPECT_LT(solved_rms, 0.5 * chain_rms);
  EXPECT_TRUE(solved.poses[0].translation() == scene.initial[0].translation());
}

TEST(PoseGraphCircle, Se3LoopClosuresBeatOdometry) { check_circle<SE3>(test::circle_spec(120, 2, 6, 21)); }
TEST(PoseGraphCircle, Sim3LoopClosuresBeatOdometry) { check_circle<Sim3>(test::circle_spec(120, 2, 6, 22)); }

TEST(PoseGraphCircle, Sim3LoopEdgeCorrectsScaleDrift) {
  CircleSceneSpec spec = test::circle_spec(60, 1, 5, 23);
  spec.scale_drift_per_step = 0.01;  // the last keyframe's local scale is 1.8
  spec.rotation_sigma_rad = 0.002;
  spec.translation_sigma_m = 0.005;
  const PoseGraphScene<Sim3> scene = test::make_drift_scene(spec);
  const Solved<Sim3> solved = solve_scene(scene, {0}, test::tight_lm_options());
  const double chain_rms = test::position_rms_m(scene.initial, scene.truth);
  const double solved_rms = test::position_rms_m(solved.poses, scene.truth);
  const double last_scale = solved.poses.back().scale();
  std::printf("scale drift %d poses: cost %.3f -> %.3f in %d iterations; position rms %.4f m (chain) -> %.4f m; "
              "scale of the last vertex %.4f (its local scale %.4f)\n",
              spec.poses, solved.summary.initial_cost, solved.summary.final_cost, solved.summary.iterations, chain_rms,
              solved_rms, last_scale, std::pow(1.0 + spec.scale_drift_per_step, spec.poses - 1));
  EXPECT_LT(solved.summary.final_cost, 1e-3 * solved.summary.initial_cost);
  EXPECT_LT(solved_rms, 0.1 * chain_rms);
  // The loop edge's relative scale is absorbed along the chain: the last vertex carries most
  // of the local scale 1.8 the loop measured.
  EXPECT_NEAR(last_scale, std::pow(1.0 + spec.scale_drift_per_step, spec.poses - 1), 0.1);
}

TEST(PoseGraphFixed, FixedVerticesAreUnchangedAndOthersMove) {
  CircleSceneSpec spec;
  spec.seed = 31;
  const PoseGraphScene<SE3> scene = test::make_circle_scene<SE3>(spec);
  // 0 and 1 share an edge, which then only adds cost.
  const std::vector<int> fixed = {64, 0, 37, 1};
  const Solved<SE3> solved = solve_scene(scene, fixed);
  for (int v = 0; v < spec.poses; ++v) {
    const bool is_fixed = v == 0 || v == 1 || v == 37 || v == 64;
    const bool same = solved.poses[v].translation() == scene.initial[v].translation() &&
                      solved.poses[v].so3().quaternion().coeffs() == scene.initial[v].so3().quaternion().coeffs();
    EXPECT_EQ(same, is_fixed) << "vertex " << v;
  }
}

TEST(PoseGraphEdges, DuplicateEdgeEqualsDoubledInformation) {
  // Two edges on the same vertex pair accumulate into the same Hessian blocks; the cost equals
  // one edge with twice the information.
  PoseGraphScene<Sim3> doubled = test::make_circle_scene<Sim3>(test::circle_spec(60, 2, 5, 33));
  PoseGraphScene<Sim3> duplicated = doubled;
  for (std::size_t k : {std::size_t{5}, doubled.edges.size() - 2}) {
    duplicated.edges.push_back(duplicated.edges[k]);
    doubled.edges[k].information *= 2.0;
  }
  const Solved<Sim3> a = solve_scene(doubled, {0}, test::tight_lm_options());
  const Solved<Sim3> b = solve_scene(duplicated, {0}, test::tight_lm_options());
  EXPECT_NEAR(a.summary.final_cost, b.summary.final_cost, 1e-9 * a.summary.final_cost);
  double largest = 0.0;
  for (std::size_t v = 0; v < a.poses.size(); ++v) {
    largest = std::max(largest, (a.poses[v].translation() - b.poses[v].translation()).cwiseAbs().maxCoeff());
  }
  // Both stop at a relative cost change of 1e-12: with F ~ 50 and a stiffest curvature of
  // 1 / (0.02 m)^2, that leaves ~sqrt(1e-12 F / 2500) ~ 1e-7 m of position between them.
  EXPECT_LT(largest, 1e-6);
}

// Three of the ten loop edges 1 m and 0.3 rad off (place recognition mistakes, 50 and 30
// sigma), optionally with a Huber kernel at the 95 % chi-square gate of 6 dof on every edge.
PoseGraphScene<SE3> wrong_loop_scene(bool corrupt, bool huber) {
  const CircleSceneSpec spec = test::circle_spec(100, 2, 5, 41);
  PoseGraphScene<SE3> scene = test::make_circle_scene<SE3>(spec);
  const int odometry = spec.poses - 1;
  if (corrupt) {
    for (int k : {odometry + 1, odometry + 4, odometry + 7}) {
      scene.edges[k].T_ij = SE3::exp((geometry::Vec6() << 1.0, 0.0, 0.0, 0.0, 0.3, 0.0).finished()) * scene.edges[k].T_ij;
    }
  }
  if (huber) {
    for (PoseGraphEdge<SE3>& edge : scene.edges) edge.kernel = RobustKernel::huber(std::sqrt(12.59));
  }
  return scene;
}

TEST(PoseGraphRobust, HuberResistsWrongLoops) {
  const PoseGraphScene<SE3> clean = wrong_loop_scene(false, false);
  const double clean_rms = test::position_rms_m(solve_scene(clean, {0}).poses, clean.truth);
  const PoseGraphScene<SE3> wrong = wrong_loop_scene(true, false);
  const double plain_rms = test::position_rms_m(solve_scene(wrong, {0}).poses, wrong.truth);
  const PoseGraphScene<SE3> robust = wrong_loop_scene(true, true);
  const double robust_rms = test::position_rms_m(solve_scene(robust, {0}).poses, robust.truth);
  std::printf("wrong loops: position rms %.4f m without them, %.4f m with them and no kernel, %.4f m with Huber\n",
              clean_rms, plain_rms, robust_rms);
  // Huber bounds each wrong edge's pull to its threshold instead of its 50 sigma.
  EXPECT_GT(plain_rms, 1.3 * clean_rms);
  EXPECT_LT(robust_rms, 1.1 * clean_rms);
}

// Bad inputs: a status, and the poses as they were.
class PoseGraphBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    scene = test::make_circle_scene<SE3>(test::circle_spec(20, 1, 5, 51));
    poses = scene.initial;
  }
  Status run(const std::vector<int>& fixed, const LmOptions& options = LmOptions()) {
    PoseGraphOptimizer<SE3> optimizer;
    const std::vector<SE3> before = poses;
    Result<PoseGraphSummary> r = optimizer.optimize(scene.edges, fixed, options, &poses);
    for (std::size_t v = 0; v < poses.size() && v < before.size(); ++v) {
      EXPECT_TRUE(poses[v].translation() == before[v].translation() ||
                  (poses[v].translation().hasNaN() && before[v].translation().hasNaN()))
          << "vertex " << v << " changed on failure";
    }
    return r.ok() ? Status::ok_status() : r.status();
  }
  PoseGraphScene<SE3> scene;
  std::vector<SE3> poses;
};

TEST_F(PoseGraphBadInput, NoEdges) {
  scene.edges.clear();
  const Status s = run({0});
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("no edges"), std::string::npos) << s.to_string();
}

TEST_F(PoseGraphBadInput, NoFixedVertex) {
  const Status s = run({});
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("gauge"), std::string::npos) << s.to_string();
}

TEST_F(PoseGraphBadInput, EveryVertexFixed) {
  std::vector<int> all(poses.size());
  for (std::size_t v = 0; v < all.size(); ++v) all[v] = static_cast<int>(v);
  EXPECT_EQ(run(all).code(), StatusCode::kInvalidArgument);
}

TEST_F(PoseGraphBadInput, FixedVertexOutOfRange) { EXPECT_EQ(run({20}).code(), StatusCode::kInvalidArgument); }

TEST_F(PoseGraphBadInput, EdgeVertexOutOfRangeOrSelf) {
  scene.edges[3].j = 25;
  EXPECT_EQ(run({0}).code(), StatusCode::kInvalidArgument);
  scene.edges[3].j = scene.edges[3].i;
  const Status s = run({0});
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("itself"), std::string::npos) << s.to_string();
}

TEST_F(PoseGraphBadInput, DisconnectedVertex) {
  poses.push_back(SE3());  // no edge reaches it
  const Status s = run({0});
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("vertex 20 is not connected"), std::string::npos) << s.to_string();
}

TEST_F(PoseGraphBadInput, ComponentWithoutFixedVertex) {
  // Cut the chain between 9 and 10: 10..19 float.
  scene.edges.erase(scene.edges.begin() + 9);
  EXPECT_EQ(run({0}).code(), StatusCode::kInvalidArgument);
  // Fixing one vertex of the second part makes it solvable.
  EXPECT_TRUE(run({0, 15}).ok());
}

TEST_F(PoseGraphBadInput, NonFinitePoseOrMeasurement) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  poses[5] = SE3(poses[5].so3(), geometry::Vec3(nan, 0.0, 0.0));
  EXPECT_EQ(run({0}).code(), StatusCode::kInvalidArgument);
  poses = scene.initial;
  scene.edges[2].T_ij = SE3(scene.edges[2].T_ij.so3(), geometry::Vec3(0.0, std::numeric_limits<double>::infinity(), 0.0));
  EXPECT_EQ(run({0}).code(), StatusCode::kInvalidArgument);
}

TEST_F(PoseGraphBadInput, InformationNotPositiveDefinite) {
  scene.edges[4].information.setZero();
  EXPECT_EQ(run({0}).code(), StatusCode::kInvalidArgument);
  scene.edges[4].information.setIdentity();
  scene.edges[4].information(0, 1) = 0.5;  // not symmetric
  EXPECT_EQ(run({0}).code(), StatusCode::kInvalidArgument);
  scene.edges[4].information.setIdentity();
  scene.edges[4].information(2, 2) = -1.0;
  EXPECT_EQ(run({0}).code(), StatusCode::kInvalidArgument);
}

TEST_F(PoseGraphBadInput, BadKernel) {
  scene.edges[1].kernel = RobustKernel::huber(0.0);
  EXPECT_EQ(run({0}).code(), StatusCode::kInvalidArgument);
}

TEST_F(PoseGraphBadInput, NotConvergedLeavesPoses) {
  LmOptions o = test::tight_lm_options();
  o.max_iterations = 1;
  // The chain fits the odometry edges exactly: move a pose so that one step cannot converge.
  poses[7] = SE3::exp((geometry::Vec6() << 0.5, 0.0, 0.0, 0.0, 0.2, 0.0).finished()) * poses[7];
  const Status s = run({0}, o);
  EXPECT_EQ(s.code(), StatusCode::kNotConverged) << s.to_string();
}

TEST_F(PoseGraphBadInput, NullPoses) {
  PoseGraphOptimizer<SE3> optimizer;
  Result<PoseGraphSummary> r = optimizer.optimize(scene.edges, {0}, LmOptions(), nullptr);
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
}

TEST(PoseGraphReuse, SecondSolveOfSameStructureIsIdenticalAndAllocatesNothing) {
  CircleSceneSpec spec;
  spec.seed = 61;
  const PoseGraphScene<Sim3> scene = test::make_circle_scene<Sim3>(spec);
  const std::vector<int> fixed = {0};
  PoseGraphOptimizer<Sim3> optimizer;
  std::vector<Sim3> first = scene.initial;
  const LmOptions options = test::tight_lm_options();
  long first_allocations = 0;
  {
    // The first solve builds the structure: the counter must see those allocations.
    const ale::test::AllocationCounter counter;
    ASSERT_TRUE(optimizer.optimize(scene.edges, fixed, options, &first).ok());
    first_allocations = counter.count();
  }
  EXPECT_GT(first_allocations, 10) << "the allocation counter does not count";
  std::printf("first solve: %ld allocations\n", first_allocations);
  std::vector<Sim3> second = scene.initial;
  long second_allocations = 0;
  Result<PoseGraphSummary> r = Status(StatusCode::kInternal, "not run");
  {
    const ale::test::AllocationCounter counter;
    r = optimizer.optimize(scene.edges, fixed, options, &second);
    second_allocations = counter.count();
  }
  EXPECT_EQ(second_allocations, 0) << "allocations in a solve of an already seen structure";
  ASSERT_TRUE(r.ok());
  EXPECT_GT(r->iterations, 2);
  for (std::size_t v = 0; v < first.size(); ++v) {
    EXPECT_TRUE(first[v].translation() == second[v].translation()) << v;
    EXPECT_EQ(first[v].scale(), second[v].scale()) << v;
  }
  // A changed fixed set is a new structure, solved correctly by the same object.
  std::vector<Sim3> third = scene.initial;
  ASSERT_TRUE(optimizer.optimize(scene.edges, {0, 50}, options, &third).ok());
  EXPECT_TRUE(third[50].translation() == scene.initial[50].translation());
}

#if ALE_HAVE_CERES

template <class Group>
void check_plus_jacobian(std::uint64_t seed) {
  using Manifold = test::LeftPerturbationManifold<Group>;
  constexpr int kDim = Manifold::kDim;
  constexpr int kAmbient = Manifold::kAmbient;
  SplitMix64 rng(seed);
  const Manifold manifold(test::CeresJacobians::kNumeric);
  for (int trial = 0; trial < 20; ++trial) {
    double x[kAmbient];
    test::Ambient<Group>::to(Group::exp(random_tangent<Group>(rng, 3.0, 3.0, 0.7)), x);
    Eigen::Matrix<double, kAmbient, kDim, Eigen::RowMajor> analytic;
    ASSERT_TRUE(manifold.PlusJacobian(x, analytic.data()));
    Eigen::Matrix<double, kAmbient, kDim> numeric;
    const double h = 1e-6;
    for (int k = 0; k < kDim; ++k) {
      double plus[kAmbient], minus[kAmbient], d[kDim] = {};
      d[k] = h;
      manifold.Plus(x, d, plus);
      d[k] = -h;
      manifold.Plus(x, d, minus);
      for (int r = 0; r < kAmbient; ++r) numeric(r, k) = (plus[r] - minus[r]) / (2.0 * h);
    }
    // (The quaternion's sign is continuous here: exp(+-h) * T stays near T.)
    EXPECT_LT((analytic - numeric).cwiseAbs().maxCoeff(), 1e-8) << trial;
  }
}

TEST(PoseGraphCeres, ManifoldPlusJacobian) {
  check_plus_jacobian<SE3>(71);
  check_plus_jacobian<Sim3>(72);
}

template <class Group>
void compare_with_ceres(const PoseGraphScene<Group>& scene, const std::vector<int>& fixed, const char* name) {
  test::CeresPoseGraph<Group> ceres_graph(scene.edges, fixed, scene.initial, test::CeresJacobians::kNumeric);
  const double ours_initial = PoseGraphOptimizer<Group>::cost(scene.edges, scene.initial);
  EXPECT_NEAR(ceres_graph.cost(), ours_initial, 1e-12 * ours_initial) << "not the same cost function";
  const ceres::Solver::Summary ceres_summary = ceres_graph.solve(test::CeresPoseGraph<Group>::options());
  const Solved<Group> ours = solve_scene(scene, fixed, test::tight_lm_options());
  const double relative = std::abs(ours.summary.final_cost - ceres_summary.final_cost) / ceres_summary.final_cost;
  std::printf("%s: initial cost %.6f; final ours %.12g (%d steps), Ceres %.12g (%d steps, %s); "
              "relative difference %.2e\n",
              name, ours_initial, ours.summary.final_cost, ours.summary.iterations, ceres_summary.final_cost,
              static_cast<int>(ceres_summary.iterations.size()) - 1, ceres::TerminationTypeToString(ceres_summary.termination_type),
              relative);
  EXPECT_EQ(ceres_summary.termination_type, ceres::CONVERGENCE) << ceres_summary.FullReport();
  EXPECT_LT(relative, 1e-6);
  double max_translation_difference = 0.0;
  for (std::size_t v = 0; v < scene.initial.size(); ++v) {
    max_translation_difference = std::max(
        max_translation_difference,
        (ceres_graph.pose(static_cast<int>(v)).translation() - ours.poses[v].translation()).cwiseAbs().maxCoeff());
  }
  std::printf("%s: largest translation difference ours vs Ceres %.2e\n", name, max_translation_difference);
  EXPECT_LT(max_translation_difference, 1e-5);
}

TEST(PoseGraphCeres, Se3CircleSameFinalCost) {
  compare_with_ceres(test::make_circle_scene<SE3>(test::circle_spec(150, 3, 5, 81)), {0}, "SE3 circle");
}

TEST(PoseGraphCeres, Se3WrongLoopsHuberSameFinalCost) {
  // The wrong loop edges stay on Huber's linear part at the minimum.
  compare_with_ceres(wrong_loop_scene(true, true), {0}, "SE3 wrong loops, Huber");
}

TEST(PoseGraphCeres, Sim3CircleSameFinalCost) {
  compare_with_ceres(test::make_circle_scene<Sim3>(test::circle_spec(120, 2, 5, 83)), {0}, "Sim3 circle");
}

TEST(PoseGraphCeres, Sim3ScaleDriftSameFinalCost) {
  CircleSceneSpec spec = test::circle_spec(60, 1, 5, 84);
  spec.scale_drift_per_step = 0.01;
  compare_with_ceres(test::make_drift_scene(spec), {0}, "Sim3 scale drift");
}

#endif  // ALE_HAVE_CERES

}  // namespace
}  // namespace ale::optim
