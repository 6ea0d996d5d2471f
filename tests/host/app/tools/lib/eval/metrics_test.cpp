// Hand-computed cases for association, alignment, ATE, RPE and coverage.
#include "app/tools/lib/eval/metrics.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <string>

#include "app/tools/lib/eval/align.h"
#include "app/tools/lib/eval/associate.h"

namespace ale::eval {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix3d rot(double angle_rad, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}

// A helix of radius 2 around the z axis, turning with the path: not planar, so every
// alignment is well determined.
Trajectory helix(std::size_t n = 50) {
  Trajectory t;
  t.name = "helix";
  for (std::size_t k = 0; k < n; ++k) {
    const double a = 0.3 * static_cast<double>(k);
    StampedPose p;
    p.t_s = 100.0 + 0.1 * static_cast<double>(k);
    p.p_wb = Eigen::Vector3d(2.0 * std::cos(a), 2.0 * std::sin(a), 0.1 * static_cast<double>(k));
    p.R_wb = rot(a, Eigen::Vector3d::UnitZ()) * rot(0.2, Eigen::Vector3d::UnitX());
    t.poses.push_back(p);
  }
  return t;
}

// est = s * R * gt + t, orientations R * R_gt: what a perfect estimator in another frame gives.
Trajectory transformed(const Trajectory& gt, const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double s) {
  Trajectory est = gt;
  est.name = "estimate";
  for (StampedPose& p : est.poses) {
    p.p_wb = s * (R * p.p_wb) + t;
    p.R_wb = R * p.R_wb;
  }
  return est;
}

struct Evaluated {
  Sim3 alignment;
  AteResult ate;
};

Evaluated evaluate(const Trajectory& gt, const Trajectory& est, Alignment alignment) {
  Result<PosePairs> pairs = associate(gt, est, 0.01);
  EXPECT_TRUE(pairs.ok()) << pairs.status().to_string();
  Result<Sim3> sim3 = align_estimate(alignment, &*pairs);
  EXPECT_TRUE(sim3.ok()) << sim3.status().to_string();
  Result<AteResult> ate = compute_ate(*pairs);
  EXPECT_TRUE(ate.ok()) << ate.status().to_string();
  return {*sim3, *ate};
}

TEST(AteTest, PureTranslationOffset) {
  const Trajectory gt = helix();
  const Eigen::Vector3d offset(1.0, -2.0, 0.5);
  const Trajectory est = transformed(gt, Eigen::Matrix3d::Identity(), offset, 1.0);

  const Evaluated raw = evaluate(gt, est, Alignment::kNone);
  const double d = std::sqrt(5.25);
  EXPECT_NEAR(raw.ate.trans_m.rmse, d, 1e-12);
  EXPECT_NEAR(raw.ate.trans_m.mean, d, 1e-12);
  EXPECT_NEAR(raw.ate.trans_m.min, d, 1e-12);
  EXPECT_NEAR(raw.ate.trans_m.max, d, 1e-12);
  EXPECT_NEAR(raw.ate.trans_m.std, 0.0, 1e-12);
  EXPECT_NEAR(raw.ate.trans_m.sse, 50 * 5.25, 1e-9);
  EXPECT_NEAR(raw.ate.rot_deg.max, 0.0, 1e-9);
  EXPECT_EQ(raw.ate.trans_m.count, 50u);

  const Evaluated aligned = evaluate(gt, est, Alignment::kSe3);
  EXPECT_NEAR(aligned.ate.trans_m.max, 0.0, 1e-9);
  EXPECT_NEAR((aligned.alignment.t + offset).norm(), 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(aligned.alignment.scale, 1.0);
}

TEST(AteTest, PureRotation) {
  const Trajectory gt = helix();
  const Eigen::Matrix3d R0 = rot(30.0 * kPi / 180.0, Eigen::Vector3d::UnitZ());
  const Trajectory est = transformed(gt, R0, Eigen::Vector3d::Zero(), 1.0);

  // Every point is 2 m from the z axis, so it moves by the chord 2 * 2 * sin(15 deg).
  const Evaluated raw = evaluate(gt, est, Alignment::kNone);
  const double chord = 4.0 * std::sin(15.0 * kPi / 180.0);
  EXPECT_NEAR(raw.ate.trans_m.min, chord, 1e-12);
  EXPECT_NEAR(raw.ate.trans_m.max, chord, 1e-12);
  EXPECT_NEAR(raw.ate.rot_deg.mean, 30.0, 1e-9);
  EXPECT_NEAR(raw.ate.rot_deg.max, 30.0, 1e-9);

  const Evaluated aligned = evaluate(gt, est, Alignment::kSe3);
  EXPECT_NEAR(aligned.ate.trans_m.max, 0.0, 1e-9);
  EXPECT_NEAR(aligned.ate.rot_deg.max, 0.0, 1e-6);
  EXPECT_TRUE(aligned.alignment.R.isApprox(R0.transpose(), 1e-12));
}

TEST(AteTest, KnownScaleWithSim3) {
  const Trajectory gt = helix();
  const Eigen::Matrix3d R0 = rot(1.0, Eigen::Vector3d(1, 2, 3));
  const Trajectory est = transformed(gt, R0, Eigen::Vector3d(5, -1, 2), 0.25);

  const Evaluated sim3 = evaluate(gt, est, Alignment::kSim3);
  EXPECT_NEAR(sim3.alignment.scale, 4.0, 1e-12);
  EXPECT_NEAR(sim3.ate.trans_m.max, 0.0, 1e-9);
  EXPECT_NEAR(sim3.ate.rot_deg.max, 0.0, 1e-6);

  // Without the scale the shape does not fit.
  const Evaluated se3 = evaluate(gt, est, Alignment::kSe3);
  EXPECT_GT(se3.ate.trans_m.rmse, 0.5);
}

TEST(AlignTest, DegenerateInputIsAnError) {
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 5; ++i) line.emplace_back(i, 2 * i, 0);
  EXPECT_FALSE(umeyama(line, line, false).ok());
  const std::vector<Eigen::Vector3d> two = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)};
  const Result<Sim3> few = umeyama(two, two, false);
  ASSERT_FALSE(few.ok());
  EXPECT_NE(few.status().message().find("at least 3"), std::string::npos);
}

