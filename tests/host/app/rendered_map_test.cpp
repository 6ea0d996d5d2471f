// The map through the daemon's loop on a sequence ale-render makes at test time (textured, one
// that initialises and tracks): kept across a camera disconnect and reconnect (the same map id,
// at least its keyframes, tracking resumed on the first frame back, no reset) and across a
// configuration reload, replaced by a RESET_MAP command sent while it holds keyframes, saved and
// loaded back by SAVE_MAP / LOAD_MAP, and saved every map.save_period_s between two frames, the
// save's time counted in the frame it delayed.
#include <gtest/gtest.h>

#include <algorithm>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "app/daemon/frame_loop.h"
#include "core/io/image_io.h"
#include "hal/replay/dataset.h"
#include "tests/host/app/camera_reconnect_fixture.h"
#include "tests/host/app/rendered_sequence.h"
#include "tests/host/support/test_data.h"

namespace ale::app {
namespace {

using test::kMsNs;

constexpr int kFrames = 40;  // 15 fps: the map has keyframes by frame 20 (measured: 5)
constexpr int kBeforeLoss = 24;

// The rendered sequence, made once for the tests of this file: its folder, and the dataset read
// from it.
const std::string& sequence_dir() {
  static const std::string dir = [] {
    const std::string d = test::make_temp_dir("rendered-map") + "/seq";
    EXPECT_TRUE(test::render_sequence(
        d, "--frames " + std::to_string(kFrames) + " --fps 15 --width 320 --height 240 --supersample 1 --seed 3"));
    return d;
  }();
  return dir;
}
const replay::Dataset& sequence() {
  static const replay::Dataset ds = [] {
    Result<replay::Dataset> opened = replay::open_dataset(sequence_dir());
    EXPECT_TRUE(opened.ok()) << opened.status().to_string();
    return opened.ok() ? std::move(*opened) : replay::Dataset{};
  }();
  return ds;
}

// The rendered frames through the V4L2 fake: the first kBeforeLoss, the camera unplugged, the
// rest after it is back (their timestamps 4 s later: the time it was away).
class RenderedReconnect : public test::CameraReconnectFixture {
 protected:
  void first_shots() override {
    const replay::Dataset& ds = sequence();
    ASSERT_EQ(static_cast<int>(ds.frames.size()), kFrames);
    ASSERT_TRUE(ds.calibration.has_value());
    calibration_ = *ds.calibration;
    options_.width = ds.width;
    options_.height = ds.height;
    driver_.max_width = ds.width;
    driver_.max_height = ds.height;
    add_frames(0, kBeforeLoss, 0);
    driver_.vanish_after = kBeforeLoss;
  }
  void replugged_shots() override { add_frames(kBeforeLoss, kFrames, 4000 * kMsNs); }

  // V4L2 stamps frames in microseconds
  static std::int64_t camera_time_ns(std::int64_t t_ns) { return t_ns / 1000 * 1000; }

