#include "app/tools/lib/eval/trajectory.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <string>

#include "tests/host/support/test_data.h"

namespace ale::eval {
namespace {

Result<Trajectory> parse(const std::string& text, TrajectoryFormat format = TrajectoryFormat::kAuto) {
  ReadOptions options;
  options.format = format;
  return parse_trajectory(text, options, "test.txt");
}

// The parse must fail with a message naming the file, the line and the problem.
void expect_error(const std::string& text, const std::string& line, const std::string& problem,
                  TrajectoryFormat format = TrajectoryFormat::kAuto) {
  const Result<Trajectory> t = parse(text, format);
  ASSERT_FALSE(t.ok()) << text;
  const std::string& message = t.status().message();
  EXPECT_NE(message.find("test.txt:" + line + ":"), std::string::npos) << message;
  EXPECT_NE(message.find(problem), std::string::npos) << message;
}

TEST(TrajectoryTest, ReadsTumWithQuaternionXyzw) {
  // 90 degrees about z: q = (0, 0, sin 45, cos 45) in x y z w order.
  const double h = std::sqrt(0.5);
  const Result<Trajectory> t = parse("# timestamp tx ty tz qx qy qz qw\n"
                                     "10.0 1 2 3 0 0 0 1\n"
                                     "10.5 4 5 6 0 0 " + std::to_string(h) + " " + std::to_string(h) + "\n");
  ASSERT_TRUE(t.ok()) << t.status().to_string();
  EXPECT_EQ(t->format, TrajectoryFormat::kTum);
  ASSERT_EQ(t->poses.size(), 2u);
  EXPECT_DOUBLE_EQ(t->poses[1].t_s, 10.5);
  EXPECT_TRUE(t->poses[1].p_wb.isApprox(Eigen::Vector3d(4, 5, 6)));
  EXPECT_NEAR((t->poses[1].R_wb * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-6);
}

TEST(TrajectoryTest, ReadsEurocWithQuaternionWFirstAndNanoseconds) {
  const double h = std::sqrt(0.5);
  const Result<Trajectory> t = parse(
      "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z []\n"
      "1403715524907143168, 1, 2, 3, " + std::to_string(h) + ", 0, 0, " + std::to_string(h) + "\n");
  ASSERT_TRUE(t.ok()) << t.status().to_string();
  EXPECT_EQ(t->format, TrajectoryFormat::kEuroc);
  EXPECT_NEAR(t->poses[0].t_s, 1403715524.907143168, 1e-6);
  EXPECT_NEAR((t->poses[0].R_wb * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-6);
}

TEST(TrajectoryTest, ReadsKittiWithLineIndexAsTime) {
  const Result<Trajectory> t = parse("1 0 0 1 0 1 0 2 0 0 1 3\n"
                                     "0 -1 0 4 1 0 0 5 0 0 1 6\n");
  ASSERT_TRUE(t.ok()) << t.status().to_string();
  EXPECT_EQ(t->format, TrajectoryFormat::kKitti);
  EXPECT_DOUBLE_EQ(t->poses[0].t_s, 0.0);
  EXPECT_DOUBLE_EQ(t->poses[1].t_s, 1.0);
  EXPECT_TRUE(t->poses[1].p_wb.isApprox(Eigen::Vector3d(4, 5, 6)));
  EXPECT_DOUBLE_EQ(t->poses[1].R_wb(0, 1), -1.0);  // row-major
  EXPECT_DOUBLE_EQ(t->poses[1].R_wb(1, 0), 1.0);
}

TEST(TrajectoryTest, ReadsLossMarkers) {
  const Result<Trajectory> t = parse("0 0 0 0 0 0 0 1\n# lost 0.5\n1 0 0 0 0 0 0 1\n");
  ASSERT_TRUE(t.ok()) << t.status().to_string();
  ASSERT_EQ(t->loss_marks_s.size(), 1u);
  EXPECT_DOUBLE_EQ(t->loss_marks_s[0], 0.5);
}

TEST(TrajectoryTest, RejectsWrongColumnCount) {
  expect_error("0 0 0 0 0 0 0 1\n1 0 0 0 0 0 1\n", "2", "7 columns, expected 8");
  expect_error("1 0 0 1 0 1 0 2 0 0 1\n", "1", "11 columns, expected 12", TrajectoryFormat::kKitti);
  expect_error("1,2,3,4,1,0,0,0\n2,2,3,4,1,0,0\n", "2", "7 columns");
}

TEST(TrajectoryTest, RejectsNanInfAndText) {
  expect_error("0 0 0 0 0 0 0 1\n1 nan 0 0 0 0 0 1\n", "2", "column 2 is not finite");
  expect_error("0 0 0 inf 0 0 0 1\n", "1", "column 4 is not finite");
  expect_error("0 0 0 0 0 0 0 1\n1 0 x 0 0 0 0 1\n", "2", "column 3 'x' is not a number");
}

TEST(TrajectoryTest, RejectsUnsortedAndDuplicateTimestamps) {
  expect_error("1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n", "2", "timestamps must increase");
  expect_error("1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", "2", "duplicate timestamp");
}

TEST(TrajectoryTest, SkipsDuplicatesOnlyWhenAsked) {
  ReadOptions options;
  options.skip_duplicate_times = true;
  const Result<Trajectory> t = parse_trajectory("1 0 0 0 0 0 0 1\n1 5 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n",
                                                options, "test.txt");
  ASSERT_TRUE(t.ok()) << t.status().to_string();
  EXPECT_EQ(t->poses.size(), 2u);
  EXPECT_EQ(t->duplicates_skipped, 1u);
  EXPECT_DOUBLE_EQ(t->poses[0].p_wb.x(), 0.0);  // the first one is kept
}

TEST(TrajectoryTest, RejectsEmptyFilesZeroQuaternionsAndUnknownLayouts) {
  EXPECT_FALSE(parse("").ok());
  EXPECT_NE(parse("# only a comment\n\n").status().message().find("no poses"), std::string::npos);
  expect_error("0 0 0 0 0 0 0 0\n", "1", "quaternion has zero length");
  expect_error("0 0 0 0 0\n", "1", "cannot tell the format");
}

TEST(TrajectoryTest, MissingFileIsNotFound) {
  const Result<Trajectory> t = read_trajectory("/nonexistent/ale/traj.txt");
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.status().code(), StatusCode::kNotFound);
  EXPECT_NE(t.status().message().find("/nonexistent/ale/traj.txt"), std::string::npos);
}

TEST(TrajectoryTest, ParsesFormatNames) {
  EXPECT_EQ(*parse_format("euroc"), TrajectoryFormat::kEuroc);
  EXPECT_FALSE(parse_format("csv").ok());
}

TEST(TrajectoryTest, ReadsRealEurocStateGroundTruth) {
  ALE_REQUIRE_DATA(path, "euroc_v101_micro/mav0/state_groundtruth_estimate0/data.csv");
  const Result<Trajectory> t = read_trajectory(path);
  ASSERT_TRUE(t.ok()) << t.status().to_string();
  EXPECT_EQ(t->format, TrajectoryFormat::kEuroc);
  ASSERT_EQ(t->poses.size(), 95u);
  // First row: 1403715273262142976, 0.878895, 2.1834, 0.948427, q = (0.069433, -0.824237, ...).
  EXPECT_NEAR(t->poses[0].t_s, 1403715273.262142976, 1e-6);
  EXPECT_NEAR(t->poses[0].p_wb.y(), 2.1834, 1e-12);
  const Eigen::Quaterniond q(t->poses[0].R_wb);
  EXPECT_NEAR(std::abs(q.w()), 0.069433, 1e-5);
  EXPECT_NEAR(std::abs(q.x()), 0.824237, 1e-5);
}

}  // namespace
}  // namespace ale::eval
