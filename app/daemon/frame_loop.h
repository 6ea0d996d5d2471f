// The daemon's one event loop: frames from the camera, through the per-frame pipeline, to the
// pose sink; stops on a signal, at the end of a replay, or when the camera fails for good.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "app/config.h"
#include "app/daemon/frame_pipeline.h"
#include "hal/camera.h"
#include "hal/gpio.h"
#include "hal/pose_sink.h"

namespace ale::app {

// Frame times for the run's median and 95th percentile in fixed memory (a daemon runs for days):
// 0.01 ms bins to 100 ms, 1 ms bins to 10 s, one bin beyond.
class FrameTimeHistogram {
 public:
  void add(double ms);
  std::uint64_t count() const { return count_; }
  // The upper edge of the bin holding quantile q (0..1) of the times; 0 when empty.
  double quantile(double q) const;

 private:
  static constexpr int kFine = 10000;   // 0.01 ms each
  static constexpr int kCoarse = 9900;  // 1 ms each, 100 ms .. 10 s
  std::vector<std::uint32_t> bins_ = std::vector<std::uint32_t>(kFine + kCoarse + 1, 0u);
  std::uint64_t count_ = 0;
};

struct RunSummary {
  std::uint64_t frames = 0;         // processed
  std::uint64_t frame_errors = 0;   // frames the camera could not deliver (corrupt, timeouts)
  std::uint64_t frames_skipped = 0; // delivered but refused by the pipeline (wrong size, time going back)
  std::uint64_t publish_errors = 0;
  std::uint64_t tracked = 0;        // frames published with a pose
  int keyframes = 0;                // in the map at the end
  int landmarks = 0;
  int resets = 0;                   // new maps started after tracking was lost
  FrameTimeHistogram frame_time_ms; // of every processed frame
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
  ale::hal::CameraCalibration calibration{};  // the lens (Board::calibration)
  // Called after each processed frame (a progress line, --verbose); may be empty.
  std::function<void(const RunSummary&, const FrameRecord&)> on_frame = nullptr;
};

// Runs until the end of the stream, a stop request or a fatal camera error. Returns the reason
// the loop ended badly, if any; `summary` is filled in every case.
Status run_frame_loop(const DaemonConfig& config, LoopDeps deps, RunSummary& summary);

}  // namespace ale::app
