#include "app/daemon/frame_loop.h"

#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include "app/daemon/commands.h"
#include "app/daemon/log.h"
#include "hal/fake/fake_camera.h"
#include "hal/replay/replay_camera.h"
#include "tests/host/app/loop_fixtures.h"
#include "tests/host/support/test_data.h"

#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace ale::app {
namespace {

using test::frames;
using test::test_lens;

LoopDeps deps_of(hal::Camera& cam, hal::PoseSink& sink, hal::Gpio& gpio, int stop_fd = -1) {
  LoopDeps d{cam, sink, gpio, stop_fd};
  d.calibration = test_lens();
  return d;
}

TEST(FrameLoopTest, PublishesPoseAndStatusForEveryFrameUntilTheEnd) {
  hal::FakeCamera cam(frames(5));
  hal::FakePoseSink sink;
  hal::FakeGpio gpio;
  DaemonConfig config;
  RunSummary summary;
  Status s = run_frame_loop(config, deps_of(cam, sink, gpio), summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_TRUE(summary.end_of_stream);
  EXPECT_EQ(summary.frames, 5u);
  ASSERT_EQ(sink.poses.size(), 5u);
  ASSERT_EQ(sink.reports.size(), 5u);
  EXPECT_EQ(sink.poses[3].frame_sequence, 3u);
  EXPECT_FLOAT_EQ(sink.reports[2].mean_intensity, 20.0f);
  EXPECT_EQ(cam.pool().stats().in_use, 0u) << "every frame must be released";
  EXPECT_FALSE(gpio.state(hal::GpioLine::kStatusLed)) << "LED off after the loop";
}

TEST(FrameLoopTest, GradesEveryFrameAndWritesTheFrameLog) {
  std::vector<GrayImage> v;
  v.emplace_back(64, 48, 20);   // extremely dark
  v.emplace_back(64, 48, 128);  // normal
  hal::FakeCamera::Options o;
  o.period_ns = 50000000;
  hal::FakeCamera cam(std::move(v), o);
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.features.enhance.grading.hysteresis = 0;
  config.daemon.frame_log = test::make_temp_dir("frame-log") + "/frames.csv";
  RunSummary summary;
  Status s = run_frame_loop(config, deps_of(cam, sink, gpio), summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
  ASSERT_EQ(sink.reports.size(), 2u);
  EXPECT_EQ(sink.reports[0].brightness, BrightnessClass::kExtremelyDark);
  EXPECT_EQ(sink.reports[1].brightness, BrightnessClass::kNormal);
  const std::string csv = test::read_file(config.daemon.frame_log);
  EXPECT_EQ(csv.rfind("#timestamp_ns,sequence,state,brightness,", 0), 0u) << csv;
  EXPECT_NE(csv.find("\n0,0,not_initialized,extremely_dark,20.00,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n50000000,1,not_initialized,normal,128.00,"), std::string::npos) << csv;
  // The frame time logged is the one published (column 12), not a copy left at 0.
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);  // header
  for (std::size_t i = 0; i < sink.reports.size(); ++i) {
    ASSERT_TRUE(static_cast<bool>(std::getline(lines, line)));
    std::istringstream fields(line);
    std::string field;
    for (int c = 0; c < 12; ++c) std::getline(fields, field, ',');
    char expected[32];
    std::snprintf(expected, sizeof expected, "%.3f", static_cast<double>(sink.reports[i].frame_time_ms));
    EXPECT_EQ(field, expected) << line;
    EXPECT_GT(sink.reports[i].frame_time_ms, 0.0f);
  }
}

// The frame log's row carries the status' loop and merge counts as they were published.
TEST(FrameLoopTest, TheFrameLogRowCarriesTheLoopAndMergeCounts) {
  FrameRecord r;
  r.status.loops_closed = 3;
  r.status.loop_ms = 1.5f;
  r.status.merges = 2;
  r.status.merges_refused = 5;
  const FrameLogRow row = frame_log_row(r);
  EXPECT_EQ(row.loops, 3);
  EXPECT_DOUBLE_EQ(row.loop_ms, 1.5);
  EXPECT_EQ(row.merges, 2);
  EXPECT_EQ(row.merges_refused, 5);
}

TEST(FrameLoopTest, ReportsTheFeaturesOfTheOrbFrontEnd) {
  GrayImage board(160, 120);
  for (int y = 0; y < board.height; ++y)
    for (int x = 0; x < board.width; ++x)
      board.view().at(x, y) = static_cast<std::uint8_t>(((x / 10 + y / 10) % 2) ? 200 : 40);
  std::vector<GrayImage> v;
  v.push_back(board);
  v.emplace_back(160, 120, 128);  // flat: nothing to detect
  hal::FakeCamera cam(std::move(v));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps_of(cam, sink, gpio), summary).ok());
  ASSERT_EQ(sink.reports.size(), 2u);
  EXPECT_GT(sink.reports[0].features, 20);
  EXPECT_LE(sink.reports[0].features, config.features.num_features);
  EXPECT_EQ(sink.reports[1].features, 0);
}

