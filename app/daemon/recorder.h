// The recorder (recorder.dir): the raw camera frames and their timestamps, and the wheel odometry
// samples the daemon received, written as EuRoC ASL sequences (hal/replay/euroc_writer.h) that
// `ale-slamd --replay` reads back unchanged.
//
// The frame loop only copies a frame into one of a fixed set of buffers (submit()); a writer
// thread encodes the PNGs, lists them in data.csv and keeps the folder under its cap, so the loop
// never waits for a disk. Odometry samples are copied into a bounded queue of their own
// (submit_odometry(), never waiting) and listed by the same thread in mav0/odometry0/ of the
// sequence of the camera session they arrived in (one that arrives before its session's first
// frame waits for it). A camera that needs no waiting (a replay) is recorded completely: submit()
// waits for a free buffer. A live camera's frame that finds every buffer queued is not recorded
// and counted. A write error or a full disk stops recording (an error event the loop
// logs); tracking never depends on the recorder.
//
// Sequences are folders <dir>/<NNNNNN>_<UTC start time> (NNNNNN counts up over the folder's life,
// so the order survives a wrong clock); one per daemon start and per camera session
// (new_sequence()). When the recordings would pass the cap the oldest sequence is deleted first;
// nothing else in dir is touched. The current sequence alone reaching the cap stops recording.
#pragma once

#include <array>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"
#include "app/daemon/log.h"
#include "core/io/image_io.h"
#include "core/slam/odometry.h"
#include "hal/camera.h"
#include "hal/pose_sink.h"
#include "hal/replay/euroc_writer.h"

