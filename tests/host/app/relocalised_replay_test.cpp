// A relocalisation through the daemon's loop, as the status, the pose and the frame log show it:
// a sequence ale-render makes at test time (the loop, 320x240 at 15 fps) in which the camera is
// carried back to where it was 6 s earlier after a 1 s gap (a kidnap) is replayed with the
// built-in vocabulary. The frame after the jump is relocalised in the same map; its status counts
// it and gives place recognition's time, its pose says so, and the frame log's row agrees.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "app/daemon/frame_loop.h"
#include "app/tools/lib/eval/frame_log.h"
#include "tests/host/app/rendered_sequence.h"
#include "tests/host/support/test_data.h"

namespace ale::app {
namespace {

// The kidnap sequence (the loop, 10 s, back 6 s after a 1 s gap at 8 s) rendered into `work` and
// replayed through the daemon's loop, with the sequence's wheel odometry when `odometry`.
::testing::AssertionResult replay_kidnap(const std::string& work, bool odometry, hal::FakePoseSink& sink,
                                         DaemonConfig& config, RunSummary& summary) {
  if (!test::render_sequence(work + "/seq", "--duration 10 --fps 15 --width 320 --height 240 --supersample 1 "
                                            "--kidnap 8,2,1"))
    return ::testing::AssertionFailure() << "render failed";
  hal::NullGpio gpio;
  test::RenderedReplay replay;
  if (::testing::AssertionResult r = replay.open(work + "/seq", sink, gpio); !r) return r;
  if (odometry) {
    if (::testing::AssertionResult r = replay.fuse_odometry(work + "/seq", config); !r) return r;
  }
  const Status s = run_frame_loop(config, *replay.deps, summary);
  if (!s.ok()) return ::testing::AssertionFailure() << s.to_string();
  return ::testing::AssertionSuccess();
}

TEST(RelocalisedReplayTest, AKidnapIsRelocalisedAndStatusPoseAndFrameLogSaySo) {
  const std::string work = test::make_temp_dir("relocalised-replay");
  hal::FakePoseSink sink;
  DaemonConfig config;
  config.daemon.frame_log = work + "/frames.csv";
  RunSummary summary;
  ASSERT_TRUE(replay_kidnap(work, false, sink, config, summary));
  EXPECT_EQ(summary.frames, 150u);
  EXPECT_EQ(summary.resets, 0);

  const Result<eval::FrameLog> log = eval::read_frame_log(config.daemon.frame_log);
  ASSERT_TRUE(log.ok()) << log.status().to_string();
  ASSERT_TRUE(log->has_place_column);
  ASSERT_EQ(log->frames.size(), 150u);
  std::map<std::int64_t, const eval::FrameRecord*> row_at;
  for (const eval::FrameRecord& r : log->frames) row_at[static_cast<std::int64_t>(r.timestamp_ns)] = &r;

  // Every frame's status against its row: the state, the relocalisations so far, the place time.
  int relocalised_rows = 0;
  int statuses = 0;
  const hal::StatusReport* relocalised = nullptr;
  for (const hal::StatusReport& st : sink.reports) {
    const auto row = row_at.find(st.timestamp_ns);
    if (row == row_at.end() || st.state != row->second->state) continue;  // not a frame's own status
    ++statuses;
    if (row->second->state == TrackingState::kRelocalized) {
      ++relocalised_rows;
      if (relocalised == nullptr) relocalised = &st;
    }
    EXPECT_EQ(st.relocalisations, relocalised_rows) << "at " << st.timestamp_ns;
    EXPECT_NEAR(st.place_ms, row->second->place_ms, 0.0006) << "at " << st.timestamp_ns;
    EXPECT_GE(st.place_ms, 0.0f);
  }
  EXPECT_EQ(statuses, 150);
  ASSERT_NE(relocalised, nullptr) << "no frame was relocalised";
  EXPECT_EQ(summary.relocalisations, relocalised_rows);
  EXPECT_EQ(sink.reports.back().relocalisations, relocalised_rows);
  // The first relocalised frame comes right after the jump (the camera is back at a mapped place).
  const double jump_s = 9.0;  // 8 s of trajectory, then the 1 s gap
  const double t_s =
      static_cast<double>(relocalised->timestamp_ns - static_cast<std::int64_t>(log->frames.front().timestamp_ns)) * 1e-9;
  EXPECT_GE(t_s, jump_s - 1e-6);
  EXPECT_LE(t_s, jump_s + 1.0) << "within a second of the jump";
  // The relocaliser ran on it: place recognition took time there.
  EXPECT_GT(relocalised->place_ms, 0.0f);
  bool pose_says_so = false;
  for (const hal::PoseEstimate& p : sink.poses) {
    if (p.timestamp_ns == relocalised->timestamp_ns) {
      pose_says_so = p.state == TrackingState::kRelocalized && p.relocalized;
      EXPECT_EQ(p.map_id, relocalised->map_id);
    }
  }
  EXPECT_TRUE(pose_says_so);
  std::printf("relocalised at %.3f s (%d frame(s)); place recognition %.3f ms there, %.3f ms max over the run\n", t_s,
              relocalised_rows, static_cast<double>(relocalised->place_ms), eval::summarize(*log).place_max_ms);
}

// The same kidnap with the sequence's wheel odometry fused. The wheels do not feel the robot carried,
// so the odometry carries the pose on at the old place (slam.odometry.coast_s) while the camera sees
// the new one: relocalisation is still tried on those frames and comes within a second, and those
// carried poses stay out of the final trajectory (the run's figure below).
TEST(RelocalisedReplayTest, WithOdometryAKidnapTheWheelsDoNotFeelIsStillRelocalised) {
  const std::string work = test::make_temp_dir("relocalised-replay-odometry");
  hal::FakePoseSink sink;
  DaemonConfig config;
  RunSummary summary;
  ASSERT_TRUE(replay_kidnap(work, true, sink, config, summary));
  EXPECT_EQ(summary.resets, 0);
  const hal::PoseEstimate* relocalised = nullptr;
  int carried = 0;
  for (const hal::PoseEstimate& p : sink.poses) {
    if (p.odometry_only && p.state == TrackingState::kTracking) ++carried;
    if (relocalised == nullptr && p.state == TrackingState::kRelocalized) relocalised = &p;
  }
  ASSERT_NE(relocalised, nullptr) << "the odometry's pose was taken for the place the camera sees";
  const double t_s = static_cast<double>(relocalised->timestamp_ns - sink.poses.front().timestamp_ns) * 1e-9;
  std::printf("with odometry: relocalised at %.3f s, %d frames carried by the odometry\n", t_s, carried);
  EXPECT_GE(t_s, 9.0 - 1e-6);
  EXPECT_LE(t_s, 9.0 + 1.0) << "within a second of the jump";
  EXPECT_GT(carried, 0) << "the frames before the relocalisation were the odometry's";
}

}  // namespace
}  // namespace ale::app
