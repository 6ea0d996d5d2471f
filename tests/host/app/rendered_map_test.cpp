// The map through the daemon's loop on a sequence ale-render makes at test time (textured, one
// that initialises and tracks): kept across a camera disconnect and reconnect (the same map id,
// at least its keyframes, tracking resumed on the first frame back, no reset) and across a
// configuration reload, and replaced by a RESET_MAP command sent while it holds keyframes.
#include <gtest/gtest.h>
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

// A controller's RESET_MAP once the given number of frames has been published.
class ResetAfter final : public hal::CommandChannel {
 public:
  ResetAfter(const hal::FakePoseSink& sink, std::size_t frames) : sink_(sink), frames_(frames) {}
  Status receive(std::vector<hal::Command>& out) override {
    if (sent_ || sink_.poses.size() != frames_) return {};
    hal::Command c;
    c.id = 42;
    c.kind = static_cast<std::int8_t>(hal::CommandKind::kResetMap);
    out.push_back(c);
    sent_ = true;
    return {};
  }
  Status reply(const hal::CommandReply& r) override {
    replies.push_back(r);
    return {};
  }
  std::vector<hal::CommandReply> replies;

 private:
  const hal::FakePoseSink& sink_;
  std::size_t frames_;
  bool sent_ = false;
};

TEST(RenderedMap, ResetMapOnAMapWithKeyframesStartsANewMap) {
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  test::RenderedReplay replay;
  ASSERT_TRUE(replay.open(sequence_dir(), sink, gpio));
  ResetAfter commands(sink, kBeforeLoss);
  DaemonConfig config;
  RunSummary summary;
  replay.deps->commands = &commands;
  const Status s = run_frame_loop(config, *replay.deps, summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
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

}  // namespace
}  // namespace ale::app