namespace ale::app {

// Writes one frame's PNG file; io::write_png by default (tests inject failures).
using FrameFileWriter = std::function<Status(const std::string& path, GrayView image)>;

// The odometry's sensor.yaml: the camera in the base frame the daemon runs with (row-major,
// p_base = T_bc * p_camera) and the MCU's rate (0: not known, left out).
struct OdometrySensor {
  std::array<double, 16> T_bc{};
  double rate_hz = 0.0;
};

struct RecorderOptions {
  std::string dir;
  std::uint64_t max_bytes = 1ull << 30;
  int queue_frames = 8;
  // Set: every sequence gets mav0/odometry0/ (its sensor.yaml at the start, data.csv with the
  // first sample). Not set: no odometry is recorded.
  std::optional<OdometrySensor> odometry;
  // Odometry samples held at most (queued, or waiting for their sequence's first frame); more are
  // not recorded and counted. 1024 is 10 s at 100 Hz, about 80 KiB.
  int queue_odometry = 1024;
  io::PngWriteOptions png{1, false};
  // submit() waits for a free buffer instead of leaving the frame out (a replay: nothing is lost).
  bool wait_when_full = false;
};

// Something the writer thread wants logged; the loop's thread logs it (the log is not shared
// between threads). kError: recording stopped (a write error, a full disk); kWarning: the cap
// stopped it; kInfo: a sequence started or an old one was dropped.
struct RecorderEvent {
  LogLevel level = LogLevel::kInfo;
  std::string message;
};

// A duration's count, sum and maximum, for the cost figures.
struct CostFigure {
  std::uint64_t count = 0;
  std::int64_t total_ns = 0;
  std::int64_t max_ns = 0;
  void add(std::int64_t ns);
  double mean_ms() const { return count == 0 ? 0.0 : static_cast<double>(total_ns) / 1e6 / static_cast<double>(count); }
  double max_ms() const { return static_cast<double>(max_ns) / 1e6; }
};

struct RecorderStats {
  hal::RecorderState state = hal::RecorderState::kOff;
  std::uint64_t frames_recorded = 0;
  std::uint64_t frames_not_recorded = 0;  // every buffer queued, or recording stopped
  std::uint64_t bytes = 0;                // of every sequence in dir (the cap's measure)
  std::uint64_t sequences_dropped = 0;
  std::uint64_t odometry_recorded = 0;
  // The queue full, recording stopped, no odometry sensor, no frame after it, or a sample the
  // file cannot take (a timestamp not after the last one, other columns than the first sample's).
  std::uint64_t odometry_not_recorded = 0;
  std::string sequence;                   // the folder being written; empty before the first frame
  CostFigure submit;                      // on the loop's thread: taking a buffer and the copy
  CostFigure waited;                      // wait_when_full: the loop waiting for a free buffer
  CostFigure write;                       // on the writer's thread: PNG, list, cap
};

class Recorder {
 public:
  explicit Recorder(RecorderOptions options, FrameFileWriter writer = nullptr);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Starts the writer thread, which first reads what dir holds (earlier sequences count against
  // the cap). Errors (dir cannot be made) arrive as events.
  void start();
  // The frames submitted from now on go to a new sequence; `lens` is written as its sensor.yaml
  // (fx 0: no sensor.yaml, and a warning event saying so; size 0: the frames' size).
  void new_sequence(const hal::CameraCalibration& lens);
  // Copies the frame (its image must stay valid only for this call).
  void submit(const hal::Frame& frame);
  // Copies the samples as received (the MCU's values and clock), in order; never waits.
  void submit_odometry(const std::vector<slam::OdometrySample>& samples);
  // The events since the last call, oldest first.
  std::vector<RecorderEvent> take_events();
  RecorderStats stats() const;
  // The status message's figures alone (stats() copies strings).
  void counters(hal::StatusReport& status) const;
  // Writes what is queued, then ends the writer thread. Idempotent.
  void finish();

 private:
  struct Slot {
    GrayImage image;
    std::int64_t timestamp_ns = 0;
    std::uint64_t session = 0;
  };
  struct QueuedSample {
    slam::OdometrySample sample;
    std::uint64_t session = 0;
  };
  struct Sequence {
    std::uint64_t number = 0;
    std::string path;
    std::uint64_t bytes = 0;
  };

  void run();
  void scan();
  bool open_sequence(std::uint64_t session, int width, int height);
  bool make_room(std::uint64_t needed);
  bool write(Slot& slot);
  // Lists the samples waiting whose sequence is open (all of them, not recorded, once recording
  // stopped or at the end: `final`).
  void write_odometry(bool final);
  bool write_row(const slam::OdometrySample& sample);
  void stop_recording(LogLevel level, const std::string& why);
  void event(LogLevel level, std::string message);
  std::uint64_t total_bytes() const;

  const RecorderOptions options_;
  FrameFileWriter writer_;

  mutable std::mutex mutex_;
  std::condition_variable work_;   // the writer waits for a queued slot or finish()
  std::condition_variable space_;  // submit() waits for a free slot (wait_when_full)
  std::vector<Slot> slots_;        // sized once; a slot belongs to whoever took its index
  std::vector<int> free_;          // slot indices
  std::vector<int> ring_;          // queued slot indices, oldest at ring_head_
  std::size_t ring_head_ = 0;
  std::size_t ring_count_ = 0;
  bool finishing_ = false;
  bool started_ = false;
  std::uint64_t session_ = 0;                 // bumped by new_sequence()
  std::optional<hal::CameraCalibration> lens_;  // of the current session
  std::size_t odometry_bound_ = 1;            // queue_odometry
  std::vector<QueuedSample> odometry_queue_;  // reserved once (odometry_bound_)
  std::size_t odometry_held_ = 0;             // queued or waiting in odometry_waiting_
  std::vector<RecorderEvent> events_;
  RecorderStats stats_;

  // The writer thread's own (no lock needed).
  std::vector<Sequence> sequences_;  // oldest first; the last is the open one when writing_
  std::optional<replay::EurocWriter> euroc_;
  std::uint64_t writing_session_ = 0;
  std::optional<std::int64_t> last_t_ns_;  // of the open sequence
  std::uint64_t last_frame_bytes_ = 0;
  std::vector<QueuedSample> odometry_taken_;    // swapped with odometry_queue_
  std::deque<QueuedSample> odometry_waiting_;   // arrival order
  std::optional<replay::OdometryWriter> odometry_writer_;  // of the open sequence
  bool odometry_warned_ = false;                // of the open sequence
  bool stopped_ = false;
  std::thread thread_;
};

}  // namespace ale::app
