// Pose-graph optimisation, ours vs Ceres (one thread, LM, sparse normal Cholesky, analytic
// Jacobians on both sides and the same stopping tolerances), from the odometry chain to the
// minimum. Each iteration restores the initial poses and solves again with a reused solver
// (ours keeps its structure, Ceres its Problem), as a loop closer solving a graph it already
// built would. Counters: final cost and iterations, to see both did the same work.
#include <benchmark/benchmark.h>

#include <vector>

#include "core/optim/pose_graph.h"
#include "tests/host/core/optim/pose_graph_scenes.h"
#if ALE_HAVE_CERES
#include "tests/host/core/optim/pose_graph_ceres.h"
#endif

namespace ale::optim {
namespace {

using geometry::Sim3;
using geometry::SE3;

template <class Group>
test::PoseGraphScene<Group> bench_scene(int poses) {
  return test::make_circle_scene<Group>(test::circle_spec(poses, 4, 4, 7));
}

template <class Group>
void BM_PoseGraphOurs(benchmark::State& state) {
  const test::PoseGraphScene<Group> scene = bench_scene<Group>(static_cast<int>(state.range(0)));
  PoseGraphOptimizer<Group> optimizer;
  const LmOptions options = test::tight_lm_options();
  std::vector<Group> poses = scene.initial;
  PoseGraphSummary last;
  for (auto _ : state) {
    std::copy(scene.initial.begin(), scene.initial.end(), poses.begin());
    Result<PoseGraphSummary> r = optimizer.optimize(scene.edges, {0}, options, &poses);
    if (!r.ok()) {
      state.SkipWithError(r.status().to_string().c_str());
      return;
    }
    last = *r;
  }
  state.counters["final_cost"] = last.final_cost;
  state.counters["iterations"] = last.iterations;
  state.counters["edges"] = static_cast<double>(scene.edges.size());
}

#if ALE_HAVE_CERES
template <class Group>
void BM_PoseGraphCeres(benchmark::State& state) {
  const test::PoseGraphScene<Group> scene = bench_scene<Group>(static_cast<int>(state.range(0)));
  test::CeresPoseGraph<Group> graph(scene.edges, {0}, scene.initial, test::CeresJacobians::kAnalytic);
  ceres::Solver::Options options = test::CeresPoseGraph<Group>::options();
  ceres::Solver::Summary summary;
  for (auto _ : state) {
    for (std::size_t v = 0; v < scene.initial.size(); ++v) {
      test::Ambient<Group>::to(scene.initial[v], graph.block(static_cast<int>(v)));
    }
    summary = graph.solve(options);
  }
  state.counters["final_cost"] = summary.final_cost;
  // Ceres lists iteration 0 (the start) too; the count of trial steps is one less.
  state.counters["iterations"] = static_cast<double>(summary.iterations.size()) - 1.0;
  state.counters["edges"] = static_cast<double>(scene.edges.size());
}
BENCHMARK_TEMPLATE(BM_PoseGraphCeres, SE3)->Arg(200)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_PoseGraphCeres, Sim3)->Arg(200)->Arg(1000)->Unit(benchmark::kMillisecond);
#endif

BENCHMARK_TEMPLATE(BM_PoseGraphOurs, SE3)->Arg(200)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_PoseGraphOurs, Sim3)->Arg(200)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ale::optim

BENCHMARK_MAIN();