  void add_frames(int from, int to, std::int64_t delay_ns) {
    const replay::Dataset& ds = sequence();
    GrayImage img;
    for (int i = from; i < to; ++i) {
      const replay::FrameEntry& f = ds.frames[static_cast<std::size_t>(i)];
      ASSERT_TRUE(io::read_gray(f.path, img).ok()) << f.path;
      auto luma = std::make_shared<std::vector<std::uint8_t>>(img.pixels);  // rows of width bytes
      test::FakeV4l2Driver::Shot shot;
      shot.sequence = static_cast<std::uint32_t>(i);
      shot.timestamp_ns = camera_time_ns(f.timestamp_ns + delay_ns);
      shot.luma = std::move(luma);
      driver_.shots.push_back(shot);
    }
  }
};

TEST_F(RenderedReconnect, ACameraReconnectKeepsTheMapAndTrackingResumes) {
  hal::FakePoseSink sink;
  config_.daemon.max_frames = kFrames;
  RunSummary summary;
  Status s = run_frame_loop(config_, deps(sink), summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_EQ(summary.frames, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(summary.camera_reconnects, 1u);
  EXPECT_EQ(summary.resets, 0);
  ASSERT_EQ(sink.poses.size(), static_cast<std::size_t>(kFrames));
  // the last frame before the loss: tracking, a map with keyframes
  std::vector<const hal::StatusReport*> frames;  // the status of each frame, in order
  for (const hal::StatusReport& r : sink.reports)
    if (r.camera_state == hal::CameraState::kStreaming) frames.push_back(&r);
  ASSERT_GE(frames.size(), static_cast<std::size_t>(kFrames));
  const hal::StatusReport& before = *frames[kBeforeLoss - 1];
  const hal::PoseEstimate& last_pose = sink.poses[kBeforeLoss - 1];
  ASSERT_EQ(last_pose.state, TrackingState::kTracking) << "the map must exist before the loss";
  ASSERT_GE(before.keyframes, 3) << "a map with keyframes beyond the initial two";
  // every frame after it: the same map, tracked from the first one
  for (int i = kBeforeLoss; i < kFrames; ++i) {
    const hal::PoseEstimate& p = sink.poses[static_cast<std::size_t>(i)];
    EXPECT_EQ(p.timestamp_ns, camera_time_ns(sequence().frames[static_cast<std::size_t>(i)].timestamp_ns + 4000 * kMsNs));
    EXPECT_EQ(p.state, TrackingState::kTracking) << "frame " << i;
    EXPECT_EQ(p.map_id, last_pose.map_id) << "frame " << i;
  }
  EXPECT_GE(summary.keyframes, before.keyframes) << "no keyframe was lost";
  std::printf("before the loss: map %d, %d keyframes; at the end: map %d, %d keyframes, %llu of %d frames tracked\n",
              before.map_id, before.keyframes, sink.reports.back().map_id, summary.keyframes,
              static_cast<unsigned long long>(summary.tracked), kFrames);
  EXPECT_EQ(sink.reports.back().map_id, before.map_id);
}

hal::Command command(std::int64_t id, hal::CommandKind kind, std::string argument = {}) {
  hal::Command c;
  c.id = id;
  c.kind = static_cast<std::int8_t>(kind);
  c.argument = std::move(argument);
  return c;
}

// A controller's commands, each sent once the given number of frames has been published.
class ScriptedCommands final : public hal::CommandChannel {
 public:
  explicit ScriptedCommands(const hal::FakePoseSink& sink) : sink_(sink) {}
  void at(std::size_t frames, hal::Command c) { script_.emplace_back(frames, std::move(c)); }
  Status receive(std::vector<hal::Command>& out) override {
    while (next_ < script_.size() && script_[next_].first <= sink_.poses.size()) out.push_back(script_[next_++].second);
    return {};
  }
  Status reply(const hal::CommandReply& r) override {
    replies.push_back(r);
    return {};
  }
  std::vector<hal::CommandReply> replies;

 private:
  const hal::FakePoseSink& sink_;
  std::vector<std::pair<std::size_t, hal::Command>> script_;
  std::size_t next_ = 0;
};

// The rendered sequence through the loop with a controller's commands.
struct CommandedRun {
  hal::FakePoseSink sink;
  ScriptedCommands commands{sink};
  RunSummary summary;
  // map.save_period_s runs on a clock that moves 1/15 s (rounded up) after each frame.
  hal::ManualClock clock{1000 * kMsNs};
  ::testing::AssertionResult run(const DaemonConfig& config = {}) {
    hal::NullGpio gpio;
    test::RenderedReplay replay;
    if (::testing::AssertionResult opened = replay.open(sequence_dir(), sink, gpio); !opened) return opened;
    replay.deps->commands = &commands;
    replay.deps->clock = &clock;
    replay.deps->on_frame = [this](const RunSummary&, const FrameRecord&) { clock.advance_ns(66666667); };
    const Status s = run_frame_loop(config, *replay.deps, summary);
    if (!s.ok()) return ::testing::AssertionFailure() << s.to_string();
    return ::testing::AssertionSuccess();
  }
};

// The time of a status' frame path stages, ms.
double stages_ms(const hal::StatusReport& r) {
  double ms = 0.0;
  for (std::size_t i = 0; i < r.timings.count; ++i) ms += static_cast<double>(r.timings.stage[i].ns) / 1e6;
  return ms;
}

TEST(RenderedMap, ResetMapOnAMapWithKeyframesStartsANewMap) {
  CommandedRun run;
  run.commands.at(kBeforeLoss, command(42, hal::CommandKind::kResetMap));
  ASSERT_TRUE(run.run());
  const hal::FakePoseSink& sink = run.sink;
  const ScriptedCommands& commands = run.commands;
  ASSERT_EQ(commands.replies.size(), 1u);
  EXPECT_EQ(commands.replies[0].id, 42);
  EXPECT_EQ(commands.replies[0].result, hal::CommandResult::kOk) << commands.replies[0].message;
  ASSERT_EQ(sink.poses.size(), static_cast<std::size_t>(kFrames));
  ASSERT_EQ(sink.reports.size(), static_cast<std::size_t>(kFrames));
  const hal::StatusReport& before = sink.reports[kBeforeLoss - 1];
  ASSERT_EQ(sink.poses[kBeforeLoss - 1].state, TrackingState::kTracking);
  ASSERT_GE(before.keyframes, 3) << "the reset must find a map with keyframes";
  // the first frame after the command: a new, empty map, not tracking
  const hal::StatusReport& after = sink.reports[kBeforeLoss];
  EXPECT_NE(after.map_id, before.map_id);
  EXPECT_LT(after.keyframes, before.keyframes);
  EXPECT_NE(sink.poses[kBeforeLoss].state, TrackingState::kTracking);
  EXPECT_NE(sink.poses[kBeforeLoss].map_id, sink.poses[kBeforeLoss - 1].map_id);
  // ... and the frames after it initialise and track the new map
  int first_tracked = -1;
  for (int i = kBeforeLoss; i < kFrames; ++i) {
    if (sink.poses[static_cast<std::size_t>(i)].state == TrackingState::kTracking && first_tracked < 0) first_tracked = i;
    EXPECT_EQ(sink.reports[static_cast<std::size_t>(i)].map_id, after.map_id) << "frame " << i;
  }
  ASSERT_GE(first_tracked, 0) << "no new map after the reset";
  EXPECT_LE(first_tracked, kBeforeLoss + 8);
  std::printf("before the reset: map %d, %d keyframes; after it: map %d, %d keyframes; tracked again from frame %d\n",
              before.map_id, before.keyframes, after.map_id, after.keyframes, first_tracked);
  EXPECT_EQ(sink.poses.back().state, TrackingState::kTracking);
}

// A configuration reload (SIGHUP) mid-run keeps the map and its tracking.
TEST(RenderedMap, AReloadKeepsTheMap) {
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  test::RenderedReplay replay;
  ASSERT_TRUE(replay.open(sequence_dir(), sink, gpio));
  DaemonConfig config;
  const int fd = eventfd(0, EFD_NONBLOCK);
  ASSERT_GE(fd, 0);
  LoopDeps& deps = *replay.deps;
  deps.reload_fd = fd;
  deps.load_config = [](DaemonConfig& c) { return parse_config("[gpio]\nir_on_dark_frames = 4\n", "reload.conf", c); };
  deps.on_frame = [fd](const RunSummary& s, const FrameRecord&) {
    if (s.frames == static_cast<std::uint64_t>(kBeforeLoss)) {
      const std::uint64_t one = 1;
      ASSERT_EQ(::write(fd, &one, sizeof one), static_cast<ssize_t>(sizeof one));
    }
  };
  RunSummary summary;
  const Status s = run_frame_loop(config, deps, summary);
  ::close(fd);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_EQ(summary.config_generation, 1);
  ASSERT_EQ(sink.poses.size(), static_cast<std::size_t>(kFrames));
  const hal::PoseEstimate& before = sink.poses[kBeforeLoss - 1];
  ASSERT_EQ(before.state, TrackingState::kTracking);
  for (int i = kBeforeLoss; i < kFrames; ++i) {
    EXPECT_EQ(sink.poses[static_cast<std::size_t>(i)].state, TrackingState::kTracking) << "frame " << i;
    EXPECT_EQ(sink.poses[static_cast<std::size_t>(i)].map_id, before.map_id) << "frame " << i;
  }
  EXPECT_EQ(summary.resets, 0);
}

// SAVE_MAP of a map with keyframes, RESET_MAP, then LOAD_MAP of the file: the saved map is back
// with its id and keyframes, and the frames after it are posed in it again.
TEST(RenderedMap, SaveMapThenLoadMapBringsTheSavedMapBack) {
  const std::string path = test::make_temp_dir("rendered-map-file") + "/home.alemap";
  constexpr std::size_t kLoadAt = 30;
  CommandedRun run;
  run.commands.at(kBeforeLoss, command(1, hal::CommandKind::kSaveMap, path));
  run.commands.at(kBeforeLoss, command(2, hal::CommandKind::kResetMap));
  run.commands.at(kLoadAt, command(3, hal::CommandKind::kLoadMap, path));
  ASSERT_TRUE(run.run());
  const hal::FakePoseSink& sink = run.sink;
  const ScriptedCommands& commands = run.commands;
  ASSERT_EQ(commands.replies.size(), 3u);
  for (const hal::CommandReply& r : commands.replies) {
    EXPECT_EQ(r.result, hal::CommandResult::kOk) << r.id << ": " << r.message;
    std::printf("reply to %lld: %s\n", static_cast<long long>(r.id), r.message.c_str());
  }
  ASSERT_EQ(sink.reports.size(), static_cast<std::size_t>(kFrames));
  const hal::StatusReport& saved = sink.reports[kBeforeLoss - 1];
  ASSERT_GE(saved.keyframes, 3) << "the save must find a map with keyframes";
  EXPECT_EQ(commands.replies[0].message.rfind("map saved to " + path + ": " + std::to_string(saved.keyframes) + " keyframes, ", 0), 0u);
  EXPECT_EQ(commands.replies[2].message.rfind("map loaded from " + path + ": " + std::to_string(saved.keyframes) + " keyframes, ", 0), 0u);
  EXPECT_NE(commands.replies[2].message.find("; relocalising in map " + std::to_string(saved.map_id)), std::string::npos);
  // the frame after the save and the reset: a new map, the save counted and in its frame time
  const hal::StatusReport& after_save = sink.reports[kBeforeLoss];
  EXPECT_EQ(after_save.map_id, saved.map_id + 1);
  EXPECT_EQ(after_save.map_saves, 1u);
  EXPECT_EQ(after_save.map_save_failures, 0u);
  EXPECT_GT(after_save.last_save_ms, 0.0f);
  EXPECT_GE(after_save.frame_time_ms, after_save.last_save_ms + stages_ms(after_save) - 0.01)
      << "the save delayed this frame: its time counts it";
  // from the load on: the saved map, its keyframes, posed in it again
  EXPECT_NE(sink.reports[kLoadAt - 1].map_id, saved.map_id);
  const hal::StatusReport& loaded = sink.reports[kLoadAt];
  EXPECT_EQ(loaded.map_id, saved.map_id);
  EXPECT_GE(loaded.keyframes, saved.keyframes);
  int posed_again = -1;
  for (std::size_t i = kLoadAt; i < sink.poses.size(); ++i) {
    EXPECT_EQ(sink.poses[i].map_id, saved.map_id) << "frame " << i;
    if (posed_again < 0 && has_pose(sink.poses[i].state)) posed_again = static_cast<int>(i);
  }
  std::printf("map %d saved with %d keyframes; map %d after the reset; loaded at frame %zu, posed in map %d again from "
              "frame %d\n",
              saved.map_id, saved.keyframes, after_save.map_id, kLoadAt, loaded.map_id, posed_again);
  ASSERT_GE(posed_again, 0) << "no frame relocalised in the loaded map";
  EXPECT_LE(posed_again, static_cast<int>(kLoadAt) + 3);
  EXPECT_EQ(run.summary.map_saves, 1u);
}

// map.save_period_s = 1 on a clock that moves 1/15 s per frame: saved after frames 15 and 30
// (never twice for one frame), each save's time in the frame after it, the previous file kept as
// PATH.bak.
// The frames whose status counts one save more than the frame before.
std::vector<int> frames_after_a_save(const hal::FakePoseSink& sink) {
  std::vector<int> frames;
  std::uint64_t saves = 0;
  for (std::size_t i = 0; i < sink.reports.size(); ++i) {
    const hal::StatusReport& r = sink.reports[i];
    EXPECT_LE(r.map_saves, saves + 1) << "at most one save per frame, at frame " << i;
    if (r.map_saves == saves) continue;
    saves = r.map_saves;
    frames.push_back(static_cast<int>(i));
    EXPECT_GE(r.frame_time_ms, r.last_save_ms + stages_ms(r) - 0.01) << "frame " << i << " waited for the save";
    std::printf("frame %zu: save %.2f ms, frame time %.2f ms (its stages %.2f ms), %d keyframes\n", i, r.last_save_ms,
                r.frame_time_ms, stages_ms(r), r.keyframes);
  }
  return frames;
}

TEST(RenderedMap, SavesEveryPeriodBetweenTwoFrames) {
  const std::string path = test::make_temp_dir("rendered-map-period") + "/home.alemap";
  DaemonConfig config;
  config.map.save_period_s = 1.0;
  config.map.save = path;
  CommandedRun run;
  ASSERT_TRUE(run.run(config));
  ASSERT_EQ(run.sink.reports.size(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(frames_after_a_save(run.sink), (std::vector<int>{15, 30}));
  EXPECT_EQ(run.sink.reports.back().map_save_failures, 0u);
  EXPECT_EQ(run.summary.map_saves, 3u) << "two while running, one at the end";
  EXPECT_EQ(run.summary.frames_after_map_file.count, 2u);
  EXPECT_FALSE(test::read_file(path).empty());
  EXPECT_FALSE(test::read_file(path + ".bak").empty()) << "the previous save kept";
}

// Due on every frame (a period shorter than a frame): never right after a frame that made a
// keyframe, whose successor runs the deferred local BA; every other frame with a map saves.
TEST(RenderedMap, APeriodicSaveKeepsOffTheFrameOfALocalBa) {
  DaemonConfig config;
  config.map.save_period_s = 0.001;
  config.map.save = test::make_temp_dir("rendered-map-period-ba") + "/home.alemap";
  CommandedRun run;
  ASSERT_TRUE(run.run(config));
  ASSERT_EQ(run.sink.reports.size(), static_cast<std::size_t>(kFrames));
  const std::vector<int> saved = frames_after_a_save(run.sink);
  int put_off = 0;
  for (int i = 2; i < kFrames; ++i) {
    // a keyframe inserted by tracking (not the initialiser's two, whose BA ran on their frame)
    const int before = run.sink.reports[static_cast<std::size_t>(i - 2)].keyframes;
    const bool made_keyframe = before > 0 && run.sink.reports[static_cast<std::size_t>(i - 1)].keyframes > before;
    const bool after_save = std::find(saved.begin(), saved.end(), i) != saved.end();
    if (made_keyframe) {
      EXPECT_FALSE(after_save) << "saved after frame " << i - 1 << ", which made a keyframe";
      ++put_off;
    }
  }
  EXPECT_GT(put_off, 0) << "no keyframe made: the test shows nothing";
  EXPECT_GT(saved.size(), 5u);
}

// A save that falls due while the current map has no keyframe (just reset) waits for one.
TEST(RenderedMap, APeriodicSaveWaitsForAMapWithKeyframes) {
  DaemonConfig config;
  config.map.save_period_s = 1.0;
  config.map.save = test::make_temp_dir("rendered-map-period-reset") + "/home.alemap";
  CommandedRun run;
  run.commands.at(14, command(1, hal::CommandKind::kResetMap));  // before frame 14, the save due after it
  ASSERT_TRUE(run.run(config));
  ASSERT_EQ(run.sink.reports.size(), static_cast<std::size_t>(kFrames));
  const std::vector<int> saved = frames_after_a_save(run.sink);
  ASSERT_FALSE(saved.empty());
  const int first = saved.front();
  EXPECT_GT(first, 15) << "put off from frame 15";
  EXPECT_EQ(run.sink.reports[static_cast<std::size_t>(first - 2)].keyframes, 0) << "due, but the map was empty";
  EXPECT_GT(run.sink.reports[static_cast<std::size_t>(first - 1)].keyframes, 0) << "saved once it had keyframes";
}

}  // namespace
}  // namespace ale::app
