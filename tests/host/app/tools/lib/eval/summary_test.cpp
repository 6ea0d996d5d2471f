#include "app/tools/lib/eval/summary.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "app/tools/lib/eval/report.h"

namespace ale::eval {
namespace {

TEST(SummaryTest, RoundsToSignificantDigitsWithoutTrailingZeros) {
  EXPECT_EQ(round_significant(0.03214, 2), "0.032");
  EXPECT_EQ(round_significant(3.214, 2), "3.2");
  EXPECT_EQ(round_significant(14.3, 2), "14");
  EXPECT_EQ(round_significant(1234.0, 2), "1234");  // whole numbers keep their digits
  EXPECT_EQ(round_significant(9.96, 2), "10");      // the carry into the next power of ten
  EXPECT_EQ(round_significant(0.996, 2), "1");
  EXPECT_EQ(round_significant(3.0, 2), "3");
  EXPECT_EQ(round_significant(0.0, 2), "0");
  EXPECT_EQ(round_significant(-0.0456, 2), "-0.046");
  EXPECT_EQ(round_significant(std::nan(""), 2), "n/a");
}

TEST(SummaryTest, PercentKeepsAShareShortOfAllOrNoneApart) {
  EXPECT_EQ(percent(0.934), "93");
  EXPECT_EQ(percent(1.0), "100");
  EXPECT_EQ(percent(0.996), "99.6");
  EXPECT_EQ(percent(0.0), "0");
  EXPECT_EQ(percent(0.004), "0.4");
}

TEST(SummaryTest, PathLengthSumsTheSteps) {
  std::vector<StampedPose> poses(3);
  poses[1].p_wb = Eigen::Vector3d(3.0, 4.0, 0.0);
  poses[2].p_wb = Eigen::Vector3d(3.0, 4.0, 2.0);
  EXPECT_DOUBLE_EQ(path_length_m(poses), 7.0);
  EXPECT_DOUBLE_EQ(path_length_m({}), 0.0);
}

FrameLogSummary small_log() {
  const Result<FrameLog> log = read_frame_log(std::string(ALE_EVAL_TEST_DATA_DIR) + "/frame_log_small.csv");
  EXPECT_TRUE(log.ok()) << log.status().to_string();
  return summarize(*log);
}

TEST(SummaryTest, AteTrackedShareAndFrameTimeInThreeLines) {
  ErrorStats ate;
  ate.rmse = 0.03214;
  const FrameLogSummary frames = small_log();
  SummaryInput in;
  in.ate_m = &ate;
  in.alignment = Alignment::kSim3;
  in.path_m = 4.02;
  in.pairs = 280;
  in.frames = &frames;
  const std::vector<std::string> lines = summary_lines(in);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "ATE 3.2 cm (RMSE after sim3 alignment), 0.8 % of the 4 m path over 280 poses");
  // frames 2, 3, 7 and 9 of the ten are in state tracking and 6 relocalised (posed too); lost
  // at 4 and at 8; 5..13 and 30 ms
  EXPECT_EQ(lines[1], "tracked 50 % of the frames (5 of 10), 2 tracking losses, 1 relocalisation, 1 map");
  EXPECT_EQ(lines[2], "frame time 9.5 ms median, 30 ms p95 (on this machine)");
}

// A log with the loop columns names the loops closed (none too) and, with one, the longest frame
// a loop was closed on.
TEST(SummaryTest, LoopsClosedAndTheLongestClosingFrame) {
  FrameLogSummary frames = small_log();
  frames.loops_logged = true;
  SummaryInput in;
  in.frames = &frames;
  std::vector<std::string> lines = summary_lines(in);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "tracked 50 % of the frames (5 of 10), 2 tracking losses, 1 relocalisation, 0 loops closed, 1 map");
  EXPECT_EQ(lines[1], "frame time 9.5 ms median, 30 ms p95 (on this machine)");
  frames.loops_closed = 1;
  frames.loop_frame_time_max_ms = 41.27;
  lines = summary_lines(in);
  EXPECT_EQ(lines[0], "tracked 50 % of the frames (5 of 10), 2 tracking losses, 1 relocalisation, 1 loop closed, 1 map");
  EXPECT_EQ(lines[1], "frame time 9.5 ms median, 30 ms p95, 41 ms at the longest loop closure (on this machine)");
}

// A log with the merge columns names the maps merged (none too), after the loops closed.
TEST(SummaryTest, MapsMerged) {
  FrameLogSummary frames = small_log();
  frames.merges_logged = true;
  SummaryInput in;
  in.frames = &frames;
  std::vector<std::string> lines = summary_lines(in);
  EXPECT_EQ(lines[0], "tracked 50 % of the frames (5 of 10), 2 tracking losses, 1 relocalisation, 0 maps merged, 1 map");
  frames.loops_logged = true;
  frames.merges = 1;
  frames.maps = 2;
  lines = summary_lines(in);
  EXPECT_EQ(lines[0],
            "tracked 50 % of the frames (5 of 10), 2 tracking losses, 1 relocalisation, 0 loops closed, 1 map merged, "
            "2 maps");
}

TEST(SummaryTest, WithoutAFrameLogTheCoverageStandsForTracking) {
  ErrorStats ate;
  ate.rmse = 0.142;
  SummaryInput in;
  in.ate_m = &ate;
  in.alignment = Alignment::kNone;
  in.path_m = 71.0;
  in.pairs = 1;
  in.coverage = 0.9996;
  in.losses = 1;
  const std::vector<std::string> lines = summary_lines(in);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "ATE 14 cm (RMSE), 0.2 % of the 71 m path over 1 pose");
  EXPECT_EQ(lines[1], "the estimate covers 99.96 % of the ground truth's time, 1 tracking loss");
}

TEST(SummaryTest, FrameLogAloneGivesTrackingAndFrameTime) {
  const FrameLogSummary frames = small_log();
  SummaryInput in;
  in.frames = &frames;
  EXPECT_EQ(summary_lines(in).size(), 2u);
}

TEST(SummaryTest, TheReportOpensWithTheSummaryAndHasTheRawTableBelow) {
  const Result<FrameLog> log = read_frame_log(std::string(ALE_EVAL_TEST_DATA_DIR) + "/frame_log_small.csv");
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  ReportInput input;
  input.title = "Frame log";
  input.frame_log = &*log;
  input.summary = {"tracked 40 % of the frames", "frame time <fast>"};
  input.figures = {{"frame_time_median_ms", "9.5"}};
  const Result<std::string> html = render_report_html(input);
  ASSERT_TRUE(html.ok()) << html.status().to_string();
  const std::size_t summary = html->find("tracked 40 % of the frames<br>\nframe time &lt;fast&gt;");
  const std::size_t table = html->find("<td>frame_time_median_ms</td><td>9.5</td>");
  ASSERT_NE(summary, std::string::npos);
  ASSERT_NE(table, std::string::npos);
  EXPECT_LT(summary, table);
  EXPECT_LT(summary, html->find("<svg"));
}

}  // namespace
}  // namespace ale::eval
