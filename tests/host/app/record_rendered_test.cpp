// Replaying a recording gives the trajectory of replaying its source: a sequence ale-render makes
// at test time (one that initialises and tracks) is replayed through the daemon's loop with the
// recorder on, then the recording is replayed; the frames, timestamps and lens come back
// unchanged, so the two trajectories are the same byte for byte.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "app/daemon/frame_loop.h"
#include "tests/host/app/rendered_sequence.h"
#include "tests/host/support/test_data.h"

namespace ale::app {
namespace {

void replay_run(const std::string& source, const std::string& trajectory, const std::string& rec_dir,
                RunSummary& summary) {
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  test::RenderedReplay replay;
  ASSERT_TRUE(replay.open(source, sink, gpio));
  DaemonConfig config;
  config.daemon.trajectory = trajectory;
  config.recorder.dir = rec_dir;
  const Status s = run_frame_loop(config, *replay.deps, summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
}

TEST(RecordRenderedTest, ReplayingARecordingGivesTheSourcesTrajectory) {
  const std::string work = test::make_temp_dir("record-replay");
  ASSERT_TRUE(test::render_sequence(work + "/seq", "--frames 40 --fps 15 --supersample 1 --seed 3"));
  RunSummary source, recording;
  replay_run(work + "/seq", work + "/source.tum", work + "/rec", source);
  EXPECT_EQ(source.frames, 40u);
  EXPECT_GT(source.tracked, 20u) << "the comparison needs poses";
  ASSERT_EQ(source.recorder.frames_recorded, 40u);
  EXPECT_EQ(source.recorder.frames_not_recorded, 0u) << "a replay waits for the writer";
  EXPECT_EQ(source.recorder.state, hal::RecorderState::kRecording);
  replay_run(source.recorder.sequence, work + "/recording.tum", "", recording);
  EXPECT_EQ(recording.recorder.state, hal::RecorderState::kOff);
  EXPECT_EQ(recording.frames, 40u);
  EXPECT_EQ(recording.tracked, source.tracked);
  const std::string a = test::read_file(work + "/source.tum");
  EXPECT_EQ(a, test::read_file(work + "/recording.tum"));
}

}  // namespace
}  // namespace ale::app