TEST(FrameLoopTest, UnwritableFrameLogStopsBeforeTheCameraStarts) {
  hal::FakeCamera cam(frames(2));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.daemon.frame_log = "/nonexistent-dir/frames.csv";
  RunSummary summary;
  Status s = run_frame_loop(config, deps_of(cam, sink, gpio), summary);
  EXPECT_EQ(s.code(), StatusCode::kIoError);
  EXPECT_NE(s.message().find("/nonexistent-dir/frames.csv"), std::string::npos);
  EXPECT_TRUE(sink.poses.empty());
}

TEST(FrameLoopTest, StopsAtMaxFrames) {
  hal::FakeCamera cam(frames(5));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.daemon.max_frames = 2;
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps_of(cam, sink, gpio), summary).ok());
  EXPECT_EQ(summary.frames, 2u);
  EXPECT_FALSE(summary.end_of_stream);
}

TEST(FrameLoopTest, VanishingCameraEndsTheLoopWithItsReason) {
  hal::FakeCamera::Options o;
  o.vanish_after = 3;
  hal::FakeCamera cam(frames(5), o);
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  RunSummary summary;
  Status s = run_frame_loop(config, deps_of(cam, sink, gpio), summary);
  EXPECT_EQ(s.code(), StatusCode::kUnavailable);
  EXPECT_EQ(summary.frames, 3u);
  EXPECT_EQ(sink.poses.size(), 3u) << "frames before the failure are not lost";
}

TEST(FrameLoopTest, StopRequestEndsTheLoopCleanly) {
  hal::FakeCamera cam(frames(5));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  const int fd = eventfd(1, EFD_NONBLOCK);  // already readable: a signal arrived
  ASSERT_GE(fd, 0);
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps_of(cam, sink, gpio, fd), summary).ok());
  ::close(fd);
  EXPECT_TRUE(summary.stopped_by_signal);
  EXPECT_EQ(summary.frames, 0u);
  EXPECT_EQ(sink.reports.size(), 1u) << "a last status on the way out";
}

TEST(FrameLoopTest, SilentCameraTimesOutAndStopsAfterTheConfiguredErrors) {
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);  // never written: the camera never becomes readable
  hal::FakeCamera::Options o;
  o.poll_fd = pipe_fds[0];
  hal::FakeCamera cam(frames(5), o);
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.camera.acquire_timeout_ms = 10;
  config.camera.max_consecutive_errors = 3;
  RunSummary summary;
  Status s = run_frame_loop(config, deps_of(cam, sink, gpio), summary);
  ::close(pipe_fds[0]);
  ::close(pipe_fds[1]);
  EXPECT_EQ(s.code(), StatusCode::kTimeout);
  EXPECT_NE(s.message().find("fake camera"), std::string::npos) << s.message();
  EXPECT_EQ(summary.frame_errors, 3u);
  EXPECT_EQ(summary.frames, 0u);
}

hal::Command command(std::int64_t id, int kind, std::string argument = {}) {
  hal::Command c;
  c.id = id;
  c.kind = static_cast<std::int8_t>(kind);
  c.argument = std::move(argument);
  return c;
}

