// A recorded dataset (EuRoC ASL or TUM layout) served as a camera: frames are decoded from their
// files into a fixed set of pooled buffers, stamped with the recorded time, and lent out like a
// V4L2 camera lends its mmap buffers. A replay runs as fast as the caller asks for frames.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/base/image.h"
#include "core/base/memory_pool.h"
#include "hal/camera.h"
#include "hal/clock.h"
#include "hal/replay/dataset.h"
#include "core/io/image_io.h"

namespace ale::replay {

// What acquire() does with a frame whose file cannot be decoded in the middle of a replay.
enum class BadFramePolicy {
  kReport,  // acquire() returns the error (naming the file); the next call serves the next frame
  kSkip,    // counted as dropped, acquire() serves the next good frame (a sequence gap shows it)
  kStop,    // acquire() returns the error, and so does every later call
};

struct ReplayOptions {
  int buffers = 4;              // frames that can be lent at once (1..64)
  std::size_t start_index = 0;  // first frame of the dataset to serve
  std::size_t max_frames = 0;   // frames to serve from there; 0: to the end
  BadFramePolicy on_bad_frame = BadFramePolicy::kReport;
  // The lens, for datasets that carry none (TUM); replaces sensor.yaml's when given. A size of
  // 0x0 takes the frames' size; any other size must match the frames.
  std::optional<hal::CameraCalibration> calibration;
  // Set to each served frame's timestamp, so time in a replay is recorded time. Not owned; must
  // outlive the camera. A clock already past a frame's time is left alone (time never goes back).
  hal::ManualClock* clock = nullptr;
  // Read the dataset's wheel odometry (mav0/odometry0/) when it has one (DatasetOptions).
  bool odometry = true;
};

class ReplayCamera final : public hal::Camera {
 public:
  // Checks `options` against `dataset` (see open_replay()); the pool is reserved by start().
  static Result<std::unique_ptr<ReplayCamera>> create(Dataset dataset, const ReplayOptions& options);

  Status start() override;
  Status stop() override;
  // kEndOfStream after the last frame; kOutOfMemory when every buffer is lent; the decoder's
  // error (kCorruptData, kNotFound... naming the file) for a bad frame, as the policy says.
  // Never blocks: timeout_ms is not used.
  Status acquire(hal::Frame& frame, int timeout_ms) override;
  Status release(const hal::Frame& frame) override;
  Result<hal::CameraCalibration> calibration() const override;
  hal::CameraStats stats() const override {
    hal::CameraStats s = stats_;
    if (pool_) {
      s.buffers = pool_->stats().capacity;
      s.buffers_high_water = pool_->stats().high_water;
    }
    return s;
  }
  std::string describe() const override;

  const Dataset& dataset() const { return dataset_; }
  // Frames this replay serves (after start_index and max_frames), and how many are left.
  std::size_t frame_count() const { return end_ - first_; }
  std::size_t remaining() const { return end_ - next_; }
  // Null until start().
  const BlockPool* pool() const { return pool_.get(); }

 private:
  ReplayCamera(Dataset dataset, const ReplayOptions& options);
  Status load_next(hal::Frame& frame);

  Dataset dataset_;
  ReplayOptions options_;
  std::size_t first_ = 0;
  std::size_t end_ = 0;
  std::size_t next_ = 0;  // dataset index of the next frame to serve
  std::unique_ptr<BlockPool> pool_;
  struct Slot {
    PooledImage image;
    std::uint64_t sequence = 0;
  };
  std::vector<Slot> slots_;  // index = Frame::buffer_index; lent while image is not empty
  io::DecodeScratch scratch_;
  std::optional<Status> stopped_by_;  // kStop policy: the error every later acquire() returns
  bool started_ = false;
  hal::CameraStats stats_;
};

// Reads the dataset at `path` (open_dataset()) and makes a camera of it. kInvalidArgument for
// options that do not fit it (no buffers, start_index past the end, a calibration of another size).
Result<std::unique_ptr<ReplayCamera>> open_replay(const std::string& path, const ReplayOptions& options);

}  // namespace ale::replay
