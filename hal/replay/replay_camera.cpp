#include "hal/replay/replay_camera.h"

#include <algorithm>
#include <new>
#include <utility>

namespace ale::replay {

namespace {
constexpr int kMaxBuffers = 64;
}  // namespace

Result<std::unique_ptr<ReplayCamera>> ReplayCamera::create(Dataset dataset, const ReplayOptions& options) {
  const std::string& where = dataset.folder;
  if (options.buffers < 1 || options.buffers > kMaxBuffers)
    return invalid_argument(where + ": replay buffers = " + std::to_string(options.buffers) + ", must be 1.." +
                            std::to_string(kMaxBuffers));
  if (dataset.frames.empty()) return not_found(where + ": no frames to replay");
  if (options.start_index >= dataset.frames.size())
    return invalid_argument(where + ": replay start_index " + std::to_string(options.start_index) +
                            " is past the last frame (" + std::to_string(dataset.frames.size()) + " frames)");
  if (dataset.width <= 0 || dataset.height <= 0) return internal_error(where + ": dataset without a frame size");
  ReplayOptions checked = options;
  if (checked.calibration) {
    hal::CameraCalibration& c = *checked.calibration;
    if (c.width == 0 && c.height == 0) {
      c.width = dataset.width;
      c.height = dataset.height;
    } else if (c.width != dataset.width || c.height != dataset.height) {
      return invalid_argument(where + ": the given calibration is for " + std::to_string(c.width) + "x" +
                              std::to_string(c.height) + " but the frames are " + std::to_string(dataset.width) +
                              "x" + std::to_string(dataset.height));
    }
  }
  return std::unique_ptr<ReplayCamera>(new ReplayCamera(std::move(dataset), checked));
}

ReplayCamera::ReplayCamera(Dataset dataset, const ReplayOptions& options)
    : dataset_(std::move(dataset)), options_(options) {
  first_ = options_.start_index;
  const std::size_t available = dataset_.frames.size() - first_;
  end_ = first_ + (options_.max_frames == 0 ? available : std::min(available, options_.max_frames));
  next_ = first_;
}

Status ReplayCamera::start() {
  if (!pool_) {
    const std::size_t block_bytes =
        static_cast<std::size_t>(aligned_stride(dataset_.width)) * static_cast<std::size_t>(dataset_.height);
    const auto count = static_cast<std::size_t>(options_.buffers);
    try {
      pool_ = std::make_unique<BlockPool>("replay camera frames", block_bytes, count);
    } catch (const std::bad_alloc&) {
      return out_of_memory(dataset_.folder + ": cannot reserve " + std::to_string(count) + " frame buffers of " +
                           std::to_string(block_bytes) + " bytes");
    }
    slots_.resize(count);
  }
  started_ = true;
  return {};
}

Status ReplayCamera::stop() {
  // Lent frames stay valid until released: the pool lives as long as the camera.
  started_ = false;
  return {};
}

Status ReplayCamera::acquire(hal::Frame& frame, int /*timeout_ms*/) {
  if (!started_) return invalid_argument(dataset_.folder + ": replay camera: acquire before start");
  if (stopped_by_) return *stopped_by_;
  for (;;) {
    if (next_ >= end_) return end_of_stream(dataset_.folder + ": replay is over after " + std::to_string(frame_count()) +
                                            " frames");
    const Status status = load_next(frame);
    if (status.ok() || status.code() == StatusCode::kOutOfMemory) return status;
    ++stats_.errors;
    switch (options_.on_bad_frame) {
      case BadFramePolicy::kReport:
        return status;
      case BadFramePolicy::kStop:
        stopped_by_ = status;
        return status;
      case BadFramePolicy::kSkip:
        ++stats_.dropped;
        break;
    }
  }
}

// Decodes frame next_ into a free buffer. On a decode error the frame is used up (next_ moves on)
// and its buffer goes back to the pool; on kOutOfMemory nothing changes.
Status ReplayCamera::load_next(hal::Frame& frame) {
  const auto free_slot = std::find_if(slots_.begin(), slots_.end(), [](const Slot& s) { return s.image.empty(); });
  if (free_slot == slots_.end())
    return out_of_memory(dataset_.folder + ": replay camera: all " + std::to_string(slots_.size()) +
                         " buffers are lent out; release a frame first");
  Result<PooledImage> image = PooledImage::create(*pool_, dataset_.width, dataset_.height);
  if (!image.ok()) return image.status();

  const FrameEntry& entry = dataset_.frames[next_];
  const std::uint64_t sequence = next_ - first_;
  ++next_;
  Status decoded = io::read_gray_into(entry.path, image->view(), scratch_);
  if (!decoded.ok()) {
    // A frame of another size is a fault of the recording, not of the caller's buffer.
    if (decoded.code() == StatusCode::kInvalidArgument) decoded = corrupt_data(decoded.message());
    return decoded;
  }
  if (options_.clock != nullptr) options_.clock->set_ns(entry.timestamp_ns);

  free_slot->image = std::move(*image);
  free_slot->sequence = sequence;
  frame.image = free_slot->image.view();
  frame.timestamp_ns = entry.timestamp_ns;
  frame.sequence = sequence;
  frame.exposure_us.reset();
  frame.buffer_index = static_cast<int>(free_slot - slots_.begin());
  ++stats_.delivered;
  return {};
}

Status ReplayCamera::release(const hal::Frame& frame) {
  const auto index = static_cast<std::size_t>(frame.buffer_index);
  // The sequence check catches a stale copy of a frame whose buffer has since been lent again.
  if (frame.buffer_index < 0 || index >= slots_.size() || slots_[index].image.empty() ||
      slots_[index].sequence != frame.sequence)
    return invalid_argument(dataset_.folder + ": replay camera: release of frame " + std::to_string(frame.sequence) +
                            " (buffer " + std::to_string(frame.buffer_index) + "), which is not lent out");
  slots_[index].image.reset();
  return {};
}

Result<hal::CameraCalibration> ReplayCamera::calibration() const {
  if (options_.calibration) return *options_.calibration;
  if (dataset_.calibration) return *dataset_.calibration;
  return unsupported(dataset_.folder + ": " + to_string(dataset_.format) +
                     " dataset carries no calibration; pass one in ReplayOptions");
}

std::string ReplayCamera::describe() const {
  return std::string("replay camera: ") + to_string(dataset_.format) + " " + dataset_.folder + " (" +
         std::to_string(frame_count()) + " frames from #" + std::to_string(first_) + ", " +
         std::to_string(dataset_.width) + "x" + std::to_string(dataset_.height) + ", " +
         std::to_string(options_.buffers) + " buffers)";
}

Result<std::unique_ptr<ReplayCamera>> open_replay(const std::string& path, const ReplayOptions& options) {
  DatasetOptions dataset_options;
  dataset_options.odometry = options.odometry;
  Result<Dataset> dataset = open_dataset(path, dataset_options);
  if (!dataset.ok()) return dataset.status();
  return ReplayCamera::create(std::move(*dataset), options);
}

}  // namespace ale::replay
