#include "app/daemon/board.h"

#include "hal/replay/replay_camera.h"

namespace ale::app {

Status build_board(const DaemonConfig& config, Board& board) {
  if (config.camera.source == "replay") {
    ale::replay::ReplayOptions options;
    options.buffers = config.camera.buffers;
    auto cam = ale::replay::open_replay(config.camera.replay_path, options);
    if (!cam.ok()) return cam.status();
    board.camera = std::move(*cam);
  } else {
    return unsupported("camera.source = v4l2: the V4L2 backend is not wired in yet");
  }
  board.gpio = std::make_unique<ale::hal::NullGpio>();
  return {};
}

}  // namespace ale::app