TEST(StatsTest, MedianAndStdFollowNumpy) {
  const Result<ErrorStats> s = compute_stats({4.0, 1.0, 3.0, 2.0});
  ASSERT_TRUE(s.ok());
  EXPECT_DOUBLE_EQ(s->median, 2.5);
  EXPECT_DOUBLE_EQ(s->mean, 2.5);
  EXPECT_DOUBLE_EQ(s->std, std::sqrt(1.25));  // population
  EXPECT_DOUBLE_EQ(s->rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s->sse, 30.0);
  EXPECT_FALSE(compute_stats({}).ok());
}

TEST(AssociateTest, NearestWithinMaxDifference) {
  const Trajectory gt = helix(10);
  Trajectory est = gt;
  for (StampedPose& p : est.poses) p.t_s += 0.004;
  est.poses.pop_back();
  Result<PosePairs> pairs = associate(gt, est, 0.01);
  ASSERT_TRUE(pairs.ok());
  ASSERT_EQ(pairs->gt.size(), 9u);
  for (std::size_t i = 0; i < 9; ++i) EXPECT_DOUBLE_EQ(pairs->gt[i].t_s + 0.004, pairs->est[i].t_s);

  const Result<PosePairs> none = associate(gt, est, 0.003);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.status().message().find("no overlap"), std::string::npos) << none.status().message();
}

TEST(AssociateTest, TieTakesTheEarlierPose) {
  Trajectory gt;
  gt.name = "gt";
  for (double t : {0.25, 0.5, 0.75}) gt.poses.push_back(StampedPose{t, Eigen::Matrix3d::Identity(), Eigen::Vector3d(t, 0, 0)});
  Trajectory est;
  est.name = "est";
  est.poses.push_back(StampedPose{0.625, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()});
  Result<PosePairs> pairs = associate(gt, est, 0.2);
  ASSERT_TRUE(pairs.ok());
  ASSERT_EQ(pairs->gt.size(), 1u);
  EXPECT_DOUBLE_EQ(pairs->gt[0].t_s, 0.5);
}

TEST(AssociateTest, NoOverlapNamesBothFiles) {
  const Trajectory gt = helix(10);
  Trajectory est = gt;
  est.name = "late.txt";
  for (StampedPose& p : est.poses) p.t_s += 1000.0;
  const Result<PosePairs> pairs = associate(gt, est, 0.01);
  ASSERT_FALSE(pairs.ok());
  EXPECT_NE(pairs.status().message().find("late.txt"), std::string::npos);
  EXPECT_NE(pairs.status().message().find("helix"), std::string::npos);
}

std::vector<StampedPose> straight_line(std::size_t n) {
  std::vector<StampedPose> poses(n);
  for (std::size_t i = 0; i < n; ++i) poses[i].p_wb.x() = static_cast<double>(i);
  return poses;
}

