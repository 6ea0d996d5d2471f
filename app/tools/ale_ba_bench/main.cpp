// ale_ba_bench: runs one bundle-adjustment problem and prints its figures.
//   ale_ba_bench --libmv FILE [--perturb SEED] [--max-iterations N] [--function-tolerance X]
//     one line: initial_cost A final_cost B iterations N time_ms T, then (host builds with
//     Ceres) the same figures of Ceres SPARSE_SCHUR on the same residual and start, and the
//     relative difference of the final costs.
//   ale_ba_bench --synthetic-local-ba [--iterations N] [--setup-only]
//     the benchmark's local-BA problem (10 keyframes, 2 fixed, 3000 points, 15000 observations,
//     5 % outliers, Huber): exactly N LM iterations (default 10); --setup-only builds the problem
//     and stops, so that an instruction count minus the setup-only count is the solver's.
//   ale_ba_bench --motion-only [--repeat N] [--setup-only]
//     one frame, 300 matches, 20 % outliers, ORB-SLAM's 4 rounds, N times (default 1).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "core/optim/bundle_adjuster.h"
#include "app/tools/lib/ba/libmv_problem.h"
#include "core/optim/motion_only.h"
#include "app/tools/lib/ba/synthetic_problem.h"
#ifdef ALE_HAVE_CERES
#include "app/tools/ale_ba_bench/ceres_ba.h"
#endif

