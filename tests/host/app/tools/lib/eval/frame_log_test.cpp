#include "app/tools/lib/eval/frame_log.h"

#include <gtest/gtest.h>

#include "core/base/frame_log.h"
#include "tests/host/support/test_data.h"

#include <cmath>
#include <string>

namespace ale::eval {
namespace {

const std::string kSmallLog = std::string(ALE_EVAL_TEST_DATA_DIR) + "/frame_log_small.csv";
const std::string kHeader =
    "#timestamp_ns,sequence,state,brightness,mean,sigma,gamma,clip,negative,features,inliers,frame_time_ms\n";

// A log line for frame k (k * 50 ms) with the given fields.
std::string line(int k, const char* state, const char* brightness, int features, int inliers, double ms) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%lld,%d,%s,%s,100.00,20.00,1.0000,0.000,0,%d,%d,%.3f\n",
                static_cast<long long>(k) * 50000000LL, k, state, brightness, features, inliers, ms);
  return buf;
}

// The message of the parse error for `text`, or "" when it parsed.
std::string error_of(const std::string& text) {
  const Result<FrameLog> log = parse_frame_log(text, "log.csv");
  return log.ok() ? std::string() : log.status().message();
}

TEST(FrameLogTest, ReadsTheDaemonFormatIgnoringUnknownTrailingColumns) {
  const Result<FrameLog> log = read_frame_log(kSmallLog);
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  ASSERT_EQ(log->frames.size(), 10u);
  const FrameRecord& f = log->frames[4];
  EXPECT_DOUBLE_EQ(f.t_s(), 1.4);
  EXPECT_EQ(f.sequence, 4u);
  EXPECT_EQ(f.state, TrackingState::kLost);
  EXPECT_EQ(f.brightness, BrightnessClass::kExtremelyDark);
  EXPECT_DOUBLE_EQ(f.mean, 30.0);
  EXPECT_DOUBLE_EQ(f.sigma, 10.0);
  EXPECT_DOUBLE_EQ(f.gamma, 0.55);
  EXPECT_DOUBLE_EQ(f.clip, 3.0);
  EXPECT_FALSE(f.negative);
  EXPECT_EQ(f.features, 50);
  EXPECT_EQ(f.inliers, 5);
  EXPECT_DOUBLE_EQ(f.frame_time_ms, 9.0);
  EXPECT_TRUE(log->frames[8].negative);
}

