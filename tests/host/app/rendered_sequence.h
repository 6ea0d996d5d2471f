// Sequences ale-render makes at test time for the daemon's loop tests (app_render_test: the
// target defines ALE_RENDER_BIN), and the loop's dependencies over their replay.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "app/daemon/frame_loop.h"
#include "hal/replay/replay_camera.h"

namespace ale::test {

// Renders into `out` (ale-render --out OUT ARGS, its report in OUT.txt); fails the calling test
// when the tool fails.
inline ::testing::AssertionResult render_sequence(const std::string& out, const std::string& args) {
  const std::string command = std::string(ALE_RENDER_BIN) + " --out " + out + " " + args + " > " + out + ".txt";
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
};

}  // namespace ale::test