namespace {

using namespace ale;
using namespace ale::optim;

int usage() {
  std::fprintf(stderr,
               "usage: ale_ba_bench --libmv FILE [--perturb SEED] [--max-iterations N] [--function-tolerance X]\n"
               "       ale_ba_bench --synthetic-local-ba [--iterations N] [--setup-only]\n"
               "       ale_ba_bench --motion-only [--repeat N] [--setup-only]\n");
  return 2;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

int run_libmv(const std::string& file, bool perturb, std::uint64_t seed, int max_iterations, double ftol) {
  Result<LibmvProblem> loaded = load_libmv_problem(file);
  if (!loaded.ok()) {
    std::fprintf(stderr, "ale_ba_bench: %s\n", loaded.status().to_string().c_str());
    return 1;
  }
  LibmvProblem problem = std::move(loaded.value());
  if (problem.skipped_observations > 0) {
    std::fprintf(stderr, "ale_ba_bench: %d observations name an undefined camera or point and are skipped\n",
                 problem.skipped_observations);
  }
  if (perturb) perturb_libmv_problem(seed, 0.3, 0.01, &problem);
  Result<geometry::Camera> camera = geometry::Camera::create(problem.intrinsics);
  if (!camera.ok()) {
    std::fprintf(stderr, "ale_ba_bench: %s\n", camera.status().to_string().c_str());
    return 1;
  }
  const auto t0 = std::chrono::steady_clock::now();
  BundleAdjuster ba;
  ba.reset(*camera);
  for (const geometry::SE3& T : problem.T_cw) ba.add_pose(T, false);
  for (const geometry::Vec3& p : problem.points_w) ba.add_point(p);
  for (const LibmvObservation& o : problem.observations) ba.add_observation(o.camera, o.point, o.uv_px);
  BaOptions options;
  options.elimination = SchurElimination::kAuto;
  options.chi2_gate = 0.0;
  options.lm.max_iterations = max_iterations;
  options.lm.function_tolerance = ftol;
  const BaSummary s = ba.solve(options);
  const double ms = ms_since(t0);
  std::printf("initial_cost %.10g final_cost %.10g iterations %d time_ms %.3f", s.initial_cost, s.final_cost,
              s.iterations, ms);
  int rc = s.status.ok() ? 0 : 1;
#ifdef ALE_HAVE_CERES
  ceres_ref::Options co;
  co.max_iterations = max_iterations;
  co.function_tolerance = ftol;
  const ceres_ref::Result c = ceres_ref::solve_libmv(&problem, co);
  std::printf("  ceres_initial_cost %.10g ceres_final_cost %.10g ceres_iterations %d ceres_time_ms %.3f"
              "  relative_difference %.3g",
              c.initial_cost, c.final_cost, c.iterations, c.time_ms,
              (s.final_cost - c.final_cost) / c.final_cost);
#endif
  std::printf("\n");
  if (!s.status.ok()) std::fprintf(stderr, "ale_ba_bench: %s\n", s.status.to_string().c_str());
  return rc;
}

int run_local_ba(int iterations, bool setup_only) {
  const SyntheticScene scene = make_synthetic_scene({});
  BundleAdjuster ba;
  ba.reset(geometry::Camera::create(scene.intrinsics).value());
  for (std::size_t i = 0; i < scene.T_cw_init.size(); ++i) ba.add_pose(scene.T_cw_init[i], scene.pose_fixed[i]);
  for (const geometry::Vec3& p : scene.points_init) ba.add_point(p);
  for (const SyntheticObservation& o : scene.observations) {
    ba.add_observation(o.pose, o.point, o.uv_px, level_information(scene.scale_factor, o.level),
                       RobustKernel::huber(std::sqrt(5.991)));
  }
  if (setup_only) {
    std::printf("setup_only observations %d\n", ba.num_observations());
    return 0;
  }
  BaOptions options;
  options.lm.max_iterations = iterations;
  options.lm.function_tolerance = 0.0;  // exactly `iterations` iterations
  options.lm.parameter_tolerance = 0.0;
  options.lm.gradient_tolerance = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  const BaSummary s = ba.solve(options);
  std::printf("initial_cost %.10g final_cost %.10g iterations %d time_ms %.3f inliers %d\n", s.initial_cost,
              s.final_cost, s.iterations, ms_since(t0), s.inliers);
  return 0;
}

int run_motion_only(int repeat, bool setup_only) {
  const SyntheticPoseScene scene = make_synthetic_pose_scene(300, 0.2, 1);
  const geometry::Camera camera = geometry::Camera::create(scene.intrinsics).value();
  std::vector<PoseObservation> obs;
  for (std::size_t k = 0; k < scene.points_w.size(); ++k) obs.push_back({scene.points_w[k], scene.uv_px[k], scene.levels[k]});
  std::vector<std::uint8_t> inlier(obs.size());
  if (setup_only) {
    std::printf("setup_only matches %zu\n", obs.size());
    return 0;
  }
  MotionOnlyResult r;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < repeat; ++i) r = optimize_pose(camera, scene.T_cw_init, obs.data(), static_cast<int>(obs.size()), {}, inlier.data());
  std::printf("inliers %d iterations %d final_cost %.10g time_ms %.4f repeat %d\n", r.inliers, r.iterations,
              r.final_cost, ms_since(t0) / repeat, repeat);
  return r.status.ok() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::string libmv;
  bool perturb = false, local_ba = false, motion = false, setup_only = false;
  std::uint64_t seed = 0;
  int iterations = 10, repeat = 1, max_iterations = 200;
  double ftol = 1e-10;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--libmv" && has_value) {
      libmv = argv[++i];
    } else if (a == "--perturb" && has_value) {
      perturb = true;
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--max-iterations" && has_value) {
      max_iterations = std::atoi(argv[++i]);
    } else if (a == "--function-tolerance" && has_value) {
      ftol = std::atof(argv[++i]);
    } else if (a == "--synthetic-local-ba") {
      local_ba = true;
    } else if (a == "--motion-only") {
      motion = true;
    } else if (a == "--iterations" && has_value) {
      iterations = std::atoi(argv[++i]);
    } else if (a == "--repeat" && has_value) {
      repeat = std::atoi(argv[++i]);
    } else if (a == "--setup-only") {
      setup_only = true;
    } else {
      std::fprintf(stderr, "ale_ba_bench: unknown or incomplete argument '%s'\n", a.c_str());
      return usage();
    }
  }
  if (iterations < 1 || repeat < 1 || max_iterations < 1 || !(ftol >= 0.0)) {
    std::fprintf(stderr, "ale_ba_bench: --iterations, --repeat, --max-iterations must be >= 1, --function-tolerance >= 0\n");
    return 2;
  }
  if (!libmv.empty()) return run_libmv(libmv, perturb, seed, max_iterations, ftol);
  if (local_ba) return run_local_ba(iterations, setup_only);
  if (motion) return run_motion_only(repeat, setup_only);
  return usage();
}
