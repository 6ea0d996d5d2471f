// The next cleaning run starts from the saved map, through the daemon's loop: ale-render makes at
// test time the first 15 s of the loop (run 1) and 18 s of the same loop started 8 s into it with
// another sensor seed (run 2: the robot starts somewhere else in the room and drives on past where
// run 1 stopped, to the end of the lap), 320x240 at 15 fps. Run 1 saves its map at the end
// (map.save); run 2 loads it (map.load), relocalises in it, publishes its poses in the saved map's
// frame and id, and adds the part of the room run 1 never saw to the same map. Run 2 without the
// map starts a map of its own, whose frame nothing ties to run 1's. A corrupt map file is moved
// aside and its backup loaded instead.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "app/daemon/frame_loop.h"
#include "app/tools/lib/eval/align.h"
#include "app/tools/lib/eval/associate.h"
#include "app/tools/lib/eval/metrics.h"
#include "app/tools/lib/eval/trajectory.h"
#include "core/io/file_bytes.h"
#include "tests/host/app/rendered_sequence.h"
#include "tests/host/support/test_data.h"

namespace ale::app {
namespace {

struct DaemonRun {
  RunSummary summary;
  hal::FakePoseSink sink;
  Result<eval::Trajectory> trajectory = Status(not_found("not run"));
};

// odometry: the render's wheel odometry fused (a sweeper's run); without it the camera alone.
void replay(const std::string& seq, const std::string& out, const std::string& load, const std::string& save, DaemonRun& run,
            bool odometry = false, bool localisation_only = false) {
  hal::NullGpio gpio;
  test::RenderedReplay replay;
  ASSERT_TRUE(replay.open(seq, run.sink, gpio));
  DaemonConfig config;
  config.daemon.trajectory = out + ".tum";
  config.map.load = load;
  config.map.save = save;
  config.slam.localisation_only = localisation_only;
  if (odometry) {
    ASSERT_TRUE(replay.fuse_odometry(seq, config));
  }
  const Status s = run_frame_loop(config, *replay.deps, run.summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
  run.trajectory = eval::read_trajectory(config.daemon.trajectory);
  ASSERT_TRUE(run.trajectory.ok()) << run.trajectory.status().to_string();
}

double path_of(const eval::Trajectory& gt) {
  double m = 0.0;
  for (std::size_t i = 1; i < gt.poses.size(); ++i) m += (gt.poses[i].p_wb - gt.poses[i - 1].p_wb).norm();
  return m;
}

// Run 2's ATE in the saved map's frame: run 1's poses aligned to its ground truth (Sim(3): the
// camera alone has no metres), the same transform applied to run 2's poses, their RMSE against
// run 2's ground truth (metres).
void ate_in_saved_frame(const eval::Trajectory& gt1, const eval::Trajectory& est1, const eval::Trajectory& gt2,
                        const eval::Trajectory& est2, double* ate_m) {
  Result<eval::PosePairs> first = eval::associate(gt1, est1, 0.01);
  ASSERT_TRUE(first.ok()) << first.status().to_string();
  const Result<eval::Sim3> frame = eval::align_estimate(eval::Alignment::kSim3, &*first);
  ASSERT_TRUE(frame.ok()) << frame.status().to_string();
  Result<eval::PosePairs> next = eval::associate(gt2, est2, 0.01);
  ASSERT_TRUE(next.ok()) << next.status().to_string();
  ASSERT_FALSE(next->est.empty());
  double sum = 0.0;
  for (std::size_t i = 0; i < next->est.size(); ++i) {
    sum += (frame->apply(next->est[i].p_wb) - next->gt[i].p_wb).squaredNorm();
  }
  *ate_m = std::sqrt(sum / static_cast<double>(next->est.size()));
}

class NextRunTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    work_ = new std::string(test::make_temp_dir("next-run"));
    const std::string common = " --fps 15 --width 320 --height 240 --supersample 1";
    rendered_ = test::render_sequence(*work_ + "/run1", "--trajectory loop --duration 15 --seed 1" + common) &&
                test::render_sequence(*work_ + "/run2", "--trajectory loop --start 8 --duration 18 --seed 2" + common) &&
                test::render_sequence(*work_ + "/inside", "--trajectory loop --start 2 --duration 10 --seed 3" + common);
  }
  static void TearDownTestSuite() { delete work_; }
  void SetUp() override {
    ASSERT_TRUE(rendered_);
    gt1_ = eval::read_trajectory(*work_ + "/run1/groundtruth.txt");
    gt2_ = eval::read_trajectory(*work_ + "/run2/groundtruth.txt");
    ASSERT_TRUE(gt1_.ok() && gt2_.ok());
  }
  static std::string* work_;
  static bool rendered_;
  Result<eval::Trajectory> gt1_ = Status(not_found("")), gt2_ = Status(not_found(""));
};
std::string* NextRunTest::work_ = nullptr;
bool NextRunTest::rendered_ = false;

// The first posed frame of a run: its index among the published poses (-1: none).
int first_posed(const hal::FakePoseSink& sink) {
  for (std::size_t i = 0; i < sink.poses.size(); ++i) {
    if (has_pose(sink.poses[i].state)) return static_cast<int>(i);
  }
  return -1;
}

// Run 1 saves, run 2 loads: relocalised within a second (15 frames) of its start, in the saved
// map's id, never reset, every frame from then on posed, in the saved map's frame (alone, no map
// loaded, its frame is its own). With odometry (a sweeper's run) its ATE in that frame is within
// the 0.5 % of its path. The camera alone at 320x240 makes a map good to about 1.3 % of
// its lap here (no scale cue: the test gives no mounting), which run 2 cannot better, so that run
// is held to the frame, not to the figure.
void next_run(const std::string& w, const eval::Trajectory& gt1, const eval::Trajectory& gt2, bool odometry) {
  const std::string tag = odometry ? "fused" : "camera";
  const std::string map = w + "/home-" + tag + ".alemap";
  DaemonRun first, next, alone;
  replay(w + "/run1", w + "/t1-" + tag, "", map, first, odometry);
  if (::testing::Test::HasFatalFailure()) return;
  ASSERT_EQ(first.summary.resets, 0);
  const std::uint32_t map_id = static_cast<std::uint32_t>(first.sink.poses.back().map_id);
  std::vector<std::uint8_t> saved;
  ASSERT_TRUE(io::read_file_bytes(map, saved).ok()) << "run 1 saved no map";
  replay(w + "/run2", w + "/t2-" + tag, map, w + "/after-" + tag + ".alemap", next, odometry);
  if (::testing::Test::HasFatalFailure()) return;
  replay(w + "/run2", w + "/t2alone-" + tag, "", "", alone, odometry);
  if (::testing::Test::HasFatalFailure()) return;

  const int at = first_posed(next.sink);
  ASSERT_GE(at, 0) << "run 2 never posed a frame";
  EXPECT_LE(at, 15);
  EXPECT_EQ(next.sink.poses[static_cast<std::size_t>(at)].state, TrackingState::kRelocalized);
  EXPECT_EQ(next.summary.resets, 0);
  EXPECT_GE(next.summary.relocalisations, 1);
  for (std::size_t i = static_cast<std::size_t>(at); i < next.sink.poses.size(); ++i) {
    EXPECT_TRUE(has_pose(next.sink.poses[i].state)) << "frame " << i;
    EXPECT_EQ(static_cast<std::uint32_t>(next.sink.poses[i].map_id), map_id) << "frame " << i;
  }
  double ate_m = 0.0, alone_m = 0.0;
  ate_in_saved_frame(gt1, *first.trajectory, gt2, *next.trajectory, &ate_m);
  ate_in_saved_frame(gt1, *first.trajectory, gt2, *alone.trajectory, &alone_m);
  const double path_m = path_of(gt2);
  EXPECT_GT(path_m, 4.0);
  if (odometry) {
    EXPECT_LE(ate_m, 0.005 * path_m);
  }
  EXPECT_GT(alone_m, 5.0 * ate_m) << "the control: without the map, run 2's frame is its own";
  // the part of the room run 1 never saw is added to the same map
  EXPECT_GT(next.summary.keyframes, first.summary.keyframes);
  std::printf("%s: run 2 from the saved map (%zu bytes): first pose at frame %d (%s); ATE in the saved map's frame "
              "%.4f m over %.2f m (%.3f %%), without the map %.4f m; keyframes %d -> %d\n",
              tag.c_str(), saved.size(), at, to_string(next.sink.poses[static_cast<std::size_t>(at)].state), ate_m,
              path_m, 100.0 * ate_m / path_m, alone_m, first.summary.keyframes, next.summary.keyframes);
}

TEST_F(NextRunTest, ASecondRunRelocalisesInTheSavedMapAndPosesInItsFrame) { next_run(*work_, *gt1_, *gt2_, false); }

TEST_F(NextRunTest, ASecondRunWithOdometryPosesInTheSavedMapsFrameToo) { next_run(*work_, *gt1_, *gt2_, true); }

// slam.localisation_only: the loaded map is frozen; a run inside the part run 1 mapped (2 s to
// 12 s of the loop, another seed) relocalises and tracks in it and adds nothing (the map saved
// after it is as large as the one loaded).
TEST_F(NextRunTest, LocalisationOnlyTracksInTheLoadedMapAndAddsNothing) {
  const std::string& w = *work_;
  const std::string map = w + "/frozen.alemap";
  DaemonRun first, next;
  replay(w + "/run1", w + "/l1", "", map, first, true);
  if (HasFatalFailure()) return;
  replay(w + "/inside", w + "/l2", map, w + "/frozen-after.alemap", next, true, true);
  if (HasFatalFailure()) return;
  const int at = first_posed(next.sink);
  ASSERT_GE(at, 0);
  EXPECT_LE(at, 15);
  std::size_t posed = 0;
  for (std::size_t i = static_cast<std::size_t>(at); i < next.sink.poses.size(); ++i) posed += has_pose(next.sink.poses[i].state);
  EXPECT_GE(posed, 9 * (next.sink.poses.size() - static_cast<std::size_t>(at)) / 10);
  EXPECT_EQ(next.summary.keyframes, first.summary.keyframes);
  EXPECT_EQ(next.summary.resets, 0);
  std::vector<std::uint8_t> before, after;
  ASSERT_TRUE(io::read_file_bytes(map, before).ok());
  ASSERT_TRUE(io::read_file_bytes(w + "/frozen-after.alemap", after).ok());
  EXPECT_EQ(after.size(), before.size()) << "the frozen map changed size";
  std::printf("localisation only: %zu of %zu frames posed from frame %d, keyframes %d -> %d\n", posed,
              next.sink.poses.size() - static_cast<std::size_t>(at), at, first.summary.keyframes, next.summary.keyframes);
}

TEST_F(NextRunTest, ACorruptMapFileIsSetAsideAndItsBackupLoaded) {
  const std::string& w = *work_;
  const std::string map = w + "/corrupt.alemap";
  DaemonRun a, b, next;
  replay(w + "/run1", w + "/c1", "", map, a);  // the file
  if (HasFatalFailure()) return;
  replay(w + "/run1", w + "/c2", "", map, b);  // again: the first one is the backup now
  if (HasFatalFailure()) return;
  std::vector<std::uint8_t> bytes;
  ASSERT_TRUE(io::read_file_bytes(map, bytes).ok());
  bytes[bytes.size() / 2] ^= 0x10;
  {
    std::ofstream out(map, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
  replay(w + "/run2", w + "/c3", map, "", next);
  if (HasFatalFailure()) return;
  std::vector<std::uint8_t> refused;
  ASSERT_TRUE(io::read_file_bytes(map + ".refused", refused).ok()) << "the corrupt file was not set aside";
  EXPECT_EQ(refused, bytes) << "the corrupt file must be kept as it was";
  const int at = first_posed(next.sink);
  ASSERT_GE(at, 0);
  EXPECT_EQ(next.sink.poses[static_cast<std::size_t>(at)].state, TrackingState::kRelocalized)
      << "the backup was not loaded: run 2 initialised a map of its own";
  EXPECT_EQ(next.summary.resets, 0);
}

}  // namespace
}  // namespace ale::app