// The daemon's writer and this reader share one row type and column table: what one writes the
// other reads back (to the writer's precision).
TEST(FrameLogTest, WhatTheWriterWritesTheReaderReads) {
  const std::string path = test::make_temp_dir("frame-log-roundtrip") + "/frames.csv";
  FrameLogWriter writer;
  ASSERT_TRUE(writer.open(path).ok());
  FrameLogRow a;
  a.timestamp_ns = 1403715273262142976ull;
  a.sequence = 3;
  a.state = TrackingState::kLost;
  a.brightness = BrightnessClass::kBright;
  a.mean = 200.126;
  a.sigma = 12.5;
  a.gamma = 0.5125;
  a.clip = 2.25;
  a.negative = true;
  a.features = 812;
  a.inliers = 97;
  a.frame_time_ms = 33.125;
  a.map_id = 2;
  a.keyframes = 41;
  a.landmarks = 3120;
  a.frontend_ms = 7.25;
  a.tracking_ms = 3.5;
  a.mapping_ms = 20.125;
  a.place_ms = 1.5;
  a.loop_ms = 0.75;
  a.merges = 1;  // a merge on a, the log's first frame
  FrameLogRow b = a;
  b.timestamp_ns += 50000000;
  b.sequence = 4;
  b.place_ms = 4.25;
  b.loops = 1;  // a loop closed on b
  b.loop_ms = 12.5;
  b.merges_refused = 2;
  b.frame_time_ms = 48.5;
  b.negative = false;
  b.map_id = 3;
  ASSERT_TRUE(writer.append(a).ok());
  ASSERT_TRUE(writer.append(b).ok());
  ASSERT_TRUE(writer.close().ok());
  const Result<FrameLog> log = read_frame_log(path);
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  ASSERT_EQ(log->frames.size(), 2u);
  const FrameRecord& r = log->frames[0];
  EXPECT_EQ(r.timestamp_ns, a.timestamp_ns);
  EXPECT_EQ(r.sequence, 3u);
  EXPECT_EQ(r.state, TrackingState::kLost);
  EXPECT_EQ(r.brightness, BrightnessClass::kBright);
  EXPECT_DOUBLE_EQ(r.mean, 200.13);  // 2 decimals
  EXPECT_DOUBLE_EQ(r.sigma, 12.5);
  EXPECT_DOUBLE_EQ(r.gamma, 0.5125);
  EXPECT_DOUBLE_EQ(r.clip, 2.25);
  EXPECT_TRUE(r.negative);
  EXPECT_EQ(r.features, 812);
  EXPECT_EQ(r.inliers, 97);
  EXPECT_DOUBLE_EQ(r.frame_time_ms, 33.125);
  EXPECT_EQ(r.map_id, 2u);
  EXPECT_EQ(r.keyframes, 41);
  EXPECT_EQ(r.landmarks, 3120);
  EXPECT_DOUBLE_EQ(r.frontend_ms, 7.25);
  EXPECT_DOUBLE_EQ(r.tracking_ms, 3.5);
  EXPECT_DOUBLE_EQ(r.mapping_ms, 20.125);
  EXPECT_DOUBLE_EQ(r.place_ms, 1.5);
  EXPECT_EQ(r.loops, 0);
  EXPECT_DOUBLE_EQ(r.loop_ms, 0.75);
  EXPECT_EQ(log->frames[1].loops, 1);
  EXPECT_DOUBLE_EQ(log->frames[1].loop_ms, 12.5);
  EXPECT_EQ(r.merges, 1);
  EXPECT_EQ(r.merges_refused, 0);
  EXPECT_EQ(log->frames[1].merges, 1);
  EXPECT_EQ(log->frames[1].merges_refused, 2);
  EXPECT_FALSE(log->frames[1].negative);
  EXPECT_TRUE(log->has_slam_columns);
  EXPECT_TRUE(log->has_place_column);
  EXPECT_TRUE(log->has_loop_columns);
  EXPECT_TRUE(log->has_merge_columns);
  const FrameLogSummary s = summarize(*log);
  EXPECT_DOUBLE_EQ(s.place_mean_ms, 2.875);
  EXPECT_DOUBLE_EQ(s.place_max_ms, 4.25);
  EXPECT_TRUE(s.loops_logged);
  EXPECT_EQ(s.loops_closed, 1u);
  EXPECT_DOUBLE_EQ(s.loop_mean_ms, 6.625);
  EXPECT_DOUBLE_EQ(s.loop_max_ms, 12.5);
  EXPECT_DOUBLE_EQ(s.loop_frame_time_max_ms, 48.5);  // b's, not a's 33.125
  EXPECT_TRUE(s.merges_logged);
  EXPECT_EQ(s.merges, 1u);
  EXPECT_EQ(s.merges_refused, 2u);
  EXPECT_EQ(s.maps, 2u);
  EXPECT_EQ(s.keyframes_last, 41);
  EXPECT_DOUBLE_EQ(s.tracked_share, 0.0);  // both lost
  EXPECT_DOUBLE_EQ(s.mapping_mean_ms, 20.125);
  EXPECT_EQ(frame_log_header().rfind("#timestamp_ns,sequence,state,brightness,", 0), 0u);
}