TEST(RpeTest, PairsByFramesAndByTravelledDistance) {
  const std::vector<StampedPose> poses = straight_line(10);
  RpeOptions frames;
  frames.delta = 4;
  EXPECT_EQ(*select_rpe_pairs(poses, frames), (IndexPairs{{0, 4}, {4, 8}}));

  // Taken whenever 2.5 m have been travelled since the last taken pose (or the start).
  RpeOptions metres;
  metres.delta = 2.5;
  metres.unit = DeltaUnit::kMeters;
  EXPECT_EQ(*select_rpe_pairs(poses, metres), (IndexPairs{{3, 6}, {6, 9}}));

  frames.delta = 1.5;
  EXPECT_FALSE(select_rpe_pairs(poses, frames).ok());
}

TEST(RpeTest, RigidMotionOfTheEstimateGivesZero) {
  const Trajectory gt = helix();
  const Trajectory est = transformed(gt, rot(0.7, Eigen::Vector3d(0, 1, 1)), Eigen::Vector3d(3, 2, 1), 1.0);
  Result<PosePairs> pairs = associate(gt, est, 0.01);
  ASSERT_TRUE(pairs.ok());
  for (DeltaUnit unit : {DeltaUnit::kFrames, DeltaUnit::kMeters}) {
    RpeOptions options;
    options.unit = unit;
    options.delta = 2;
    const Result<RpeResult> rpe = compute_rpe(*pairs, options);
    ASSERT_TRUE(rpe.ok()) << rpe.status().to_string();
    EXPECT_GT(rpe->pairs.size(), 5u);
    EXPECT_NEAR(rpe->trans_m.max, 0.0, 1e-9);
    EXPECT_NEAR(rpe->rot_deg.max, 0.0, 1e-5);
  }
}

TEST(RpeTest, DoubledStepsGiveTheStepLength) {
  // Same orientations, positions twice as far apart: E = Q_rel^-1 P_rel has translation
  // R_j^T (q_j - q_i), whose length is the ground-truth step.
  const Trajectory gt = helix();
  Trajectory est = gt;
  for (StampedPose& p : est.poses) p.p_wb *= 2.0;
  Result<PosePairs> pairs = associate(gt, est, 0.01);
  ASSERT_TRUE(pairs.ok());
  RpeOptions options;  // 1 frame
  const Result<RpeResult> rpe = compute_rpe(*pairs, options);
  ASSERT_TRUE(rpe.ok());
  ASSERT_EQ(rpe->pairs.size(), 49u);
  const double step = (gt.poses[1].p_wb - gt.poses[0].p_wb).norm();  // the same for every step
  EXPECT_NEAR(rpe->trans_m.min, step, 1e-12);
  EXPECT_NEAR(rpe->trans_m.max, step, 1e-12);
  EXPECT_NEAR(rpe->rot_deg.max, 0.0, 1e-6);

  options.delta = 100;
  const Result<RpeResult> too_long = compute_rpe(*pairs, options);
  ASSERT_FALSE(too_long.ok());
  EXPECT_NE(too_long.status().message().find("smaller delta"), std::string::npos);
}

Trajectory at_times(std::initializer_list<double> times) {
  Trajectory t;
  t.name = "t";
  for (double s : times) t.poses.push_back(StampedPose{s, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()});
  return t;
}

TEST(CoverageTest, GapsMarkersAndEarlyEndAreLosses) {
  const Trajectory gt = at_times({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10});
  Trajectory est = at_times({0, 1, 2, 3, 7, 8, 9});
  Result<CoverageResult> c = compute_coverage(gt, est, 1.5);
  ASSERT_TRUE(c.ok());
  EXPECT_DOUBLE_EQ(c->coverage, 0.5);  // [0,3] and [7,9]
  EXPECT_EQ(c->losses, 1u);            // the 3..7 gap; 9..10 is shorter than 1.5

  est.loss_marks_s.push_back(8.5);
  c = compute_coverage(gt, est, 1.5);
  EXPECT_DOUBLE_EQ(c->coverage, 0.4);
  EXPECT_EQ(c->losses, 2u);

  // Tracking stops for good at 5: one loss. A late start is not a loss.
  c = compute_coverage(gt, at_times({2, 3, 4, 5}), 1.5);
  EXPECT_DOUBLE_EQ(c->coverage, 0.3);
  EXPECT_EQ(c->losses, 1u);

  // Default threshold: five times the median spacing (1 s here).
  c = compute_coverage(gt, at_times({0, 1, 2, 3, 4, 10}), 0.0);
  EXPECT_DOUBLE_EQ(c->max_gap_s, 5.0);
  EXPECT_EQ(c->losses, 1u);
  EXPECT_DOUBLE_EQ(c->coverage, 0.4);
}

}  // namespace
}  // namespace ale::eval
