// Bundle adjustment and motion-only optimisation, ours vs Ceres (one thread, same residual, same
// start, same stopping rules: Ceres' defaults, function tolerance 1e-6, at most 50 iterations).
//   ALE_DATA_DIR=../shared/data build/host/bin/ale_optim_bench
// - Libmv/<problem>: the three libmv problems from perturbation seed 1 (0.3 deg, 1 %); ours
//   eliminates the side that leaves the smaller reduced system (here the cameras); Ceres
//   SPARSE_SCHUR and DENSE_SCHUR.
// - LocalBA: 10 keyframes (2 fixed), 3000 points, 15000 observations, 5 % outliers, Huber
//   sqrt(5.991), 10 iterations at most; Ceres DENSE_SCHUR and SPARSE_SCHUR.
// - MotionOnly: one frame, 300 matches, 20 % outliers, ORB-SLAM's 4 rounds of 10 iterations;
//   Ceres DENSE_QR does each round's optimisation.
// The counter "final_cost" (and "iterations") shows that both solved the same problem.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "app/tools/ale_ba_bench/ceres_ba.h"
#include "core/optim/bundle_adjuster.h"
#include "app/tools/lib/ba/libmv_problem.h"
#include "core/optim/motion_only.h"
#include "app/tools/lib/ba/synthetic_problem.h"

