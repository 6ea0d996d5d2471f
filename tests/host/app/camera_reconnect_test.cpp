// Camera loss: the loop over a V4L2 camera whose driver (the in-memory FakeV4l2Driver behind the
// injectable system-call layer) is unplugged and plugged back in, on a fake clock that the loop's
// waits advance (camera_reconnect_fixture.h). That the map is kept across it is tested on
// rendered frames, which make one (rendered_map_test.cpp).
#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/daemon/frame_loop.h"
#include "hal/replay/dataset.h"
#include "tests/host/app/camera_reconnect_fixture.h"
#include "tests/host/support/test_data.h"

namespace ale::app {
namespace {

using test::kMsNs;
using CameraReconnect = test::CameraReconnectFixture;

TEST_F(CameraReconnect, ReopensWithBackoffAfterADisconnectAndFramesResume) {
  hal::FakePoseSink sink;
  config_.daemon.max_frames = 10;
  RunSummary summary;
  Status s = run_frame_loop(config_, deps(sink), summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_EQ(summary.frames, 10u) << "five before the disconnect, five after";
  EXPECT_EQ(summary.camera_reconnects, 1u);
  EXPECT_EQ(summary.frame_errors, 0u) << "the loss is seen when the fifth frame is given back, not as a frame error";
  // Doubling from 250 ms to the 1 s cap; the device is back 3 s after it went, seen at 3.75 s.
  EXPECT_EQ(waits_ms_, (std::vector<std::int64_t>{250, 500, 1000, 1000, 1000}));
  EXPECT_EQ(reopen_calls_, 5);
  ASSERT_EQ(sink.poses.size(), 10u);
  EXPECT_EQ(sink.poses[4].timestamp_ns, 4 * 33 * kMsNs);
  EXPECT_EQ(sink.poses[5].timestamp_ns, 10000 * kMsNs) << "the first frame after the reconnect";
  EXPECT_EQ(sink.poses[9].map_id, 0) << "no map reset (rendered_map_test.cpp has a map to keep)";

  // The controller saw the camera go and come back.
  std::vector<hal::CameraState> states;
  for (const hal::StatusReport& r : sink.reports)
    if (states.empty() || states.back() != r.camera_state) states.push_back(r.camera_state);
  EXPECT_EQ(states, (std::vector<hal::CameraState>{hal::CameraState::kStreaming, hal::CameraState::kReconnecting,
                                                   hal::CameraState::kStreaming}));
  int reconnecting = 0;
  for (const hal::StatusReport& r : sink.reports) reconnecting += r.camera_state == hal::CameraState::kReconnecting;
  EXPECT_EQ(reconnecting, 5) << "one when lost, one after each of the four failed tries";
  EXPECT_EQ(sink.reports.back().camera_reconnects, 1u);
  EXPECT_NE(sink.reports.back().last_error.find("camera lost"), std::string::npos) << sink.reports.back().last_error;
  camera_.reset();
  EXPECT_EQ(driver_.open_fds, 0) << "every descriptor closed, the old camera's too";
}

// A reopened camera is a new camera session: the recorder starts a second sequence, and each
// replays as recorded.
TEST_F(CameraReconnect, TheRecorderStartsANewSequenceAfterAReconnect) {
  hal::FakePoseSink sink;
  config_.daemon.max_frames = 10;
  config_.recorder.dir = test::make_temp_dir("reconnect-recorder");
  config_.recorder.queue_frames = 16;  // a live camera: every frame of both sessions fits, however slow the writer
  RunSummary summary;
  Status s = run_frame_loop(config_, deps(sink), summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_EQ(summary.camera_reconnects, 1u);
  EXPECT_EQ(summary.recorder.frames_recorded, 10u) ;
  std::vector<std::string> seqs;
  for (const auto& e : std::filesystem::directory_iterator(config_.recorder.dir)) seqs.push_back(e.path().string());
  std::sort(seqs.begin(), seqs.end());
  ASSERT_EQ(seqs.size(), 2u);
  const std::int64_t first[] = {0, 10000 * kMsNs};
  for (std::size_t i = 0; i < 2; ++i) {
    Result<replay::Dataset> ds = replay::open_dataset(seqs[i]);
    ASSERT_TRUE(ds.ok()) << ds.status().to_string();
    ASSERT_EQ(ds->frames.size(), 5u);
    EXPECT_EQ(ds->frames[0].timestamp_ns, first[i]);
    EXPECT_EQ(ds->width, 64);
  }
}

TEST_F(CameraReconnect, GivesUpAfterTheConfiguredTimeAndSaysSo) {
  replug_after_ns_ = -1;  // never comes back
  config_.camera.reconnect_give_up_ms = 2000;
  hal::FakePoseSink sink;
  RunSummary summary;
  Status s = run_frame_loop(config_, deps(sink), summary);
  EXPECT_EQ(s.code(), StatusCode::kUnavailable);
  EXPECT_NE(s.message().find("not back after 2750 ms"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("reconnect_give_up_ms"), std::string::npos) << s.message();
  EXPECT_EQ(summary.frames, 5u);
  EXPECT_EQ(summary.camera_reconnects, 0u);
  EXPECT_EQ(waits_ms_, (std::vector<std::int64_t>{250, 500, 1000, 1000}));
  ASSERT_FALSE(sink.reports.empty());
  EXPECT_EQ(sink.reports.back().camera_state, hal::CameraState::kGone);
  EXPECT_FALSE(gpio_.state(hal::GpioLine::kStatusLed)) << "LED off when the daemon exits";
}

TEST_F(CameraReconnect, WithoutAReopenerALostCameraEndsTheLoop) {
  hal::FakePoseSink sink;
  RunSummary summary;
  LoopDeps d = deps(sink);
  d.reopen_camera = nullptr;
  Status s = run_frame_loop(config_, d, summary);
  EXPECT_EQ(s.code(), StatusCode::kUnavailable);
  EXPECT_EQ(summary.frames, 5u);
  EXPECT_TRUE(waits_ms_.empty());
}

TEST_F(CameraReconnect, ACameraThatOpensButStaysSilentIsGivenUpToo) {
  driver_.vanish_after = -1;  // five frames, then nothing: poll times out, DQBUF says EAGAIN
  replug_after_ns_ = -1;
  config_.camera.max_consecutive_errors = 3;
  config_.camera.reconnect_give_up_ms = 1000;
  hal::FakePoseSink sink;
  RunSummary summary;
  Status s = run_frame_loop(config_, deps(sink), summary);
  // Three silent periods count as a lost camera; it reopens (the node is there) and stays
  // silent. The give-up time runs from the last frame, not from each reopen: four reopens,
  // 250 ms apart on the fake clock, then the daemon exits.
  EXPECT_EQ(s.code(), StatusCode::kUnavailable) << s.to_string();
  EXPECT_EQ(summary.frames, 5u);
  EXPECT_EQ(reopen_calls_, 4);
  EXPECT_EQ(summary.camera_reconnects, 4u);
  EXPECT_EQ(summary.frame_errors, 15u) << "three timeouts before each of the five losses";
  bool saw_timeout = false;
  for (const hal::StatusReport& r : sink.reports) saw_timeout |= r.camera_state == hal::CameraState::kTimeout;
  EXPECT_TRUE(saw_timeout);
  EXPECT_EQ(sink.reports.back().camera_state, hal::CameraState::kGone);
}

// The loop's own waits (no injected clock or wait), the camera never back: before reopen try
// `reload_at` a reload of `hup` is requested, before try `stop_at` a stop.
class CameraReconnectRealWaits : public CameraReconnect {
 protected:
  struct Run {
    Status status;
    RunSummary summary;
    int tries = 0;
    double elapsed_ms = 0.0;
  };

  Run run(const std::string& hup, int reload_at, int stop_at) {
    replug_after_ns_ = -1;
    const int reload_fd = eventfd(0, EFD_NONBLOCK);
    const int stop_fd = eventfd(0, EFD_NONBLOCK);
    hal::FakePoseSink sink;
    Run r;
    LoopDeps d{*camera_, sink, gpio_};
    d.calibration = lens();
    d.stop_fd = stop_fd;
    d.reload_fd = reload_fd;
    d.load_config = [hup](DaemonConfig& c) { return parse_config(hup, "hup.conf", c); };
    d.reopen_camera = [&]() -> Result<hal::Camera*> {
      const std::uint64_t one = 1;
      ++r.tries;
      if (r.tries == reload_at) {
        EXPECT_EQ(::write(reload_fd, &one, sizeof one), 8);
      }
      if (r.tries == stop_at) {
        EXPECT_EQ(::write(stop_fd, &one, sizeof one), 8);
      }
      return reopen();
    };
    const auto t0 = std::chrono::steady_clock::now();
    r.status = run_frame_loop(config_, d, r.summary);
    r.elapsed_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ::close(reload_fd);
    ::close(stop_fd);
    return r;
  }
};

// A reload requested while the camera is away is served, a stop request ends the wait at once.
TEST_F(CameraReconnectRealWaits, ServeReloadsAndStops) {
  config_.camera.reconnect_initial_ms = 10;
  config_.camera.reconnect_max_ms = 20;
  // far beyond the three tries (30 ms of waits), so that a loaded machine does not give up first
  // (100 ms did: the waits took 41, 71 and 144 ms under load)
  config_.camera.reconnect_give_up_ms = 2000;
  const Run r = run("[gpio]\nir_on_dark_frames = 3\n", 1, 3);
  ASSERT_TRUE(r.status.ok()) << r.status.to_string();
  EXPECT_TRUE(r.summary.stopped_by_signal);
  EXPECT_EQ(r.summary.config_generation, 1) << "the reload during the second wait";
  EXPECT_EQ(r.tries, 3);
  EXPECT_GE(r.elapsed_ms, 30.0) << "waits of 10 and 20 ms before the second and third tries";
  EXPECT_LT(r.elapsed_ms, 1000.0);
}

// A reload that shortens camera.reconnect_give_up_ms applies to the reconnection under way: the
// loop gives up by the new limit, not the one it started with. The stop request comes far beyond
// the new limit (200 ms, about 10 tries), so that a loop keeping the old one ends the test.
TEST_F(CameraReconnectRealWaits, AReloadedGiveUpTimeAppliesToTheReconnectionUnderWay) {
  config_.camera.reconnect_initial_ms = 10;
  config_.camera.reconnect_max_ms = 20;
  config_.camera.reconnect_give_up_ms = 600000;
  const Run r = run("[camera]\nreconnect_initial_ms = 10\nreconnect_max_ms = 20\nreconnect_give_up_ms = 200\n", 1, 500);
  EXPECT_EQ(r.summary.config_generation, 1);
  EXPECT_FALSE(r.summary.stopped_by_signal) << "still reconnecting after " << r.tries
                                            << " tries: the reloaded limit was not applied";
  EXPECT_EQ(r.status.code(), StatusCode::kUnavailable) << r.status.to_string();
  EXPECT_NE(r.status.message().find("camera.reconnect_give_up_ms = 200"), std::string::npos) << r.status.message();
  EXPECT_LT(r.tries, 500);
}

}  // namespace
}  // namespace ale::app