TEST(FrameLogTest, SummaryOfTheSmallLog) {
  const Result<FrameLog> log = read_frame_log(kSmallLog);
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  const FrameLogSummary s = summarize(*log);
  EXPECT_EQ(s.frames, 10u);
  EXPECT_DOUBLE_EQ(s.brightness_share[static_cast<std::size_t>(BrightnessClass::kExtremelyDark)], 0.2);
  EXPECT_DOUBLE_EQ(s.brightness_share[static_cast<std::size_t>(BrightnessClass::kDark)], 0.3);
  EXPECT_DOUBLE_EQ(s.brightness_share[static_cast<std::size_t>(BrightnessClass::kNormal)], 0.3);
  EXPECT_DOUBLE_EQ(s.brightness_share[static_cast<std::size_t>(BrightnessClass::kBright)], 0.2);
  EXPECT_DOUBLE_EQ(s.features_mean, 310.0);
  // Inliers 120, 100, 40, 140, 60 reach 10; 0, 0, 5, 0, 8 do not.
  EXPECT_EQ(s.via_frames, 5u);
  EXPECT_DOUBLE_EQ(s.via, 92.0);
  EXPECT_DOUBLE_EQ(s.frame_time_mean_ms, 11.1);
  EXPECT_DOUBLE_EQ(s.frame_time_max_ms, 30.0);
  // tracking -> lost twice; lost -> lost is the same loss.
  EXPECT_EQ(s.tracking_losses, 2u);
  // Posed: tracking (2, 3, 7, 9) and relocalized (6).
  EXPECT_DOUBLE_EQ(s.tracked_share, 0.5);
  EXPECT_EQ(s.relocalisations, 1u);
  // A log from before the SLAM core's columns: they read as 0, one map.
  EXPECT_EQ(s.maps, 1u);
  EXPECT_EQ(s.keyframes_last, 0);
  EXPECT_FALSE(log->has_place_column);
  EXPECT_FALSE(log->has_loop_columns);
  EXPECT_FALSE(s.loops_logged);
  EXPECT_EQ(s.loops_closed, 0u);
  EXPECT_FALSE(log->has_merge_columns);
  EXPECT_FALSE(s.merges_logged);
}

// A log the daemon wrote before loop closing had columns (everything up to place_ms): it reads,
// loops and loop_ms as 0, and says the columns were not there.
TEST(FrameLogTest, ALogWithoutTheLoopColumnsReadsThemAsZero) {
  const std::string header = frame_log_header();
  const std::string later = ",loops,loop_ms,merges,merges_refused";
  const std::size_t cut = header.find(later);
  ASSERT_NE(cut, std::string::npos) << header;
  ASSERT_EQ(cut + later.size(), header.size()) << "the loop and merge columns come last";
  const std::string text = header.substr(0, cut) + "\n" +
                           "1000000000,1,tracking,normal,100.00,20.00,1.0000,0.000,0,500,120,12.500,1,5,800,4.000,3.000,"
                           "5.000,0.250\n";
  const Result<FrameLog> log = parse_frame_log(text, "old.csv");
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  EXPECT_TRUE(log->has_slam_columns);
  EXPECT_TRUE(log->has_place_column);
  EXPECT_FALSE(log->has_loop_columns);
  EXPECT_DOUBLE_EQ(log->frames[0].place_ms, 0.25);
  EXPECT_EQ(log->frames[0].loops, 0);
  EXPECT_DOUBLE_EQ(log->frames[0].loop_ms, 0.0);
  const FrameLogSummary s = summarize(*log);
  EXPECT_FALSE(s.loops_logged);
  EXPECT_EQ(s.loops_closed, 0u);
  EXPECT_DOUBLE_EQ(s.loop_frame_time_max_ms, 0.0);
  EXPECT_FALSE(log->has_merge_columns);
  EXPECT_FALSE(s.merges_logged);
}

// A log the daemon wrote before map merging had columns (everything up to loop_ms): it reads,
// merges and merges_refused as 0, and says the columns were not there.
TEST(FrameLogTest, ALogWithoutTheMergeColumnsReadsThemAsZero) {
  const std::string header = frame_log_header();
  const std::size_t cut = header.find(",merges,merges_refused");
  ASSERT_NE(cut, std::string::npos) << header;
  ASSERT_EQ(cut + std::string(",merges,merges_refused").size(), header.size()) << "the merge columns come last";
  const std::string text = header.substr(0, cut) + "\n" +
                           "1000000000,1,tracking,normal,100.00,20.00,1.0000,0.000,0,500,120,12.500,1,5,800,4.000,3.000,"
                           "5.000,0.250,2,1.500\n";
  const Result<FrameLog> log = parse_frame_log(text, "old.csv");
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  EXPECT_TRUE(log->has_loop_columns);
  EXPECT_FALSE(log->has_merge_columns);
  EXPECT_EQ(log->frames[0].loops, 2);
  EXPECT_DOUBLE_EQ(log->frames[0].loop_ms, 1.5);
  EXPECT_EQ(log->frames[0].merges, 0);
  EXPECT_EQ(log->frames[0].merges_refused, 0);
  const FrameLogSummary s = summarize(*log);
  EXPECT_TRUE(s.loops_logged);
  EXPECT_FALSE(s.merges_logged);
  EXPECT_EQ(s.merges, 0u);
  EXPECT_EQ(s.merges_refused, 0u);
}

