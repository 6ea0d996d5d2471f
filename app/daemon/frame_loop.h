// The daemon's one event loop: frames from the camera, through the per-frame pipeline, to the
// pose sink; stops on a signal, at the end of a replay, or when the camera fails for good.
#pragma once

#include <cstdint>
#include <functional>

#include "app/config.h"
#include "hal/camera.h"
#include "hal/gpio.h"
#include "hal/pose_sink.h"

namespace ale::app {

struct RunSummary {
  std::uint64_t frames = 0;
  std::uint64_t frame_errors = 0;   // frames the camera could not deliver (corrupt, timeouts)
  std::uint64_t publish_errors = 0;
  bool stopped_by_signal = false;
  bool end_of_stream = false;
};

struct LoopDeps {
  ale::hal::Camera& camera;
  ale::hal::PoseSink& sink;
  ale::hal::Gpio& gpio;
  int stop_fd = -1;                         // readable when the daemon must stop (a signalfd)
  int aux_fd = -1;                          // e.g. LCM's fd: on_aux_ready() runs when it is readable
  std::function<void()> on_aux_ready = nullptr;
};

// Runs until the end of the stream, a stop request or a fatal camera error. Returns the reason
// the loop ended badly, if any; `summary` is filled in every case.
Status run_frame_loop(const DaemonConfig& config, LoopDeps deps, RunSummary& summary);

}  // namespace ale::app
