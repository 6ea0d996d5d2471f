// The five-point essential solver on exact synthetic data: the true E among the solutions (to
// 1e-8 up to scale and sign), every solution an essential matrix that satisfies the five
// constraints, and degenerate or non-finite samples giving no solution.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "core/base/rng.h"
#include "core/geometry/essential.h"
#include "tests/host/core/geometry/two_view_scene.h"

namespace ale::geometry {
namespace {

struct Sample {
  Vec2 q1[kEssentialSampleSize], q2[kEssentialSampleSize];
  Mat3 E;  // unit Frobenius norm
};

Mat3 hat(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

double symmetric(SplitMix64& rng) { return 2.0 * rng.uniform_double() - 1.0; }

// Five points 2-8 m in front of camera 1, seen by camera 2 at a random rotation (up to ~20 deg)
// and a random unit translation.
Sample make_sample(SplitMix64& rng) {
  Sample s;
  const Vec3 axis = Vec3(symmetric(rng), symmetric(rng), symmetric(rng)).normalized();
  const Mat3 R = Eigen::AngleAxisd(0.35 * rng.uniform_double(), axis).toRotationMatrix();
  const Vec3 t = Vec3(symmetric(rng), symmetric(rng), symmetric(rng)).normalized();
  for (int i = 0; i < kEssentialSampleSize; ++i) {
    const Vec3 p1(symmetric(rng), symmetric(rng), 2.0 + 6.0 * rng.uniform_double());
    const Vec3 p2 = R * p1 + t;
    s.q1[i] = p1.hnormalized();
    s.q2[i] = p2.hnormalized();
  }
  s.E = hat(t) * R;
  s.E /= s.E.norm();
  return s;
}

double distance_up_to_sign(const Mat3& a, const Mat3& b) { return std::min((a - b).norm(), (a + b).norm()); }

TEST(Essential5Point, TrueEssentialMatrixIsAmongTheSolutions) {
  SplitMix64 rng(11);
  double worst = 0.0;
  int total_solutions = 0;
  constexpr int kTrials = 200;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Sample s = make_sample(rng);
    std::array<Mat3, kEssentialMaxSolutions> E;
    const int count = essential_5point(s.q1, s.q2, &E);
    ASSERT_GE(count, 1) << "trial " << trial;
    ASSERT_LE(count, kEssentialMaxSolutions);
    total_solutions += count;
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < count; ++k) {
      const Mat3& Ek = E[static_cast<std::size_t>(k)];
      EXPECT_NEAR(Ek.norm(), 1.0, 1e-12);
      // Every solution satisfies the five epipolar constraints and is essential (two equal
      // singular values, the third zero).
      for (int i = 0; i < kEssentialSampleSize; ++i)
        EXPECT_NEAR(s.q2[i].homogeneous().dot(Ek * s.q1[i].homogeneous()), 0.0, 1e-9) << "trial " << trial;
      const Vec3 sv = Eigen::JacobiSVD<Mat3>(Ek).singularValues();
      EXPECT_NEAR(sv(0), sv(1), 1e-7) << "trial " << trial;
      EXPECT_NEAR(sv(2), 0.0, 1e-7) << "trial " << trial;
      best = std::min(best, distance_up_to_sign(Ek, s.E));
    }
    EXPECT_LT(best, 1e-8) << "trial " << trial;
    worst = std::max(worst, best);
  }
  std::printf("five-point: %d samples, %.2f solutions on average, worst distance to the true E %.3g\n", kTrials,
              static_cast<double>(total_solutions) / kTrials, worst);
}

TEST(Essential5Point, DegenerateSamplesGiveNoSolution) {
  SplitMix64 rng(5);
  Sample s = make_sample(rng);
  std::array<Mat3, kEssentialMaxSolutions> E;
  // A repeated correspondence: four independent constraints leave a 5-dimensional null space.
  Sample repeated = s;
  repeated.q1[4] = repeated.q1[0];
  repeated.q2[4] = repeated.q2[0];
  EXPECT_EQ(essential_5point(repeated.q1, repeated.q2, &E), 0);
  // All five the same point.
  Sample same = s;
  for (int i = 1; i < kEssentialSampleSize; ++i) {
    same.q1[i] = same.q1[0];
    same.q2[i] = same.q2[0];
  }
  EXPECT_EQ(essential_5point(same.q1, same.q2, &E), 0);
  // Non-finite coordinates.
  Sample bad = s;
  bad.q1[2].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(essential_5point(bad.q1, bad.q2, &E), 0);
  bad = s;
  bad.q2[3].y() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(essential_5point(bad.q1, bad.q2, &E), 0);
}

// The hypotheses: the first scores at least as estimate_essential's answer, they are min_separation apart, a
// rescore reorders them, and reconstruct_two_view_from recovers the pose from the true F.
TEST(EssentialHypotheses, FirstScoresAsTheRansacAnswerAndTheyAreDistinct) {
  test::SceneSpec spec;
  const test::Scene s = test::make_scene(spec);
  const Mat3 K = test::K_of(s.camera);
  const int n = static_cast<int>(s.x1.size());
  TwoViewParams params;
  TwoViewScratch scratch;
  Mat3 F;
  std::vector<std::uint8_t> mask;
  RansacStats st;
  ASSERT_TRUE(estimate_essential(s.x1.data(), s.x2.data(), n, K, params, &F, mask, &st, scratch).ok());
  EssentialHypothesesParams hp;
  std::vector<EssentialHypothesis> hyps;
  ASSERT_TRUE(estimate_essential_hypotheses(s.x1.data(), s.x2.data(), n, K, params, hp, &hyps, scratch).ok());
  ASSERT_FALSE(hyps.empty());
  EXPECT_LE(static_cast<int>(hyps.size()), hp.max_hypotheses);
  // estimate_essential's answer is one of the refined pool, so the first scores at least as well.
  EXPECT_GE(hyps[0].score, st.score);
  EXPECT_LT(essential_distance(hyps[0].F_21, F, K), 0.01);
  for (std::size_t a = 0; a < hyps.size(); ++a) {
    if (a > 0) {
      EXPECT_LE(hyps[a].score, hyps[a - 1].score);
    }
    for (std::size_t b = a + 1; b < hyps.size(); ++b)
      EXPECT_GE(essential_distance(hyps[a].F_21, hyps[b].F_21, K), hp.min_separation);
  }
  // A rescore that prefers the model farthest from the truth puts another model first.
  const Mat3 F_true = test::true_fundamental(s);
  const auto far = [&](const Mat3& m) { return essential_distance(m, F_true, K); };
  std::vector<EssentialHypothesis> rescored;
  ASSERT_TRUE(estimate_essential_hypotheses(s.x1.data(), s.x2.data(), n, K, params, hp, &rescored, scratch, far).ok());
  EXPECT_GT(essential_distance(rescored[0].F_21, F_true, K), 0.1);
  EXPECT_DOUBLE_EQ(rescored[0].score, far(rescored[0].F_21));
  hp.max_hypotheses = 0;
  EXPECT_EQ(estimate_essential_hypotheses(s.x1.data(), s.x2.data(), n, K, params, hp, &hyps, scratch).code(),
            StatusCode::kInvalidArgument);

  TwoViewResult r;
  ASSERT_TRUE(reconstruct_two_view_from(F_true, s.x1, s.x2, s.camera, params, &r, scratch).ok());
  EXPECT_EQ(r.model, TwoViewModel::kFundamental);
  EXPECT_LT(SO3::from_matrix(r.R_21.transpose() * s.R_21).log().norm() * 180.0 / M_PI, 0.5);
  EXPECT_GT(r.t_21.dot(s.t_21.normalized()), std::cos(3.0 * M_PI / 180.0));
  EXPECT_EQ(reconstruct_two_view_from(Mat3::Zero(), s.x1, s.x2, s.camera, params, &r, scratch).code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace ale::geometry
