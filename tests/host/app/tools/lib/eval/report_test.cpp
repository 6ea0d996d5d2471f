#include "app/tools/lib/eval/report.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <set>
#include <string>

namespace ale::eval {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

struct Fixture {
  Trajectory gt;
  PosePairs pairs;
  ReportInput input;

  Fixture() {
    gt.name = "gt.txt";
    for (int k = 0; k < 20; ++k) {
      StampedPose p;
      p.t_s = k;
      p.p_wb = Eigen::Vector3d(k, 0.1 * k * k, 0.0);  // planar in x-y: the view drops z
      gt.poses.push_back(p);
    }
    pairs.gt = gt.poses;
    pairs.est = gt.poses;
    pairs.est.erase(pairs.est.begin() + 8, pairs.est.begin() + 14);  // a 7 s gap
    input.title = "ATE <se3>";
    input.figures = {{"ate_rmse", "0.5"}, {"estimate", "a&b.txt"}};
    input.gt = &gt;
    input.aligned = &pairs;
    input.max_gap_s = 2.0;
    for (const StampedPose& p : pairs.est) {
      input.error_t_s.push_back(p.t_s);
      input.error_values.push_back(0.5);
    }
    input.error_label = "ATE [m]";
  }
};

TEST(ReportTest, PageHasBothPlotsEscapedTextAndABrokenEstimatePath) {
  Fixture f;
  const Result<std::string> html = render_report_html(f.input);
  ASSERT_TRUE(html.ok()) << html.status().to_string();
  EXPECT_EQ(count(*html, "<svg"), 2u);
  EXPECT_NE(html->find("ATE &lt;se3&gt;"), std::string::npos);
  EXPECT_NE(html->find("a&amp;b.txt"), std::string::npos);
  EXPECT_NE(html->find(">x [m]<"), std::string::npos);
  EXPECT_NE(html->find(">y [m]<"), std::string::npos);
  EXPECT_NE(html->find("rmse 0.5"), std::string::npos);
  // Ground truth, the estimate in two runs (split at the gap), rmse line and error curve.
  EXPECT_EQ(count(*html, "<polyline"), 5u);
}

const std::string kSmallLog = std::string(ALE_EVAL_TEST_DATA_DIR) + "/frame_log_small.csv";

TEST(ReportTest, FrameLogAloneGivesOnePlotPerSeries) {
  const Result<FrameLog> log = read_frame_log(kSmallLog);
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  ReportInput input;
  input.title = "Frame log";
  input.frame_log = &*log;
  const Result<std::string> html = render_report_html(input);
  ASSERT_TRUE(html.ok()) << html.status().to_string();
  // Brightness band, mean intensity, features, inliers, frame time, tracking-state band.
  EXPECT_EQ(count(*html, "<svg"), 6u);
  EXPECT_EQ(count(*html, ">time since first frame [s]<"), 6u);
  EXPECT_EQ(count(*html, ">frame time [ms]<"), 1u);
  EXPECT_NE(html->find("VIA threshold 10"), std::string::npos);
  EXPECT_NE(html->find("p95 30 ms"), std::string::npos);
  // One stripe per run: the two lost runs (frames 4-5 and 8) in the lost colour.
  EXPECT_EQ(count(*html, "fill=\"#d62728\""), 2u);
  // Six brightness runs and eight state runs.
  EXPECT_EQ(count(*html, "<rect x=") - 2 * 6, 14u);  // each plot also has a frame and a clip rect
}

TEST(ReportTest, FrameLogWithTheSlamColumnsAddsMapAndStageTimePlots) {
  Result<FrameLog> log = read_frame_log(kSmallLog);
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  EXPECT_FALSE(log->has_slam_columns);
  log->has_slam_columns = true;
  for (std::size_t i = 0; i < log->frames.size(); ++i) {
    log->frames[i].keyframes = static_cast<int>(i);
    log->frames[i].mapping_ms = 2.0 * static_cast<double>(i);
  }
  ReportInput input;
  input.title = "Frame log";
  input.frame_log = &*log;
  const Result<std::string> html = render_report_html(input);
  ASSERT_TRUE(html.ok()) << html.status().to_string();
  // The six of the frame log, then keyframes, map points, front end, tracking, mapping.
  EXPECT_EQ(count(*html, "<svg"), 11u);
  EXPECT_EQ(count(*html, ">mapping [ms]<"), 1u);
  EXPECT_EQ(count(*html, ">keyframes<"), 1u);
}

TEST(ReportTest, FrameLogSharesTheErrorPlotsTimeAxis) {
  Fixture f;
  const Result<FrameLog> log = read_frame_log(kSmallLog);
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  f.input.frame_log = &*log;
  const Result<std::string> html = render_report_html(f.input);
  ASSERT_TRUE(html.ok()) << html.status().to_string();
  EXPECT_EQ(count(*html, "<svg"), 8u);
  EXPECT_EQ(count(*html, ">time since ground-truth start [s]<"), 7u);
  // The error plot and the frame plots put the x tick at 15 s (ticks 0, 5, 10, 15 for 0..19 s)
  // at the same pixel column.
  const std::string tick = "\" text-anchor=\"middle\">15</text>";
  std::set<std::string> columns;
  std::size_t ticks = 0;
  for (std::size_t at = html->find(tick); at != std::string::npos; at = html->find(tick, at + 1), ++ticks) {
    const std::size_t x = html->rfind("<text x=\"", at) + 9;
    columns.insert(html->substr(x, html->find('"', x) - x));
  }
  EXPECT_EQ(ticks, 7u);
  EXPECT_EQ(columns.size(), 1u);
}

// Whether the pixel (x, y), formatted as the page formats it, is a point of the estimate's path.
::testing::AssertionResult on_estimate_path(const std::string& html, const std::string& x, const std::string& y) {
  const std::size_t estimate = html.find("stroke=\"#d62728\" stroke-width=\"1.2\" points=\"");
  if (estimate == std::string::npos) return ::testing::AssertionFailure() << "no estimate path";
  if (html.find(" " + x + "," + y + " ", estimate) == std::string::npos) {
    return ::testing::AssertionFailure() << x << "," << y << " is not on the estimate's path";
  }
  return ::testing::AssertionSuccess();
}

// Whether the first polygon marker of class css_class is centred on a point of the estimate's
// path: its first corner straight above the centre (the centre's x), its second corner dy px below
// the centre.
::testing::AssertionResult polygon_on_estimate_path(const std::string& html, const std::string& css_class, double dy) {
  const std::size_t polygon = html.find("<polygon class=\"" + css_class + "\" points=\"");
  if (polygon == std::string::npos) return ::testing::AssertionFailure() << "no " << css_class << " polygon";
  const std::size_t first = html.find("points=\"", polygon) + 8;
  const std::string x = html.substr(first, html.find(',', first) - first);
  const std::size_t second = html.find(',', html.find(' ', first) + 1) + 1;
  char y[32];
  std::snprintf(y, sizeof y, "%.1f", std::stod(html.substr(second, html.find(' ', second) - second)) - dy);
  return on_estimate_path(html, x, y);
}

// A log of frames 1..19 at k seconds, tracking in map 1, with the SLAM core's and place
// recognition's columns; `fill` sets frame k's events.
FrameLog event_log(const char* name, void (*fill)(int k, FrameRecord& r)) {
  FrameLog log;
  log.name = name;
  log.has_slam_columns = true;
  log.has_place_column = true;
  for (int k = 1; k < 20; ++k) {
    FrameRecord r;
    r.timestamp_ns = static_cast<std::uint64_t>(k) * 1000000000ull;
    r.sequence = static_cast<std::uint64_t>(k);
    r.state = TrackingState::kTracking;
    r.map_id = 1;
    fill(k, r);
    log.frames.push_back(r);
  }
  return log;
}

// The fixture's estimate has poses at 0..7 s and 14..19 s. The log: tracking in map 1, lost at
// 3 s, relocalised at 4 s (ring at the estimate's pose at 4 s), relocalised again at 10 s (no
// aligned pose then: counted, not drawn), map 2 from 15 s, its first pose at 16 s (square there).
TEST(ReportTest, TheTopViewMarksRelocalisationsAndNewMapsFromTheFrameLog) {
  Fixture f;
  const FrameLog log = event_log("events.csv", [](int k, FrameRecord& r) {
    r.state = k == 3 ? TrackingState::kLost : k == 4 || k == 10 ? TrackingState::kRelocalized : TrackingState::kTracking;
    r.map_id = k < 15 ? 1 : 2;
    if (k == 15) r.state = TrackingState::kInitializing;
    r.place_ms = r.state == TrackingState::kRelocalized ? 6.0 : 0.5;
  });
  f.input.frame_log = &log;
  const Result<std::string> html = render_report_html(f.input);
  ASSERT_TRUE(html.ok()) << html.status().to_string();
  EXPECT_EQ(count(*html, "<circle class=\"relocalisation\""), 1u);
  EXPECT_EQ(count(*html, "<rect class=\"new-map\""), 1u);
  EXPECT_NE(html->find("relocalised frame (1, rings)"), std::string::npos);
  EXPECT_NE(html->find("first pose of a new map (1, squares); 1 events without an aligned pose"), std::string::npos);
  // The ring is centred on a point of the estimate's path (the same pixel formatting).
  const std::size_t ring = html->find("<circle class=\"relocalisation\"");
  ASSERT_NE(ring, std::string::npos);
  const std::size_t cx = html->find("cx=\"", ring) + 4;
  const std::string x = html->substr(cx, html->find('"', cx) - cx);
  const std::size_t cy = html->find("cy=\"", cx) + 4;
  const std::string y = html->substr(cy, html->find('"', cy) - cy);
  EXPECT_TRUE(on_estimate_path(*html, x, y));
  // The place-recognition plot, with a line at both relocalised frames.
  EXPECT_EQ(count(*html, ">place recognition [ms]<"), 1u);
  EXPECT_EQ(count(*html, "<line class=\"relocalisation\""), 2u);
}

// The fixture's estimate has poses at 0..7 s and 14..19 s. The log (with the loop columns): one
// loop closed at 5 s (a diamond at the estimate's pose there), one at 10 s (no aligned pose:
// counted, not drawn), two more at 16 s (one frame, one diamond).
TEST(ReportTest, LoopsClosedAreMarkedOnTheTopViewAndOverTime) {
  Fixture f;
  FrameLog log = event_log("loops.csv", [](int k, FrameRecord& r) {
    r.loops = k < 5 ? 0 : k < 10 ? 1 : k < 16 ? 2 : 4;
    r.loop_ms = k == 5 || k == 10 || k == 16 ? 30.0 : 0.4;
  });
  log.has_loop_columns = true;
  f.input.frame_log = &log;
  Result<std::string> html = render_report_html(f.input);
  ASSERT_TRUE(html.ok()) << html.status().to_string();
  EXPECT_EQ(count(*html, "<polygon class=\"loop-closure\""), 2u);
  EXPECT_NE(html->find("frame a loop was closed on (2, diamonds)"), std::string::npos);
  EXPECT_NE(html->find("1 events without an aligned pose"), std::string::npos);
  // The diamond around 5 s (its right corner at the centre's height) is centred on the estimate's path.
  EXPECT_TRUE(polygon_on_estimate_path(*html, "loop-closure", 0.0));
  // A line at each of the three frames on the error, frame time, map points, mapping and
  // loop-closing plots, and the loop-closing plot itself.
  EXPECT_EQ(count(*html, "<line class=\"loop-closure\""), 15u);
  EXPECT_EQ(count(*html, "loop closed (3)"), 5u);
  EXPECT_EQ(count(*html, ">loop closing [ms]<"), 1u);
  EXPECT_EQ(count(*html, "<h2>Loop closing</h2>"), 1u);

  // A log without the loop columns (an older daemon's): nothing marked, no loop plot.
  log.has_loop_columns = false;
  html = render_report_html(f.input);
  ASSERT_TRUE(html.ok()) << html.status().to_string();
  EXPECT_EQ(count(*html, "loop-closure"), 0u);
  EXPECT_EQ(count(*html, "loop clos"), 0u);
}

// The fixture's estimate has poses at 0..7 s and 14..19 s. The log (with the loop and merge
// columns): map 1, a new map 2 from 15 s (its first pose at 16 s: a square), moved into map 1 by a
// merge at 17 s (a triangle at the estimate's pose there; not a new map), a merge refused at 18 s
// (not marked); no loop closed.
TEST(ReportTest, MapsMergedAreMarkedOnTheTopView) {
  Fixture f;
  FrameLog log = event_log("merges.csv", [](int k, FrameRecord& r) {
    r.map_id = k == 15 || k == 16 ? 2 : 1;
    if (k == 15) r.state = TrackingState::kInitializing;
    r.merges = k < 17 ? 0 : 1;
    r.merges_refused = k < 18 ? 0 : 1;
  });
  log.has_loop_columns = true;
  log.has_merge_columns = true;
  f.input.frame_log = &log;
  Result<std::string> html = render_report_html(f.input);
  ASSERT_TRUE(html.ok()) << html.status().to_string();
  EXPECT_EQ(count(*html, "<polygon class=\"map-merge\""), 1u);
  EXPECT_NE(html->find("frame a map was merged on (1, triangles)"), std::string::npos);
  EXPECT_EQ(count(*html, "<rect class=\"new-map\""), 1u);
  EXPECT_NE(html->find("first pose of a new map (1, squares)"), std::string::npos);
  EXPECT_NE(html->find("frame a loop was closed on (0, diamonds)"), std::string::npos);
  // The triangle (its base 4 px below its centre) is centred on the estimate's path.
  EXPECT_TRUE(polygon_on_estimate_path(*html, "map-merge", 4.0));

  // A log without the merge columns (an older daemon's): nothing marked, the return to map 1 a new map.
  log.has_merge_columns = false;
  html = render_report_html(f.input);
  ASSERT_TRUE(html.ok()) << html.status().to_string();
  EXPECT_EQ(count(*html, "map-merge"), 0u);
  EXPECT_EQ(count(*html, "merged"), 0u);
  EXPECT_EQ(count(*html, "<rect class=\"new-map\""), 2u);
}

TEST(ReportTest, FrameLogNeedsATimedGroundTruth) {
  Fixture f;
  f.gt.format = TrajectoryFormat::kKitti;
  const Result<FrameLog> log = read_frame_log(kSmallLog);
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  f.input.frame_log = &*log;
  EXPECT_FALSE(render_report_html(f.input).ok());
  FrameLog empty;
  ReportInput alone;
  alone.frame_log = &empty;
  EXPECT_FALSE(render_report_html(alone).ok());
  EXPECT_FALSE(render_report_html(ReportInput{}).ok());
}

TEST(ReportTest, RejectsMissingOrMismatchedInput) {
  Fixture f;
  f.input.error_values.pop_back();
  EXPECT_FALSE(render_report_html(f.input).ok());
  Fixture g;
  g.input.aligned = nullptr;
  EXPECT_FALSE(render_report_html(g.input).ok());
  Fixture h;
  EXPECT_FALSE(write_report("/nonexistent/dir/report.html", h.input).ok());
}

}  // namespace
}  // namespace ale::eval
