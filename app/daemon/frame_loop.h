// The daemon's one event loop: frames from the camera, through the per-frame pipeline, to the
// pose sink; commands from the command channel; the status LED and IR illuminator. Stops on a
// signal, at the end of a replay, or when the camera stays away past the give-up time.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "app/config.h"
#include "app/daemon/frame_pipeline.h"
#include "app/daemon/odometry_input.h"
#include "app/daemon/recorder.h"
#include "hal/camera.h"
#include "hal/clock.h"
#include "hal/command_channel.h"
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
  std::uint64_t frames = 0;          // processed
  // Delivered but not processed: released on purpose (slam.process_fps, paused) or refused by
  // the pipeline (another size, time going back).
  std::uint64_t frames_skipped = 0;
  std::uint64_t frame_errors = 0;    // frames the camera could not deliver (corrupt, timeouts)
  std::uint64_t publish_errors = 0;
  std::uint64_t tracked = 0;         // frames published with a pose
  int keyframes = 0;                 // in the map at the end
  int landmarks = 0;
  int resets = 0;                    // new maps started after tracking was lost
  int relocalisations = 0;           // losses ended by relocalisation in the same map
  int loops_closed = 0;              // drift corrected by a loop closed
  int loops_refused = 0;             // verified loops refused by the correction bound
  int merges = 0;                    // older maps the current map moved into (recognised a place of)
  int merges_refused = 0;            // verified places of another map not joined
  FrameTimeHistogram frame_time_ms;  // of every processed frame
  std::uint64_t commands = 0;
  std::uint64_t commands_rejected = 0;
  std::uint64_t camera_reconnects = 0;  // camera reopened after it went away
  int config_generation = 0;            // configuration reloads applied
  std::uint64_t reloads_refused = 0;
  std::int64_t first_status_ns = -1;    // steady-clock time from start_ns to the first status published
  RecorderStats recorder;               // recorder.dir; state kOff when not configured
  std::uint64_t odometry_accepted = 0;  // wheel odometry samples the SLAM core kept
  std::uint64_t odometry_refused = 0;   // refused by its checks, or messages that did not decode
  // Map saves (map.save_period_s, SAVE_MAP, the end of the run) that succeeded and that failed,
  // and the time of those that succeeded.
  std::uint64_t map_saves = 0;
  std::uint64_t map_save_failures = 0;
  CostFigure save;
  // The frame time of the processed frames that waited for a map save or load done between the
  // previous frame and them (its time is in theirs), and of all the others.
  CostFigure frames_after_map_file;
  CostFigure other_frames;
  bool stopped_by_signal = false;
  bool end_of_stream = false;
};

// Closes the camera that went away and opens it again; returns the new one (owned by the
// caller, e.g. the board) or why it cannot be opened yet.
using ReopenCamera = std::function<Result<ale::hal::Camera*>()>;
// Waits up to wait_ns; true when the daemon must stop meanwhile.
using WaitFor = std::function<bool(std::int64_t wait_ns)>;
// Reads the configuration again (file and command line) into `config`; an error keeps the old one.
using LoadConfig = std::function<Status(DaemonConfig& config)>;
// Hands a reloaded configuration to what lives outside the loop (the LCM channels).
using ApplyConfig = std::function<Status(const DaemonConfig& config)>;

struct LoopDeps {
  ale::hal::Camera& camera;
  ale::hal::PoseSink& sink;
  ale::hal::Gpio& gpio;
  int stop_fd = -1;                                 // readable when the daemon must stop (a signalfd)
  ale::hal::CommandChannel* commands = nullptr;     // null: no commands
  ReopenCamera reopen_camera = nullptr;             // null: a lost camera ends the loop
  const ale::hal::Clock* clock = nullptr;           // for backoff and give-up; null: steady clock
  WaitFor wait = nullptr;                           // null: poll on stop_fd
  int reload_fd = -1;                               // readable when the configuration must be reloaded (SIGHUP)
  LoadConfig load_config = nullptr;                 // null: reload requests are ignored
  ApplyConfig apply_config = nullptr;
  std::int64_t start_ns = 0;                        // steady-clock time the process started (0: unknown)
  ale::hal::CameraCalibration calibration{};        // the lens (Board::calibration)
  FrameFileWriter record_writer = nullptr;          // the recorder's PNG writer; null: io::write_png
  // Wheel odometry (odometry_input.h): a replay's samples, handed over before each frame.
  ReplayOdometry replay_odometry{};
  // The odometry's description for the recorder's mav0/odometry0/sensor.yaml; unset: samples are
  // not recorded (there are none without a T_bc).
  std::optional<OdometrySensor> odometry_sensor = std::nullopt;
  // Appends the samples received since the last call (LCM), in arrival order, and returns how
  // many messages did not decode; called whenever commands are drained. Null: none.
  std::function<std::uint64_t(std::vector<ale::slam::OdometrySample>&)> take_odometry = nullptr;
  // Called after each processed frame (a progress line, --verbose); may be empty.
  std::function<void(const RunSummary&, const FrameRecord&)> on_frame = nullptr;
};

// Runs until the end of the stream, a stop request or a camera that does not come back. Returns
// the reason the loop ended badly, if any; `summary` is filled in every case. A reload request
// takes over the keys that can change at run time (reload.h); a bad file is logged and refused.
Status run_frame_loop(const DaemonConfig& config, LoopDeps deps, RunSummary& summary);

}  // namespace ale::app
