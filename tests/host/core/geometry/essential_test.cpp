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

}  // namespace
}  // namespace ale::geometry