TEST(FrameLoopTest, AnswersEveryCommandAndKeepsRunning) {
  hal::FakeCamera cam(frames(8));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  hal::FakeCommandChannel commands;  // one command reaches the loop before each frame
  using K = hal::CommandKind;
  commands.pending.push_back(command(1, static_cast<int>(K::kPause)));
  commands.pending.push_back(command(2, static_cast<int>(K::kResume)));
  commands.pending.push_back(command(3, static_cast<int>(K::kResetMap)));
  commands.pending.push_back(command(4, static_cast<int>(K::kSaveMap)));  // no path, no map.save
  commands.pending.push_back(command(5, 99));
  hal::Command junk;
  junk.malformed = true;
  junk.error = "13 bytes on ALE_COMMAND are not an ale_lcm.command_t";
  commands.pending.push_back(junk);
  commands.pending.push_back(command(7, static_cast<int>(K::kSetLogLevel), "loud"));
  commands.pending.push_back(command(8, static_cast<int>(K::kSetLogLevel), "warning"));
  DaemonConfig config;
  RunSummary summary;
  LoopDeps deps = deps_of(cam, sink, gpio);
  deps.commands = &commands;
  Status s = run_frame_loop(config, deps, summary);
  const LogLevel level_after = log_level();
  set_log_level(LogLevel::kInfo);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_TRUE(summary.end_of_stream);

  using R = hal::CommandResult;
  ASSERT_EQ(commands.replies.size(), 8u);
  const R expected[] = {R::kOk, R::kOk, R::kOk, R::kBadArgument, R::kUnknownCommand, R::kMalformed, R::kBadArgument,
                        R::kOk};
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(commands.replies[i].result, expected[i]) << "reply " << i << ": " << commands.replies[i].message;
    EXPECT_EQ(commands.replies[i].id, i == 5 ? -1 : static_cast<std::int64_t>(i + 1));
  }
  EXPECT_EQ(commands.replies[3].message, "no path given and map.save is not set");
  EXPECT_NE(commands.replies[6].message.find("loud"), std::string::npos);
  EXPECT_EQ(level_after, LogLevel::kWarning);
  EXPECT_EQ(summary.commands, 8u);
  EXPECT_EQ(summary.commands_rejected, 4u);

  // Frame 0 arrived paused: released, counted as skipped, no pose; the rest processed.
  EXPECT_EQ(summary.frames_skipped, 1u);
  EXPECT_EQ(summary.frames, 7u);
  ASSERT_EQ(sink.poses.size(), 7u);
  EXPECT_EQ(sink.poses[0].frame_sequence, 1u);
  EXPECT_EQ(sink.poses[0].map_id, 0) << "before the reset";
  EXPECT_EQ(sink.poses[1].map_id, 1) << "after the reset";
  ASSERT_EQ(sink.reports.size(), 8u) << "a status for the skipped frame too";
  EXPECT_TRUE(sink.reports[0].paused);
  EXPECT_EQ(sink.reports[0].frames_skipped, 1u);
  EXPECT_FALSE(sink.reports[1].paused);
  EXPECT_EQ(sink.reports.back().commands_received, 8u);
  EXPECT_EQ(sink.reports.back().commands_rejected, 4u);
  EXPECT_EQ(cam.pool().stats().in_use, 0u);
}

