// Agreement with the numbers evo stored for its own test data
// (../shared/data/evo_reference/REFERENCE.txt).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include "app/tools/lib/eval/align.h"
#include "app/tools/lib/eval/associate.h"
#include "app/tools/lib/eval/metrics.h"
#include "app/tools/lib/eval/trajectory.h"
#include "tests/host/support/test_data.h"

namespace ale::eval {
namespace {

constexpr double kRelTol = 1e-6;

// What REFERENCE.txt lists for one metric.
struct EvoStats {
  double rmse, mean, median, max, min, std;
};

void expect_agreement(const ErrorStats& got, const EvoStats& evo) {
  const std::pair<const char*, std::pair<double, double>> rows[] = {
      {"rmse", {got.rmse, evo.rmse}}, {"mean", {got.mean, evo.mean}}, {"median", {got.median, evo.median}},
      {"max", {got.max, evo.max}},    {"min", {got.min, evo.min}},    {"std", {got.std, evo.std}}};
  for (const auto& [name, values] : rows) {
    EXPECT_NEAR(values.first, values.second, kRelTol * std::abs(values.second)) << name;
  }
}

PosePairs load_pairs(const std::string& gt_path, const std::string& est_path) {
  Result<Trajectory> gt = read_trajectory(gt_path);
  EXPECT_TRUE(gt.ok()) << gt.status().to_string();
  Result<Trajectory> est = read_trajectory(est_path);
  EXPECT_TRUE(est.ok()) << est.status().to_string();
  if (!gt.ok() || !est.ok()) return {};
  Result<PosePairs> pairs = associate(*gt, *est, 0.01);
  EXPECT_TRUE(pairs.ok()) << pairs.status().to_string();
  return pairs.ok() ? *pairs : PosePairs{};
}

// evo_ape kitti KITTI_00_gt.txt KITTI_00_ORB.txt --align (translation part).
TEST(EvoReferenceTest, KittiApeSe3) {
  ALE_REQUIRE_DATA(dir, "evo_reference");
  PosePairs pairs = load_pairs(dir + "/KITTI_00_gt.txt", dir + "/KITTI_00_ORB.txt");
  ASSERT_EQ(pairs.gt.size(), 4541u);
  const Result<Sim3> sim3 = align_estimate(Alignment::kSe3, &pairs);
  ASSERT_TRUE(sim3.ok()) << sim3.status().to_string();
  const Result<AteResult> ate = compute_ate(pairs);
  ASSERT_TRUE(ate.ok()) << ate.status().to_string();
  expect_agreement(ate->trans_m, {1.3034497145650266, 1.1569971285389768, 1.065624769555848,
                                  3.587949120678954, 0.06931322021483087, 0.6002822693968323});
}

// evo_rpe kitti KITTI_00_gt.txt KITTI_00_ORB.txt --delta 10 --delta_unit m (translation part,
// consecutive pairs, no alignment). evo picks the pairs on the estimate's path by default.
TEST(EvoReferenceTest, KittiRpe10Metres) {
  ALE_REQUIRE_DATA(dir, "evo_reference");
  const PosePairs pairs = load_pairs(dir + "/KITTI_00_gt.txt", dir + "/KITTI_00_ORB.txt");
  RpeOptions options;
  options.delta = 10.0;
  options.unit = DeltaUnit::kMeters;
  const Result<RpeResult> rpe = compute_rpe(pairs, options);
  ASSERT_TRUE(rpe.ok()) << rpe.status().to_string();
  expect_agreement(rpe->trans_m, {0.22626134329310163, 0.16901737200653275, 0.13848432516645606,
                                  1.2722090778658726, 0.025322719660754993, 0.1504238127053164});

  // Selecting the pairs on the ground-truth path (evo's --pairs_from_reference) is a
  // different measurement: it must not reproduce the numbers above.
  options.pairs_from_gt = true;
  const Result<RpeResult> from_gt = compute_rpe(pairs, options);
  ASSERT_TRUE(from_gt.ok());
  EXPECT_GT(std::abs(from_gt->trans_m.rmse - 0.22626134329310163), 1e-3);
}

// The same EuRoC V1_02 ground truth as state CSV (ns, quaternion w first) and as TUM (s,
// quaternion w last): reading both must give identical poses.
TEST(EvoReferenceTest, EurocCsvAndTumReadersAgree) {
  ALE_REQUIRE_DATA(csv, "evo_reference/V102_groundtruth.csv");
  ALE_REQUIRE_DATA(tum, "euroc_groundtruth/V1_02_medium.txt");
  PosePairs pairs = load_pairs(csv, tum);
  ASSERT_EQ(pairs.gt.size(), 16702u);
  const Result<AteResult> ate = compute_ate(pairs);
  ASSERT_TRUE(ate.ok());
  EXPECT_LT(ate->trans_m.max, 1e-9);
  EXPECT_LT(ate->rot_deg.max, 1e-4);
}

TEST(EvoReferenceTest, DisjointTimeRangesAreAnError) {
  ALE_REQUIRE_DATA(dir, "evo_reference");
  Result<Trajectory> kitti = read_trajectory(dir + "/KITTI_00_gt.txt");
  Result<Trajectory> tum = read_trajectory(dir + "/freiburg1_xyz-groundtruth.txt");
  ASSERT_TRUE(kitti.ok() && tum.ok());
  const Result<PosePairs> pairs = associate(*kitti, *tum, 0.01);
  ASSERT_FALSE(pairs.ok());
  EXPECT_NE(pairs.status().message().find("no overlap"), std::string::npos);
}

}  // namespace
}  // namespace ale::eval