namespace {

using namespace ale;
using namespace ale::optim;

std::string data_dir() {
  const char* d = std::getenv("ALE_DATA_DIR");
  return d ? d : "../shared/data";
}

const LibmvProblem* libmv_start(int index) {
  static std::vector<LibmvProblem> problems;
  static bool loaded = false;
  if (!loaded) {
    loaded = true;
    for (int i = 1; i <= 3; ++i) {
      Result<LibmvProblem> p = load_libmv_problem(data_dir() + "/ba_libmv/problem_0" + std::to_string(i) + ".bin");
      if (!p.ok()) {
        std::fprintf(stderr, "%s (set ALE_DATA_DIR)\n", p.status().to_string().c_str());
        problems.clear();
        return nullptr;
      }
      perturb_libmv_problem(1, 0.3, 0.01, &p.value());
      problems.push_back(std::move(p.value()));
    }
  }
  return index < static_cast<int>(problems.size()) ? &problems[index] : nullptr;
}

void BM_LibmvOurs(benchmark::State& state) {
  const LibmvProblem* start = libmv_start(static_cast<int>(state.range(0)));
  if (!start) {
    state.SkipWithError("libmv data missing");
    return;
  }
  const geometry::Camera cam = geometry::Camera::create(start->intrinsics).value();
  BundleAdjuster ba;
  BaOptions options;
  options.elimination = SchurElimination::kAuto;
  options.chi2_gate = 0.0;
  BaSummary s;
  for (auto _ : state) {
    ba.reset(cam);
    for (const geometry::SE3& T : start->T_cw) ba.add_pose(T, false);
    for (const geometry::Vec3& p : start->points_w) ba.add_point(p);
    for (const LibmvObservation& o : start->observations) ba.add_observation(o.camera, o.point, o.uv_px);
    s = ba.solve(options);
  }
  state.counters["final_cost"] = s.final_cost;
  state.counters["iterations"] = s.iterations;
}

void libmv_ceres(benchmark::State& state, ceres_ref::Solver solver) {
  const LibmvProblem* start = libmv_start(static_cast<int>(state.range(0)));
  if (!start) {
    state.SkipWithError("libmv data missing");
    return;
  }
  ceres_ref::Options o;
  o.solver = solver;
  ceres_ref::Result r;
  for (auto _ : state) {
    LibmvProblem p = *start;
    r = ceres_ref::solve_libmv(&p, o);
  }
  state.counters["final_cost"] = r.final_cost;
  state.counters["iterations"] = r.iterations;
}
void BM_LibmvCeresSparseSchur(benchmark::State& s) { libmv_ceres(s, ceres_ref::Solver::kSparseSchur); }
void BM_LibmvCeresDenseSchur(benchmark::State& s) { libmv_ceres(s, ceres_ref::Solver::kDenseSchur); }

const SyntheticScene& local_ba_scene() {
  static const SyntheticScene scene = make_synthetic_scene({});
  return scene;
}
constexpr int kLocalBaIterations = 10;

void BM_LocalBaOurs(benchmark::State& state) {
  const SyntheticScene& sc = local_ba_scene();
  const geometry::Camera cam = geometry::Camera::create(sc.intrinsics).value();
  BundleAdjuster ba;
  BaOptions options;
  options.lm.max_iterations = kLocalBaIterations;
  BaSummary s;
  for (auto _ : state) {
    ba.reset(cam);
    for (std::size_t i = 0; i < sc.T_cw_init.size(); ++i) ba.add_pose(sc.T_cw_init[i], sc.pose_fixed[i]);
    for (const geometry::Vec3& p : sc.points_init) ba.add_point(p);
    for (const SyntheticObservation& o : sc.observations) {
      ba.add_observation(o.pose, o.point, o.uv_px, level_information(sc.scale_factor, o.level),
                         RobustKernel::huber(std::sqrt(5.991)));
    }
    s = ba.solve(options);
  }
  state.counters["final_cost"] = s.final_cost;
  state.counters["iterations"] = s.iterations;
}

void local_ba_ceres(benchmark::State& state, ceres_ref::Solver solver) {
  const SyntheticScene& sc = local_ba_scene();
  std::vector<ceres_ref::Observation> obs;
  for (const SyntheticObservation& o : sc.observations) {
    obs.push_back({o.pose, o.point, o.uv_px, level_information(sc.scale_factor, o.level)});
  }
  ceres_ref::Options o;
  o.solver = solver;
  o.max_iterations = kLocalBaIterations;
  o.huber_delta = std::sqrt(5.991);
  ceres_ref::Result r;
  for (auto _ : state) {
    std::vector<geometry::SE3> poses = sc.T_cw_init;
    std::vector<geometry::Vec3> points = sc.points_init;
    r = ceres_ref::solve_ba(sc.intrinsics, &poses, sc.pose_fixed, &points, obs, o);
  }
  state.counters["final_cost"] = r.final_cost;
  state.counters["iterations"] = r.iterations;
}
void BM_LocalBaCeresDenseSchur(benchmark::State& s) { local_ba_ceres(s, ceres_ref::Solver::kDenseSchur); }
void BM_LocalBaCeresSparseSchur(benchmark::State& s) { local_ba_ceres(s, ceres_ref::Solver::kSparseSchur); }

struct PoseCase {
  SyntheticPoseScene scene = make_synthetic_pose_scene(300, 0.2, 1);
  std::vector<PoseObservation> obs;
  PoseCase() {
    for (std::size_t k = 0; k < scene.points_w.size(); ++k) obs.push_back({scene.points_w[k], scene.uv_px[k], scene.levels[k]});
  }
};
const PoseCase& pose_case() {
  static const PoseCase c;
  return c;
}

void BM_MotionOnlyOurs(benchmark::State& state) {
  const PoseCase& c = pose_case();
  const geometry::Camera cam = geometry::Camera::create(c.scene.intrinsics).value();
  std::vector<std::uint8_t> inlier(c.obs.size());
  MotionOnlyResult r;
  for (auto _ : state) {
    r = optimize_pose(cam, c.scene.T_cw_init, c.obs.data(), static_cast<int>(c.obs.size()), {}, inlier.data());
  }
  state.counters["inliers"] = r.inliers;
  state.counters["iterations"] = r.iterations;
}

void BM_MotionOnlyCeres(benchmark::State& state) {
  const PoseCase& c = pose_case();
  std::vector<std::uint8_t> inlier(c.obs.size());
  MotionOnlyResult r;
  for (auto _ : state) {
    r = ceres_ref::optimize_pose(c.scene.intrinsics, c.scene.T_cw_init, c.obs.data(), static_cast<int>(c.obs.size()),
                                 {}, inlier.data());
  }
  state.counters["inliers"] = r.inliers;
  state.counters["iterations"] = r.iterations;
}

}  // namespace

BENCHMARK(BM_LibmvOurs)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LibmvCeresSparseSchur)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LibmvCeresDenseSchur)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LocalBaOurs)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LocalBaCeresDenseSchur)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LocalBaCeresSparseSchur)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MotionOnlyOurs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MotionOnlyCeres)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