// handle_command's answers to the map commands from what the actions report.
TEST(FrameLoopTest, MapCommandsSayWhatTheFileHoldsOrWhyNot) {
  using K = hal::CommandKind;
  using R = hal::CommandResult;
  const int save = static_cast<int>(K::kSaveMap), load = static_cast<int>(K::kLoadMap);
  LoopControl control;
  MapCommands none;
  EXPECT_EQ(handle_command(command(1, save, "a"), control, none, 1).result, R::kNotSupported);
  EXPECT_EQ(handle_command(command(2, load, "a"), control, none, 1).result, R::kNotSupported);
  EXPECT_EQ(handle_command(command(3, static_cast<int>(K::kResetMap)), control, none, 1).result, R::kNotSupported);

  std::vector<std::string> paths;
  MapFileDone done;
  done.file.bytes = 1976448;
  done.file.maps = 1;
  done.file.keyframes = 52;
  done.file.landmarks = 2358;
  done.file.current_map = 3;
  done.ms = 7.84;
  MapCommands map;
  map.save = [&](const std::string& path) -> Result<MapFileDone> {
    paths.push_back(path);
    if (path == "full") return io_error("full: write: no space left on device");
    return done;
  };
  map.load = [&](const std::string& path) -> Result<MapFileDone> {
    paths.push_back(path);
    if (path == "later") return MapFileDone{{}, 0.0, true};
    if (path == "bad") return corrupt_data("bad: checksum of section 2 does not match");
    return done;
  };
  map.save_path = "home.alemap";
  hal::CommandReply r = handle_command(command(4, save, "/data/map.alemap"), control, map, 9);
  EXPECT_EQ(r.result, R::kOk);
  EXPECT_EQ(r.message, "map saved to /data/map.alemap: 52 keyframes, 2358 landmarks in 1 map(s), 1976448 bytes, 7.8 ms");
  EXPECT_EQ(r.timestamp_ns, 9);
  r = handle_command(command(5, save), control, map, 9);
  EXPECT_EQ(r.message, "map saved to home.alemap: 52 keyframes, 2358 landmarks in 1 map(s), 1976448 bytes, 7.8 ms");
  r = handle_command(command(6, save, "full"), control, map, 9);
  EXPECT_EQ(r.result, R::kFailed);
  EXPECT_EQ(r.message, "map not saved to full: i/o error: full: write: no space left on device; the previous file is kept");
  r = handle_command(command(7, load, "/data/map.alemap"), control, map, 9);
  EXPECT_EQ(r.result, R::kOk);
  EXPECT_EQ(r.message, "map loaded from /data/map.alemap: 52 keyframes, 2358 landmarks in 1 map(s), 1976448 bytes, "
                       "7.8 ms; relocalising in map 3");
  r = handle_command(command(8, load, "bad"), control, map, 9);
  EXPECT_EQ(r.result, R::kFailed);
  EXPECT_EQ(r.message.rfind("map file bad not loaded: ", 0), 0u) << r.message;
  EXPECT_NE(r.message.find("checksum of section 2 does not match; the map is as it was"), std::string::npos) << r.message;
  r = handle_command(command(9, load, "later"), control, map, 9);
  EXPECT_EQ(r.result, R::kOk);
  EXPECT_EQ(r.message, "map file later will be loaded when the SLAM core starts (the first frame)");
  r = handle_command(command(10, load), control, map, 9);  // no map.load
  EXPECT_EQ(r.result, R::kBadArgument);
  EXPECT_EQ(paths, (std::vector<std::string>{"/data/map.alemap", "home.alemap", "full", "/data/map.alemap", "bad", "later"}));
  EXPECT_EQ(control.commands_received, 10u);
  EXPECT_EQ(control.commands_rejected, 6u);
}

