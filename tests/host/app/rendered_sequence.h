// Sequences ale-render makes at test time for the daemon's loop tests (app_render_test: the
// target defines ALE_RENDER_BIN), and the loop's dependencies over their replay.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>

#include "app/daemon/frame_loop.h"
#include "app/daemon/odometry_input.h"
#include "hal/replay/dataset.h"
#include "hal/replay/replay_camera.h"

namespace ale::test {

// The ale-render that makes the sequences: in a sanitizer build the host build's when it is
// there (ALE_RENDER_NATIVE: rendering is not what these tests test), else this build's.
inline std::string render_binary() {
#ifdef ALE_RENDER_NATIVE
  if (access(ALE_RENDER_NATIVE, X_OK) == 0) return ALE_RENDER_NATIVE;
#endif
  return ALE_RENDER_BIN;
}

// Renders into `out` (ale-render --out OUT ARGS, its report in OUT.txt); fails the calling test
// when the tool fails.
inline ::testing::AssertionResult render_sequence(const std::string& out, const std::string& args) {
  const std::string command = render_binary() + " --out " + out + " " + args + " > " + out + ".txt";
  if (std::system(command.c_str()) != 0) return ::testing::AssertionFailure() << command;
  return ::testing::AssertionSuccess();
}

// The replay of a rendered sequence and the loop's dependencies over it, its lens included.
struct RenderedReplay {
  std::unique_ptr<replay::ReplayCamera> camera;
  std::unique_ptr<app::LoopDeps> deps;

  ::testing::AssertionResult open(const std::string& dir, hal::PoseSink& sink, hal::Gpio& gpio) {
    auto cam = replay::open_replay(dir, replay::ReplayOptions{});
    if (!cam.ok()) return ::testing::AssertionFailure() << cam.status().to_string();
    camera = std::move(*cam);
    auto lens = camera->calibration();
    if (!lens.ok()) return ::testing::AssertionFailure() << lens.status().to_string();
    deps = std::make_unique<app::LoopDeps>(app::LoopDeps{*camera, sink, gpio});
    deps->calibration = *lens;
    return ::testing::AssertionSuccess();
  }

  // The sequence's wheel odometry (DIR/mav0/odometry0) fused, as ale-slamd --replay does (the
  // camera's mounting goes into config.slam.odometry).
  ::testing::AssertionResult fuse_odometry(const std::string& dir, app::DaemonConfig& config) {
    const Result<replay::OdometryTrack> track = replay::read_odometry_folder(dir + "/mav0/odometry0");
    if (!track.ok()) return ::testing::AssertionFailure() << track.status().to_string();
    app::OdometryPlan plan;
    if (Status s = app::resolve_odometry(config, *track, plan); !s.ok()) return ::testing::AssertionFailure() << s.to_string();
    if (plan.replay.empty()) return ::testing::AssertionFailure() << dir << ": no odometry to replay";
    deps->replay_odometry = app::ReplayOdometry(std::move(plan.replay), config.slam.odometry.clock_offset_ns,
                                                std::llround(config.odometry.lookahead_ms * 1e6));
    return ::testing::AssertionSuccess();
  }
};

}  // namespace ale::test
