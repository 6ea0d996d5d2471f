// The three real libmv bundle-adjustment problems (../shared/data/ba_libmv): loading, and our
// solver from the file's values and from seeded perturbations (0.3 deg, 1 %). With Ceres (host
// builds) the final cost must equal Ceres SPARSE_SCHUR's on the same residual within 1e-6
// relative; without it (armhf, under qemu) the run must converge and keep every pose finite.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "core/optim/bundle_adjuster.h"
#include "app/tools/lib/ba/libmv_problem.h"
#include "tests/host/support/test_data.h"
#ifdef ALE_HAVE_CERES
#include "app/tools/ale_ba_bench/ceres_ba.h"
#endif

namespace ale::optim {
namespace {

// Both solvers are run to the same tight tolerances so that each stops at the minimum (Ceres'
// default 1e-6 relative cost change could stop either one short by about that much).
constexpr double kFunctionTolerance = 1e-10;
constexpr int kMaxIterations = 200;

BaSummary solve_ours(LibmvProblem* p) {
  BundleAdjuster ba;
  ba.reset(geometry::Camera::create(p->intrinsics).value());
  for (const geometry::SE3& T : p->T_cw) ba.add_pose(T, false);
  for (const geometry::Vec3& x : p->points_w) ba.add_point(x);
  for (const LibmvObservation& o : p->observations) ba.add_observation(o.camera, o.point, o.uv_px);
  BaOptions options;
  options.elimination = SchurElimination::kAuto;
  options.chi2_gate = 0.0;
  options.lm.function_tolerance = kFunctionTolerance;
  options.lm.max_iterations = kMaxIterations;
  const BaSummary s = ba.solve(options);
  for (int i = 0; i < ba.num_poses(); ++i) p->T_cw[i] = ba.pose(i);
  for (int j = 0; j < ba.num_points(); ++j) p->points_w[j] = ba.point(j);
  return s;
}

class Libmv : public ::testing::TestWithParam<const char*> {};

TEST_P(Libmv, FinalCostMatchesTheReference) {
  ALE_REQUIRE_DATA(path, std::string("ba_libmv/") + GetParam());
  Result<LibmvProblem> loaded = load_libmv_problem(path);
  ASSERT_TRUE(loaded.ok()) << loaded.status().to_string();
  const geometry::Camera cam = geometry::Camera::create(loaded->intrinsics).value();
  for (int seed = -1; seed <= 2; ++seed) {  // -1: the file's values
    LibmvProblem ours = *loaded;
    if (seed >= 0) perturb_libmv_problem(static_cast<std::uint64_t>(seed), 0.3, 0.01, &ours);
    const double start_cost = libmv_cost(ours, cam);
#ifdef ALE_HAVE_CERES
    LibmvProblem theirs = ours;
#endif
    const BaSummary s = solve_ours(&ours);
    ASSERT_TRUE(s.status.ok()) << s.status.to_string() << " seed " << seed;
    EXPECT_NEAR(s.initial_cost, start_cost, 1e-9 * start_cost);
    EXPECT_NEAR(libmv_cost(ours, cam), s.final_cost, 1e-9 * s.final_cost);  // the state is the one reported
    EXPECT_LT(s.final_cost, s.initial_cost);
    for (const geometry::SE3& T : ours.T_cw) ASSERT_TRUE(T.translation().allFinite());
#ifdef ALE_HAVE_CERES
    ceres_ref::Options co;
    co.function_tolerance = kFunctionTolerance;
    co.max_iterations = kMaxIterations;
    const ceres_ref::Result c = ceres_ref::solve_libmv(&theirs, co);
    ASSERT_TRUE(c.usable);
    EXPECT_NEAR(c.initial_cost, s.initial_cost, 1e-9 * s.initial_cost) << "same residual, same start";
    EXPECT_NEAR(s.final_cost, c.final_cost, 1e-6 * c.final_cost) << GetParam() << " seed " << seed;
    std::printf("%s seed %d: initial %.10g ours %.10g (%d it) ceres %.10g (%d it) relative %.2e\n", GetParam(), seed,
                s.initial_cost, s.final_cost, s.iterations, c.final_cost, c.iterations,
                (s.final_cost - c.final_cost) / c.final_cost);
#endif
  }
}

INSTANTIATE_TEST_SUITE_P(Problems, Libmv, ::testing::Values("problem_01.bin", "problem_02.bin", "problem_03.bin"));

TEST(LibmvLoader, RejectsBadFiles) {
  const std::string dir = test::make_temp_dir("libmv");
  EXPECT_EQ(load_libmv_problem(dir + "/missing.bin").status().code(), StatusCode::kNotFound);
  ASSERT_TRUE(test::write_file(dir + "/tag.bin", "xP"));
  EXPECT_EQ(load_libmv_problem(dir + "/tag.bin").status().code(), StatusCode::kCorruptData);
  ASSERT_TRUE(test::write_file(dir + "/space.bin", "vQ"));
  EXPECT_EQ(load_libmv_problem(dir + "/space.bin").status().code(), StatusCode::kCorruptData);
  ASSERT_TRUE(test::write_file(dir + "/short.bin", std::string("vP") + std::string(20, '\0')));
  EXPECT_EQ(load_libmv_problem(dir + "/short.bin").status().code(), StatusCode::kCorruptData);
  // a valid file with one observation naming an unknown camera (skipped, as libmv does)
  std::string b = "vP";
  const auto put32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
  };
  const auto putf = [&](float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    put32(u);
  };
  for (float f : {500.f, 320.f, 240.f, 0.f, 0.f, 0.f, 0.f, 0.f}) putf(f);
  put32(1);
  put32(7);
  for (float f : {1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f}) putf(f);
  put32(1);
  put32(3);
  for (float f : {0.f, 0.f, 5.f}) putf(f);
  put32(1);
  put32(8);  // image 8 does not exist
  put32(3);
  putf(320.f);
  putf(240.f);
  ASSERT_TRUE(test::write_file(dir + "/unknown.bin", b));
  const Result<LibmvProblem> skipped = load_libmv_problem(dir + "/unknown.bin");
  ASSERT_TRUE(skipped.ok()) << skipped.status().to_string();
  EXPECT_EQ(skipped->observations.size(), 0u);
  EXPECT_EQ(skipped->skipped_observations, 1);
  ASSERT_TRUE(test::write_file(dir + "/trailing.bin", b + "x"));
  EXPECT_EQ(load_libmv_problem(dir + "/trailing.bin").status().code(), StatusCode::kCorruptData);
  ASSERT_TRUE(test::write_file(dir + "/truncated.bin", b.substr(0, b.size() - 3)));
  EXPECT_EQ(load_libmv_problem(dir + "/truncated.bin").status().code(), StatusCode::kCorruptData);
  b[b.size() - 16] = 7;  // now it names image 7
  ASSERT_TRUE(test::write_file(dir + "/good.bin", b));
  const Result<LibmvProblem> good = load_libmv_problem(dir + "/good.bin");
  ASSERT_TRUE(good.ok()) << good.status().to_string();
  EXPECT_EQ(good->observations.size(), 1u);
  EXPECT_EQ(good->skipped_observations, 0);
  EXPECT_EQ(good->image_ids[0], 7);
  EXPECT_EQ(good->observations[0].camera, 0);
  EXPECT_DOUBLE_EQ(good->observations[0].uv_px.x(), 320.0);
}

}  // namespace
}  // namespace ale::optim