// SAVE_MAP and LOAD_MAP through the loop on flat frames (an empty map: what the files hold is the
// rendered tests' and the core's): each answer, the file written, the status' save counters.
TEST(FrameLoopTest, SavesAndLoadsTheMapByCommandAndSaysHowItWent) {
  const std::string dir = test::make_temp_dir("map-commands");
  ASSERT_TRUE(test::write_file(dir + "/noise.alemap", std::string(4096, '\x5a')));
  hal::FakeCamera cam(frames(9));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  hal::FakeCommandChannel commands;  // one command reaches the loop before each frame
  using K = hal::CommandKind;
  const int save = static_cast<int>(K::kSaveMap), load = static_cast<int>(K::kLoadMap);
  commands.pending.push_back(command(1, save, dir + "/early.alemap"));  // before the first frame: no core yet
  commands.pending.push_back(command(2, save, dir + "/a.alemap"));
  commands.pending.push_back(command(3, save, dir + "/no/such/dir/b.alemap"));
  commands.pending.push_back(command(4, load, dir + "/missing.alemap"));
  commands.pending.push_back(command(5, load, dir + "/noise.alemap"));
  commands.pending.push_back(command(6, save));  // map.save
  commands.pending.push_back(command(7, load));  // no map.load
  commands.pending.push_back(command(8, load, dir + "/a.alemap"));
  DaemonConfig config;
  config.map.save = dir + "/home.alemap";
  config.map.save_period_s = 0;  // only by command, and at the end
  RunSummary summary;
  LoopDeps deps = deps_of(cam, sink, gpio);
  deps.commands = &commands;
  const Status s = run_frame_loop(config, deps, summary);
  ASSERT_TRUE(s.ok()) << s.to_string();

  using R = hal::CommandResult;
  ASSERT_EQ(commands.replies.size(), 8u);
  const R expected[] = {R::kFailed, R::kOk, R::kFailed, R::kFailed, R::kFailed, R::kOk, R::kBadArgument, R::kOk};
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(commands.replies[i].result, expected[i]) << "reply " << i << ": " << commands.replies[i].message;
    EXPECT_EQ(commands.replies[i].kind, i <= 2 || i == 5 ? save : load) << "reply " << i;
  }
  const auto& m = [&](std::size_t i) -> const std::string& { return commands.replies[i].message; };
  EXPECT_EQ(m(0).rfind("map not saved to " + dir + "/early.alemap: ", 0), 0u) << m(0);
  EXPECT_NE(m(0).find("no map to save yet"), std::string::npos) << m(0);
  EXPECT_EQ(m(1).rfind("map saved to " + dir + "/a.alemap: 0 keyframes, 0 landmarks in ", 0), 0u) << m(1);
  EXPECT_NE(m(1).find(" bytes, "), std::string::npos) << m(1);
  EXPECT_NE(m(1).find(" ms", m(1).size() - 3), std::string::npos) << m(1);
  EXPECT_EQ(m(2).rfind("map not saved to " + dir + "/no/such/dir/b.alemap: ", 0), 0u) << m(2);
  EXPECT_NE(m(2).find("; the previous file is kept", m(2).size() - 27), std::string::npos) << m(2);
  for (std::size_t i : {3u, 4u}) {
    EXPECT_EQ(m(i).rfind("map file " + dir + (i == 3 ? "/missing" : "/noise") + ".alemap not loaded: ", 0), 0u) << m(i);
    EXPECT_NE(m(i).find("; the map is as it was", m(i).size() - 22), std::string::npos) << m(i);
  }
  EXPECT_EQ(m(5).rfind("map saved to " + dir + "/home.alemap: ", 0), 0u) << m(5);
  EXPECT_EQ(m(6), "no path given and map.load is not set");
  EXPECT_EQ(m(7).rfind("map loaded from " + dir + "/a.alemap: 0 keyframes", 0), 0u) << m(7);
  EXPECT_FALSE(test::read_file(dir + "/a.alemap").empty());
  EXPECT_TRUE(test::read_file(dir + "/early.alemap").empty());
  EXPECT_TRUE(test::read_file(dir + "/noise.alemap.refused").empty()) << "only map.load at start sets a file aside";

  // 2 by command and map.save at the end; the save without a map is no failure, the other one is
  EXPECT_EQ(summary.map_saves, 3u);
  EXPECT_EQ(summary.map_save_failures, 1u);
  EXPECT_EQ(summary.save.count, 3u);
  EXPECT_EQ(summary.commands_rejected, 5u);
  EXPECT_EQ(summary.frames, 9u);
  ASSERT_EQ(sink.reports.size(), 9u);
  const hal::StatusReport& last = sink.reports.back();  // before the save at the end
  EXPECT_EQ(last.map_saves, 2u);
  EXPECT_EQ(last.map_save_failures, 1u);
  EXPECT_GT(last.last_save_ms, 0.0f);
  EXPECT_EQ(sink.reports[0].map_saves, 0u);
  EXPECT_EQ(sink.reports[1].map_saves, 1u) << "the first save came before the second frame";
  EXPECT_EQ(summary.frames_after_map_file.count + summary.other_frames.count, 9u);
  EXPECT_EQ(summary.frames_after_map_file.count, 7u) << "the frames after commands 2 to 6 and 8";
}