// A frame whose count rose closed as many loops as it rose by; a log's first frame counts from 0.
TEST(FrameLogTest, LoopsClosedAreWhereTheCountRises) {
  FrameLog log;
  log.has_loop_columns = true;
  const int loops[] = {0, 0, 1, 1, 3, 3};
  const double frame_ms[] = {5.0, 6.0, 40.0, 7.0, 30.0, 90.0};
  for (int k = 0; k < 6; ++k) {
    FrameRecord r;
    r.timestamp_ns = static_cast<std::uint64_t>(k + 1) * 1000000ull;
    r.loops = loops[k];
    r.frame_time_ms = frame_ms[k];
    log.frames.push_back(r);
  }
  const int closed[] = {0, 0, 1, 0, 2, 0};
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(loops_closed_at(log, i), closed[i]) << "frame " << i;
  const FrameLogSummary s = summarize(log);
  EXPECT_EQ(s.loops_closed, 3u);
  EXPECT_DOUBLE_EQ(s.loop_frame_time_max_ms, 40.0);  // not the 90 ms frame: no loop closed on it
  log.frames[0].loops = 2;
  EXPECT_EQ(loops_closed_at(log, 0), 2);
}

// A frame whose merges count rose merged as many maps as it rose by; the change of map_id a merge
// brings (back into an older map) starts no new map.
TEST(FrameLogTest, MergesAreWhereTheCountRisesAndStartNoMap) {
  FrameLog log;
  log.has_merge_columns = true;
  const std::uint64_t map_id[] = {1, 1, 2, 2, 1, 1, 3};
  const int merges[] = {0, 0, 0, 0, 1, 1, 1};
  const int refused[] = {0, 1, 1, 3, 3, 3, 3};
  for (int k = 0; k < 7; ++k) {
    FrameRecord r;
    r.timestamp_ns = static_cast<std::uint64_t>(k + 1) * 1000000ull;
    r.map_id = map_id[k];
    r.merges = merges[k];
    r.merges_refused = refused[k];
    log.frames.push_back(r);
  }
  const int merged[] = {0, 0, 0, 0, 1, 0, 0};
  for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(merges_at(log, i), merged[i]) << "frame " << i;
  const FrameLogSummary s = summarize(log);
  EXPECT_EQ(s.merges, 1u);
  EXPECT_EQ(s.merges_refused, 3u);
  EXPECT_EQ(s.maps, 3u);  // maps 1, 2 and 3; the return to map 1 was the merge
  log.frames[0].merges = 2;
  EXPECT_EQ(merges_at(log, 0), 2);
}

TEST(FrameLogTest, P95IsTheNearestRankAndViaIsNanWithoutValidFrames) {
  std::string text = kHeader;
  for (int k = 0; k < 20; ++k) text += line(k, "tracking", "normal", 100, 9, 20 - k);  // times 20 .. 1
  const Result<FrameLog> log = parse_frame_log(text, "log.csv");
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  const FrameLogSummary s = summarize(*log);
  EXPECT_DOUBLE_EQ(s.frame_time_p95_ms, 19.0);  // the 19th of 20 sorted
  EXPECT_DOUBLE_EQ(s.frame_time_mean_ms, 10.5);
  EXPECT_EQ(s.via_frames, 0u);
  EXPECT_TRUE(std::isnan(s.via));
  EXPECT_EQ(s.tracking_losses, 0u);
}

TEST(FrameLogTest, HeaderColumnsAreFoundByName) {
  // Another order, no '#', an unknown column in the middle.
  const std::string text =
      "sequence,timestamp_ns,brightness,state,extra,mean,sigma,gamma,clip,negative,features,inliers,frame_time_ms\n"
      "7,2000000000,dark,tracking,x,60,10,1,2,0,300,50,4.5\n";
  const Result<FrameLog> log = parse_frame_log(text, "log.csv");
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  EXPECT_EQ(log->frames[0].sequence, 7u);
  EXPECT_DOUBLE_EQ(log->frames[0].t_s(), 2.0);
  EXPECT_EQ(log->frames[0].brightness, BrightnessClass::kDark);
  EXPECT_EQ(log->frames[0].state, TrackingState::kTracking);
  EXPECT_EQ(log->frames[0].inliers, 50);
}

