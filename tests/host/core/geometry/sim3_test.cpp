// Sim(3) / SE(3) from 3-D matches: the closed form is exact on exact data and refuses
// reflections; weights act as repetition; RANSAC recovers the truth from noisy matches with
// 30 % outliers within stated tolerances; degenerate input gives a status; the same seed gives
// the same result.
#include "core/geometry/sim3_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "core/base/rng.h"

namespace ale::geometry {
namespace {

constexpr double kRadToDeg = 57.29577951308232;

double uniform(SplitMix64& rng, double lo, double hi) { return lo + (hi - lo) * rng.uniform_double(); }

Vec3 uniform_box(SplitMix64& rng, double half) {
  // one declaration per draw: constructor arguments are evaluated in an unspecified order
  // (right to left on x86 GCC, not on ARM), which would give each platform other scenes
  const double vx = uniform(rng, -half, half);
  const double vy = uniform(rng, -half, half);
  const double vz = uniform(rng, -half, half);
  return Vec3(vx, vy, vz);
}

Sim3 random_sim3(SplitMix64& rng, bool with_scale) {
  Vec7 z;
  z << uniform_box(rng, 3.0), uniform_box(rng, 1.5), with_scale ? uniform(rng, -1.0, 1.5) : 0.0;
  return Sim3::exp(z);
}

double rotation_error_deg(const Sim3& a, const Sim3& b) {
  return (a.so3().inverse() * b.so3()).log().norm() * kRadToDeg;
}

struct Scene {
  std::vector<Vec3> x, y;
  std::vector<std::uint8_t> is_inlier;
  Sim3 truth;
};

// n matches, x in a 4 m box, y = truth * x + N(0, (s sigma)^2) per axis (sigma in x's units);
// a share of them replaced by random points in y's region (outliers).
Scene make_scene(std::uint64_t seed, int n, double sigma, double outlier_share, bool with_scale) {
  SplitMix64 rng(seed);
  Scene s;
  s.truth = random_sim3(rng, with_scale);
  for (int i = 0; i < n; ++i) {
    const Vec3 x = uniform_box(rng, 2.0);
    Vec3 y = s.truth * x;
    const bool outlier = rng.uniform_double() < outlier_share;
    if (outlier) {
      y = s.truth * uniform_box(rng, 2.0);  // anywhere in the same region: not trivially far
    } else {
      const double nx = rng.gaussian();
      const double ny = rng.gaussian();
      const double nz = rng.gaussian();
      y += sigma * s.truth.scale() * Vec3(nx, ny, nz);
    }
    s.x.push_back(x);
    s.y.push_back(y);
    s.is_inlier.push_back(outlier ? 0 : 1);
  }
  return s;
}

TEST(Umeyama, ExactOnExactData) {
  SplitMix64 rng(1);
  for (int trial = 0; trial < 20; ++trial) {
    for (bool with_scale : {true, false}) {
      const Sim3 truth = random_sim3(rng, with_scale);
      std::vector<Vec3> x, y;
      for (int i = 0; i < 3 + trial; ++i) {
        x.push_back(uniform_box(rng, 2.0));
        y.push_back(truth * x.back());
      }
      const Result<Sim3> s = umeyama(x, y, with_scale);
      ASSERT_TRUE(s.ok()) << s.status().to_string();
      EXPECT_LT((s->matrix() - truth.matrix()).cwiseAbs().maxCoeff(), 1e-11) << trial;
      EXPECT_NEAR(s->scale(), truth.scale(), 1e-12 * truth.scale());
    }
  }
}

TEST(Umeyama, WithoutScaleFitsTheBestRigidMotion) {
  // Data scaled by 2 but fitted without scale: rotation still exact, scale stays 1 and the
  // translation puts the centroids on each other.
  SplitMix64 rng(2);
  Vec7 z;
  z << 0.5, -1.0, 2.0, 0.3, -0.4, 0.8, std::log(2.0);
  const Sim3 truth = Sim3::exp(z);
  std::vector<Vec3> x, y;
  Vec3 mx = Vec3::Zero(), my = Vec3::Zero();
  for (int i = 0; i < 30; ++i) {
    x.push_back(uniform_box(rng, 2.0));
    y.push_back(truth * x.back());
    mx += x.back() / 30.0;
    my += y.back() / 30.0;
  }
  const Result<Sim3> s = umeyama(x, y, false);
  ASSERT_TRUE(s.ok());
  EXPECT_EQ(s->scale(), 1.0);
  EXPECT_LT(rotation_error_deg(*s, truth), 1e-9);
  EXPECT_LT((*s * mx - my).norm(), 1e-12);
}

TEST(Umeyama, ReflectionGivesARotation) {
  // y is a mirror image of x: the best proper rotation, never a reflection.
  SplitMix64 rng(3);
  std::vector<Vec3> x, y;
  for (int i = 0; i < 20; ++i) {
    x.push_back(uniform_box(rng, 1.0));
    y.push_back(Vec3(-x.back().x(), x.back().y(), x.back().z()));
  }
  const Result<Sim3> s = umeyama(x, y, true);
  ASSERT_TRUE(s.ok());
  EXPECT_NEAR(s->rotation().determinant(), 1.0, 1e-12);
}

TEST(Umeyama, WeightsActAsRepetition) {
  SplitMix64 rng(4);
  const Sim3 truth = random_sim3(rng, true);
  std::vector<Vec3> x, y, x_rep, y_rep;
  std::vector<double> w;
  for (int i = 0; i < 12; ++i) {
    x.push_back(uniform_box(rng, 2.0));
    y.push_back(truth * x.back() + 0.05 * uniform_box(rng, 1.0));
    const int times = 1 + i % 3;
    w.push_back(times);
    for (int k = 0; k < times; ++k) {
      x_rep.push_back(x.back());
      y_rep.push_back(y.back());
    }
  }
  const Result<Sim3> weighted = umeyama(x, y, true, w);
  const Result<Sim3> repeated = umeyama(x_rep, y_rep, true);
  ASSERT_TRUE(weighted.ok() && repeated.ok());
  EXPECT_LT((weighted->matrix() - repeated->matrix()).cwiseAbs().maxCoeff(), 1e-12);
  // and a zero weight removes a gross outlier completely
  x.push_back(Vec3(0.1, 0.2, 0.3));
  y.push_back(Vec3(50.0, -40.0, 9.0));
  w.push_back(0.0);
  const Result<Sim3> ignoring = umeyama(x, y, true, w);
  ASSERT_TRUE(ignoring.ok());
  EXPECT_LT((ignoring->matrix() - repeated->matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Umeyama, DegenerateInputGivesStatus) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto rejected = [](const std::vector<Vec3>& x, const std::vector<Vec3>& y, const std::vector<double>& w,
                           const char* what) {
    const Result<Sim3> s = umeyama(x, y, true, w);
    ASSERT_FALSE(s.ok()) << what;
    EXPECT_EQ(s.status().code(), StatusCode::kInvalidArgument) << what;
    EXPECT_FALSE(s.status().message().empty());
  };
  const std::vector<Vec3> tri = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  rejected({Vec3(0, 0, 0), Vec3(1, 0, 0)}, {Vec3(0, 0, 0), Vec3(1, 0, 0)}, {}, "two points");
  rejected(tri, {Vec3(0, 0, 0), Vec3(1, 0, 0)}, {}, "sizes differ");
  std::vector<Vec3> line;
  for (int i = 0; i < 6; ++i) line.push_back(Vec3(0.5, 1.0, -2.0) * i + Vec3(1, 2, 3));
  rejected(line, line, {}, "collinear");
  std::vector<Vec3> near_line = line;
  near_line[3].y() += 1e-9;  // far below the 1e-5 relative spread
  rejected(near_line, near_line, {}, "collinear to 1e-9");
  rejected(std::vector<Vec3>(5, Vec3(1, 2, 3)), std::vector<Vec3>(5, Vec3(1, 2, 3)), {}, "one point");
  rejected(tri, std::vector<Vec3>(line.begin(), line.begin() + 3), {}, "y collinear");
  rejected({Vec3(0, 0, 0), Vec3(1, nan, 0), Vec3(0, 1, 0)}, tri, {}, "nan in x");
  rejected(tri, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, std::numeric_limits<double>::infinity(), 0)}, {}, "inf in y");
  rejected(tri, tri, {1.0, -1.0, 1.0}, "negative weight");
  rejected(tri, tri, {0.0, 0.0, 0.0}, "zero weights");
  rejected(tri, tri, {1.0, 1.0}, "weights size");
  rejected(tri, tri, {1.0, nan, 1.0}, "nan weight");
  EXPECT_TRUE(umeyama(tri, tri, true).ok());
}

// Tolerances for 200 matches, sigma = 1 cm per axis in a 4 m box, 30 % outliers (the errors
// expected from noise alone are about 10x smaller).
constexpr double kMaxRotationErrorDeg = 0.2;
constexpr double kMaxRelScaleError = 0.005;
constexpr double kMaxTranslationError = 0.02;

Sim3RansacParams params_for(double sigma, bool with_scale, std::uint64_t seed) {
  Sim3RansacParams p;
  p.ransac.seed = seed;
  p.ransac.max_iterations = 500;
  p.with_scale = with_scale;
  p.max_error_y = 4.0 * sigma;  // beyond the 99.9 % radius (3.7 sigma) of 3-D Gaussian noise
  return p;
}

TEST(Sim3Ransac, RecoversTruthWith30PercentOutliers) {
  Sim3Scratch scratch;
  for (bool with_scale : {true, false}) {
    double worst_rot = 0.0, worst_scale = 0.0, worst_t = 0.0;
    int worst_iterations = 0;
    for (std::uint64_t seed = 10; seed < 30; ++seed) {
      const double sigma = 0.01;
      const Scene scene = make_scene(seed, 200, sigma, 0.3, with_scale);
      Sim3RansacParams p = params_for(sigma * scene.truth.scale(), with_scale, seed);
      Sim3RansacResult r;
      const Status st = solve_sim3_ransac(scene.x, scene.y, p, &r, scratch);
      ASSERT_TRUE(st.ok()) << st.to_string();
      EXPECT_LT(rotation_error_deg(r.S_yx, scene.truth), kMaxRotationErrorDeg) << seed;
      EXPECT_LT(std::abs(r.S_yx.scale() / scene.truth.scale() - 1.0), kMaxRelScaleError) << seed;
      EXPECT_LT((r.S_yx.translation() - scene.truth.translation()).norm(), kMaxTranslationError * scene.truth.scale())
          << seed;
      if (!with_scale) {
        EXPECT_EQ(r.S_yx.scale(), 1.0);
      }
      // inlier classification: every true outlier rejected, at least 98 % of the inliers kept
      int true_in = 0, kept = 0, false_in = 0;
      for (std::size_t i = 0; i < scene.x.size(); ++i) {
        true_in += scene.is_inlier[i];
        kept += scene.is_inlier[i] && r.inlier_mask[i];
        false_in += !scene.is_inlier[i] && r.inlier_mask[i];
      }
      EXPECT_GE(kept, 0.98 * true_in) << seed;
      EXPECT_LE(false_in, 1) << seed;  // an outlier may fall within 4 sigma of its true place by chance
      EXPECT_EQ(r.inliers, kept + false_in);
      EXPECT_LT(r.rms_error_y, 2.0 * sigma * scene.truth.scale());
      EXPECT_GT(r.stats.iterations, 0);
      worst_rot = std::max(worst_rot, rotation_error_deg(r.S_yx, scene.truth));
      worst_scale = std::max(worst_scale, std::abs(r.S_yx.scale() / scene.truth.scale() - 1.0));
      worst_t = std::max(worst_t, (r.S_yx.translation() - scene.truth.translation()).norm() / scene.truth.scale());
      worst_iterations = std::max(worst_iterations, r.stats.iterations);
    }
    std::printf("%s, 20 scenes: worst rotation %.4f deg, scale %.2e rel, translation / s %.4f, iterations %d\n",
                with_scale ? "sim3" : "se3", worst_rot, worst_scale, worst_t, worst_iterations);
  }
}

TEST(Sim3Ransac, BothGatesForMapsOfDifferentScale) {
  // x in a map 10x smaller than y: gates of 4 sigma in each map's own units.
  Vec7 z;
  z << 1.0, 2.0, -1.0, 0.2, 0.5, -0.3, std::log(10.0);
  SplitMix64 rng(77);
  std::vector<Vec3> x, y;
  const Sim3 truth = Sim3::exp(z);
  for (int i = 0; i < 150; ++i) {
    x.push_back(uniform_box(rng, 0.3));
    const bool outlier = i % 3 == 0;
    y.push_back(outlier ? truth * uniform_box(rng, 0.3) : truth * x.back() + 0.02 * uniform_box(rng, 1.0));
  }
  Sim3RansacParams p;
  p.ransac.seed = 5;
  p.max_error_y = 0.08;
  p.max_error_x = 0.008;
  Sim3RansacResult r;
  Sim3Scratch scratch;
  ASSERT_TRUE(solve_sim3_ransac(x, y, p, &r, scratch).ok());
  EXPECT_NEAR(r.S_yx.scale(), 10.0, 0.05);
  EXPECT_LT(rotation_error_deg(r.S_yx, truth), 0.5);
  EXPECT_GE(r.inliers, 95);
  EXPECT_LE(r.inliers, 101);
}

TEST(Sim3Ransac, SameSeedSameResult) {
  const Scene scene = make_scene(99, 120, 0.02, 0.3, true);
  const Sim3RansacParams p = params_for(0.02 * scene.truth.scale(), true, 1234);
  Sim3Scratch scratch_a, scratch_b;
  Sim3RansacResult a, b, c;
  ASSERT_TRUE(solve_sim3_ransac(scene.x, scene.y, p, &a, scratch_a).ok());
  ASSERT_TRUE(solve_sim3_ransac(scene.x, scene.y, p, &b, scratch_b).ok());
  // the same scratch reused after another problem must not change the stream
  const Scene other = make_scene(5, 60, 0.02, 0.1, true);
  Sim3RansacResult unused;
  ASSERT_TRUE(solve_sim3_ransac(other.x, other.y, params_for(0.02 * other.truth.scale(), true, 9), &unused, scratch_a)
                  .ok());
  ASSERT_TRUE(solve_sim3_ransac(scene.x, scene.y, p, &c, scratch_a).ok());
  for (const Sim3RansacResult* r : {&b, &c}) {
    EXPECT_EQ(r->S_yx.matrix(), a.S_yx.matrix());
    EXPECT_EQ(r->inlier_mask, a.inlier_mask);
    EXPECT_EQ(r->stats.iterations, a.stats.iterations);
  }
}

TEST(Sim3Ransac, DegenerateAndBadInputGiveStatus) {
  Sim3Scratch scratch;
  Sim3RansacResult r;
  Sim3RansacParams p;
  p.max_error_y = 0.05;
  const std::vector<Vec3> tri = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  EXPECT_EQ(solve_sim3_ransac({Vec3(0, 0, 0), Vec3(1, 0, 0)}, {Vec3(0, 0, 0), Vec3(1, 0, 0)}, p, &r, scratch).code(),
            StatusCode::kInvalidArgument);
  std::vector<Vec3> line;
  for (int i = 0; i < 20; ++i) line.push_back(Vec3(1.0, -1.0, 0.5) * (0.1 * i));
  EXPECT_EQ(solve_sim3_ransac(line, line, p, &r, scratch).code(), StatusCode::kInvalidArgument);
  std::vector<Vec3> bad = tri;
  bad[1].z() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(solve_sim3_ransac(bad, tri, p, &r, scratch).code(), StatusCode::kInvalidArgument);
  Sim3RansacParams no_gate;
  EXPECT_EQ(solve_sim3_ransac(tri, tri, no_gate, &r, scratch).code(), StatusCode::kInvalidArgument);
  Sim3RansacParams neg_x = p;
  neg_x.max_error_x = -1.0;
  EXPECT_EQ(solve_sim3_ransac(tri, tri, neg_x, &r, scratch).code(), StatusCode::kInvalidArgument);
  // pure noise: no model gathers min_inliers
  SplitMix64 rng(8);
  std::vector<Vec3> x, y;
  for (int i = 0; i < 100; ++i) {
    x.push_back(uniform_box(rng, 2.0));
    y.push_back(uniform_box(rng, 2.0));
  }
  p.min_inliers = 20;
  p.max_error_y = 0.01;
  EXPECT_EQ(solve_sim3_ransac(x, y, p, &r, scratch).code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace ale::geometry