TEST(FrameLoopTest, ProcessFpsSkipsEvenlyAndCountsTheSkipped) {
  hal::FakeCamera cam(frames(10));  // 30 fps timestamps
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.slam.process_fps = 15;
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps_of(cam, sink, gpio), summary).ok());
  EXPECT_EQ(summary.frames, 5u);
  EXPECT_EQ(summary.frames_skipped, 5u);
  ASSERT_EQ(sink.poses.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(sink.poses[i].frame_sequence, 2 * i);
  EXPECT_EQ(sink.reports.back().frames_skipped, 4u) << "skipped before the last processed frame";
  EXPECT_EQ(sink.reports.back().frames_dropped, 0u) << "skipped is not dropped";
  EXPECT_EQ(cam.pool().stats().in_use, 0u);
}

TEST(FrameLoopTest, StatusCarriesStageTimesAndCameraState) {
  hal::FakeCamera cam(frames(2));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps_of(cam, sink, gpio), summary).ok());
  ASSERT_EQ(sink.reports.size(), 2u);
  const hal::StatusReport& r = sink.reports[1];
  EXPECT_GT(r.timings.count, 2u) << "the frame path's stages";
  EXPECT_EQ(r.camera_state, hal::CameraState::kStreaming);
  // the camera's buffers and the map store's two arenas
  ASSERT_EQ(r.pool_count, 3u);
  auto pool = [&](const char* name) -> const hal::PoolUse* {
    for (std::size_t i = 0; i < r.pool_count; ++i)
      if (std::strcmp(r.pools[i].name, name) == 0) return &r.pools[i];
    return nullptr;
  };
  const hal::PoolUse* cam_pool = pool("camera_buffers");
  ASSERT_NE(cam_pool, nullptr);
  EXPECT_EQ(cam_pool->high_water, 1u) << "one frame lent at a time";
  EXPECT_EQ(cam_pool->capacity, 3u);
  const hal::PoolUse* kf_pool = pool("map_keyframes");
  ASSERT_NE(kf_pool, nullptr);
  EXPECT_EQ(kf_pool->capacity, static_cast<std::uint64_t>(config.slam.capacity.max_keyframes));
  ASSERT_NE(pool("map_landmarks"), nullptr);
  EXPECT_EQ(r.frames_skipped, 0u);
  EXPECT_EQ(r.publish_errors, 0u);
}

// A sink whose every publish fails: counted, the loop goes on.
class FailingSink final : public hal::PoseSink {
 public:
  Status publish(const hal::PoseEstimate&) override { return io_error("pose: no route"); }
  Status publish(const hal::StatusReport&) override { return io_error("status: no route"); }
};

TEST(FrameLoopTest, CountsFailedPublishesAndKeepsRunning) {
  hal::FakeCamera cam(frames(3));
  FailingSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps_of(cam, sink, gpio), summary).ok());
  EXPECT_EQ(summary.frames, 3u);
  EXPECT_EQ(summary.publish_errors, 6u);
  EXPECT_NE(last_error().find("no route"), std::string::npos) << last_error();
}

// A reload request before the first frame (an eventfd stands in for the SIGHUP signalfd).
struct ReloadRun {
  hal::FakePoseSink sink;
  RunSummary summary;
  std::vector<DaemonConfig> applied;
  Status result;
  int fd_left = 0;  // what was still readable on the request descriptor afterwards
};

ReloadRun run_with_reload(const DaemonConfig& config, LoadConfig load) {
  ReloadRun r;
  hal::FakeCamera cam(frames(3));
  hal::NullGpio gpio;
  const int fd = eventfd(1, EFD_NONBLOCK);
  LoopDeps deps = deps_of(cam, r.sink, gpio);
  deps.reload_fd = fd;
  deps.load_config = std::move(load);
  deps.apply_config = [&r](const DaemonConfig& c) {
    r.applied.push_back(c);
    return Status{};
  };
  r.result = run_frame_loop(config, deps, r.summary);
  std::uint64_t left = 0;
  r.fd_left = static_cast<int>(::read(fd, &left, sizeof left));
  ::close(fd);
  return r;
}