TEST(FrameLogTest, ErrorsNameFileAndLine) {
  const std::string ok1 = line(1, "tracking", "normal", 100, 50, 3.0);
  const std::string ok2 = line(2, "tracking", "normal", 100, 50, 3.0);
  EXPECT_EQ(error_of(kHeader + ok1 + "1,2,3\n"), "log.csv:3: 3 columns, the header has 12");
  EXPECT_EQ(error_of(kHeader + line(1, "tracking", "dim", 100, 50, 3.0)),
            "log.csv:2: unknown brightness class 'dim' (expected extremely_dark, dark, normal, bright)");
  EXPECT_EQ(error_of(kHeader + ok1 + line(2, "walking", "normal", 100, 50, 3.0)),
            "log.csv:3: unknown tracking state 'walking' (expected not_initialized, initializing, tracking, "
            "lost, relocalized)");
  EXPECT_EQ(error_of(kHeader + line(1, "tracking", "normal", 100, 50, -1.0)),
            "log.csv:2: frame_time_ms '-1.000' is not a time >= 0");
  EXPECT_EQ(error_of(kHeader + ok2 + ok1), "log.csv:3: timestamp_ns 50000000 is not later than 100000000 on line 2 "
                                           "(timestamps must increase)");
  std::string bad_number = ok1;
  bad_number.replace(bad_number.find("100.00"), 6, "1e9x");
  EXPECT_EQ(error_of(kHeader + bad_number), "log.csv:2: mean '1e9x' is not a finite number");
  std::string fraction = ok1;
  fraction.replace(fraction.find(",100,50,"), 8, ",100.5,50,");
  EXPECT_EQ(error_of(kHeader + fraction), "log.csv:2: features '100.5' is not a whole number >= 0");
  const std::string loop_header = kHeader.substr(0, kHeader.size() - 1) + ",loops,loop_ms\n";
  const std::string ok_line = ok1.substr(0, ok1.size() - 1);
  EXPECT_EQ(error_of(loop_header + ok_line + ",-1,0.5\n"), "log.csv:2: loops '-1' is not a whole number >= 0");
  EXPECT_EQ(error_of(loop_header + ok_line + ",1,-0.5\n"), "log.csv:2: loop_ms '-0.5' is not a time >= 0");
  EXPECT_EQ(error_of(loop_header + ok_line + ",1,0.500\n"), "");
  const std::string merge_header = loop_header.substr(0, loop_header.size() - 1) + ",merges,merges_refused\n";
  EXPECT_EQ(error_of(merge_header + ok_line + ",1,0.500,-1,0\n"), "log.csv:2: merges '-1' is not a whole number >= 0");
  EXPECT_EQ(error_of(merge_header + ok_line + ",1,0.500,1,0.5\n"),
            "log.csv:2: merges_refused '0.5' is not a whole number >= 0");
  EXPECT_EQ(error_of(merge_header + ok_line + ",1,0.500,1,2\n"), "");
}

TEST(FrameLogTest, HeaderErrors) {
  const std::string no_inliers =
      "#timestamp_ns,sequence,state,brightness,mean,sigma,gamma,clip,negative,features,frame_time_ms\n";
  EXPECT_EQ(error_of("\n" + no_inliers),
            "log.csv:2: header has no column 'inliers' (is this an ale-slamd --frame-log file?)");
  // A data line where the header should be is a missing header.
  EXPECT_EQ(error_of(line(1, "tracking", "normal", 100, 50, 3.0)),
            "log.csv:1: header has no column 'timestamp_ns' (is this an ale-slamd --frame-log file?)");
  EXPECT_EQ(error_of("#timestamp_ns,timestamp_ns\n"), "log.csv:1: column 'timestamp_ns' appears twice");
  EXPECT_EQ(error_of(""), "log.csv: empty file, expected a frame log header");
  EXPECT_EQ(error_of(kHeader), "log.csv: no frames in the log");
}

TEST(FrameLogTest, MissingFileIsNotFound) {
  const Result<FrameLog> log = read_frame_log("/nonexistent/frames.csv");
  ASSERT_FALSE(log.ok());
  EXPECT_EQ(log.status().code(), StatusCode::kNotFound);
  EXPECT_NE(log.status().message().find("/nonexistent/frames.csv"), std::string::npos);
}

}  // namespace
}  // namespace ale::eval