TEST(FrameLoopTest, ReloadTakesOverRuntimeKeysAndKeepsTheRest) {
  DaemonConfig config;
  ReloadRun r = run_with_reload(config, [](DaemonConfig& c) {
    return parse_config("[log]\nlevel = warning\n[lcm]\npose_channel = ROBOT_POSE\n[gpio]\nir_on_dark_frames = 2\n"
                        "[camera]\nwidth = 320\n",
                        "reload.conf", c);
  });
  const LogLevel level_after = log_level();
  set_log_level(LogLevel::kInfo);
  ASSERT_TRUE(r.result.ok()) << r.result.to_string();
  EXPECT_EQ(r.summary.config_generation, 1);
  EXPECT_EQ(level_after, LogLevel::kWarning);
  ASSERT_EQ(r.applied.size(), 1u);
  EXPECT_EQ(r.applied[0].lcm.pose_channel, "ROBOT_POSE");
  EXPECT_EQ(r.applied[0].gpio.ir_on_dark_frames, 2);
  EXPECT_EQ(r.applied[0].camera.width, 640) << "the capture size needs a restart";
  ASSERT_FALSE(r.sink.reports.empty());
  EXPECT_EQ(r.sink.reports.back().config_generation, 1);
  EXPECT_EQ(r.summary.frames, 3u);
  EXPECT_LT(r.fd_left, 0) << "the request was drained";
}

TEST(FrameLoopTest, ABadReloadIsLoggedAndTheOldConfigurationKept) {
  DaemonConfig config;
  ReloadRun r = run_with_reload(config, [](DaemonConfig& c) {
    return parse_config("[gpio]\nir_on_dark_frames = 0\n", "bad.conf", c);  // out of range
  });
  ASSERT_TRUE(r.result.ok()) << r.result.to_string();
  EXPECT_EQ(r.summary.config_generation, 0);
  EXPECT_EQ(r.summary.reloads_refused, 1u);
  EXPECT_TRUE(r.applied.empty());
  EXPECT_EQ(r.summary.frames, 3u) << "the daemon keeps running";
  ASSERT_FALSE(r.sink.reports.empty());
  EXPECT_EQ(r.sink.reports.back().config_generation, 0);
  EXPECT_NE(r.sink.reports.back().last_error.find("gpio.ir_on_dark_frames"), std::string::npos)
      << r.sink.reports.back().last_error;
}

// SIGHUP mid-run with new grading thresholds: the frames after the reload are graded by them, the
// held class is kept, and a restart-only key of the same file is logged, not applied.
TEST(FrameLoopTest, ReloadAppliesEnhancementThresholdsFromTheNextFrame) {
  std::vector<GrayImage> v;
  for (int i = 0; i < 6; ++i) v.emplace_back(64, 48, 100);  // normal by the default thresholds
  hal::FakeCamera cam(std::move(v));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  const int fd = eventfd(0, EFD_NONBLOCK);
  ASSERT_GE(fd, 0);
  LoopDeps deps = deps_of(cam, sink, gpio);
  deps.reload_fd = fd;
  deps.load_config = [](DaemonConfig& c) {
    return parse_config("[features.enhance.grading]\nt_low = 120\nt_high = 200\n[features]\nnum_features = 300\n",
                        "reload.conf", c);
  };
  deps.on_frame = [fd](const RunSummary& s, const FrameRecord&) {
    if (s.frames == 2) {
      const std::uint64_t one = 1;
      ASSERT_EQ(::write(fd, &one, sizeof one), static_cast<ssize_t>(sizeof one));  // SIGHUP after frame 2
    }
  };
  RunSummary summary;
  const Status s = run_frame_loop(config, deps, summary);
  ::close(fd);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_EQ(summary.frames, 6u);
  EXPECT_EQ(summary.config_generation, 1);
  // Frame statuses only (the reload's own status repeats the last frame's timestamp).
  std::vector<BrightnessClass> per_frame;
  std::vector<int> generation;
  for (std::size_t i = 0; i < sink.reports.size(); ++i) {
    if (i > 0 && sink.reports[i].timestamp_ns == sink.reports[i - 1].timestamp_ns) continue;
    per_frame.push_back(sink.reports[i].brightness);
    generation.push_back(sink.reports[i].config_generation);
  }
  ASSERT_EQ(per_frame.size(), 6u);
  EXPECT_EQ(per_frame[0], BrightnessClass::kNormal);
  EXPECT_EQ(per_frame[1], BrightnessClass::kNormal);
  for (std::size_t i = 2; i < 6; ++i) {
    EXPECT_EQ(per_frame[i], BrightnessClass::kDark) << "frame " << i << ": 100 < t_low 120 - hysteresis";
    EXPECT_EQ(generation[i], 1);
  }
  EXPECT_EQ(summary.resets, 0) << "no reset (rendered_map_test.cpp: a reload keeps a map with keyframes)";
}

TEST(FrameLoopTest, PublishesTheBodyPoseThroughTheCalibrationsExtrinsics) {
  ALE_REQUIRE_DATA(dataset, "euroc_v101_micro");
  auto cam = replay::open_replay(dataset, replay::ReplayOptions{});
  ASSERT_TRUE(cam.ok()) << cam.status().to_string();
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.daemon.max_frames = 2;
  config.daemon.body_frame = "calibration";
  RunSummary summary;
  LoopDeps deps{**cam, sink, gpio};
  auto lens = (*cam)->calibration();
  ASSERT_TRUE(lens.ok()) << lens.status().to_string();
  deps.calibration = *lens;
  ASSERT_TRUE(run_frame_loop(config, deps, summary).ok());
  ASSERT_EQ(sink.poses.size(), 2u);
  const hal::PoseEstimate& p = sink.poses[1];
  EXPECT_TRUE(p.body_valid);
  // EuRoC V1_01 cam0 sensor.yaml, T_BS translation.
  EXPECT_NEAR(p.p_bc[0], -0.0216401454975, 1e-12);
  EXPECT_NEAR(p.p_bc[1], -0.064676986768, 1e-12);
  EXPECT_NEAR(p.p_bc[2], 0.00981073058949, 1e-12);
  // The camera at the map origin: the body sits at -R_bc^T p_bc.
  EXPECT_NEAR(p.p_wb[0] * p.p_wb[0] + p.p_wb[1] * p.p_wb[1] + p.p_wb[2] * p.p_wb[2],
              p.p_bc[0] * p.p_bc[0] + p.p_bc[1] * p.p_bc[1] + p.p_bc[2] * p.p_bc[2], 1e-12);
}

// The recorder failing (a full disk here) stops recording with a logged error; every frame is
// still processed and published, and the status says the recorder stopped and why.
TEST(FrameLoopTest, ARecorderWriteErrorNeverStopsTracking) {
  hal::FakeCamera cam(frames(6));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.recorder.dir = test::make_temp_dir("loop-recorder");
  LoopDeps deps = deps_of(cam, sink, gpio);
  deps.record_writer = [](const std::string& path, GrayView) {
    return io_error(path + ": cannot write PNG: Write Error (No space left on device)");
  };
  RunSummary summary;
  const Status s = run_frame_loop(config, deps, summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_TRUE(summary.end_of_stream);
  EXPECT_EQ(summary.frames, 6u);
  EXPECT_EQ(sink.poses.size(), 6u);
  EXPECT_EQ(summary.recorder.state, hal::RecorderState::kStopped);
  EXPECT_EQ(summary.recorder.frames_recorded, 0u);
  EXPECT_EQ(summary.recorder.frames_not_recorded, 6u);
  ASSERT_FALSE(sink.reports.empty());
  const hal::StatusReport& last = sink.reports.back();
  EXPECT_EQ(last.recorder_state, hal::RecorderState::kStopped);
  EXPECT_EQ(last.frames_not_recorded, 6u);
  EXPECT_NE(last.last_error.find("No space left on device"), std::string::npos) << last.last_error;
  EXPECT_EQ(cam.pool().stats().in_use, 0u);
}

TEST(FrameLoopTest, AnUnwritableRecorderFolderIsLoggedAndTrackingGoesOn) {
  hal::FakeCamera cam(frames(3));
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  const std::string base = test::make_temp_dir("loop-recorder");
  ASSERT_TRUE(test::write_file(base + "/file", "x"));
  config.recorder.dir = base + "/file/rec";
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps_of(cam, sink, gpio), summary).ok());
  EXPECT_EQ(summary.frames, 3u);
  EXPECT_EQ(summary.recorder.state, hal::RecorderState::kStopped);
  EXPECT_NE(last_error().find("recorder.dir " + config.recorder.dir), std::string::npos) << last_error();
}

}  // namespace
}  // namespace ale::app
