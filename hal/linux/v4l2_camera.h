// The robot's camera: a V4L2 capture device streaming into mmap buffers, delivered as grey frames.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/base/image.h"
#include "core/base/memory_pool.h"
#include "hal/camera.h"
#include "hal/linux/v4l2_formats.h"
#include "hal/linux/v4l2_io.h"

namespace ale::linux_hal {

struct V4l2CameraOptions {
  std::string device = "/dev/video0";
  int width = 640;  // the driver must offer exactly this size (the calibration depends on it)
  int height = 480;
  int fps = 30;     // asked for with VIDIOC_S_PARM; 0 leaves the driver's rate
  int buffers = 4;  // mmap buffers asked for; the driver may grant more
  // Manual exposure (V4L2_CID_EXPOSURE_ABSOLUTE, 100 us steps) and gain (V4L2_CID_GAIN, driver
  // units). Unset: the driver's automatic control. kUnsupported when the driver lacks them.
  std::optional<int> exposure_us;
  std::optional<int> gain;
};

class V4l2Camera final : public hal::Camera {
 public:
  // Opens the device, checks that it can capture by streaming, negotiates the format, the frame
  // rate and the manual controls. Nothing streams until start(). kNotFound when the device does
  // not exist, kInvalidArgument when it is not a V4L2 device or an option is out of range,
  // kUnsupported when it cannot deliver grey frames of the asked size.
  static Result<std::unique_ptr<V4l2Camera>> open(const V4l2CameraOptions& options,
                                                  V4l2Io& io = system_v4l2_io());
  ~V4l2Camera() override;
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  // Maps the buffers, queues them and starts streaming.
  Status start() override;
  // Stops streaming and unmaps the buffers; frames still lent out become invalid.
  Status stop() override;
  // kUnavailable (naming the device) once the device has gone away; it stays so until reopened.
  Status acquire(hal::Frame& frame, int timeout_ms) override;
  Status release(const hal::Frame& frame) override;
  int poll_fd() const override { return fd_; }
  hal::CameraStats stats() const override { return stats_; }
  std::string describe() const override;

  const LumaFormat& format() const { return format_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // The rate the driver accepted (0 when it does not say).
  double fps() const { return fps_; }

 private:
  struct Buffer {
    std::uint8_t* start = nullptr;
    std::size_t length = 0;
    bool lent = false;
    PooledImage grey;  // kPacked422 only
  };

  V4l2Camera(const V4l2CameraOptions& options, V4l2Io& io, int fd);
  Status query_capabilities();
  Status negotiate_format();
  Status set_frame_rate();
  Status set_controls();
  // Sets a control given in the option's units (`scale` of them per driver unit).
  Status set_control(std::uint32_t id, const char* control, int value, int scale, const char* option);
  bool has_control(std::uint32_t id, bool need_read);
  Status request_buffers();
  void release_buffers();
  Status queue(std::uint32_t index);
  // Turns a failed DQBUF/QBUF/poll into a Status; a device that went away is remembered.
  Status device_error(const char* what, int err);
  Status vanish(const std::string& why);
  // The frame sequence for the driver's `v4l2_sequence`; gaps are counted as dropped.
  std::uint64_t next_sequence(std::uint32_t v4l2_sequence);
  Status deliver(std::uint32_t index, std::size_t luma_offset, hal::Frame& frame);
  std::string name() const { return "camera " + options_.device; }

  V4l2CameraOptions options_;
  V4l2Io& io_;
  int fd_ = -1;
  std::uint32_t buf_type_ = 0;  // V4L2_BUF_TYPE_VIDEO_CAPTURE or _MPLANE
  std::string driver_;
  std::string card_;
  LumaFormat format_;
  int width_ = 0;
  int height_ = 0;
  int bytes_per_line_ = 0;
  double fps_ = 0;
  bool rate_settable_ = false;
  bool exposure_readable_ = false;

  std::vector<Buffer> buffers_;
  std::unique_ptr<BlockPool> grey_pool_;  // kPacked422 only
  int queued_ = 0;
  bool streaming_ = false;
  bool vanished_ = false;
  bool monotonic_timestamps_ = true;
  bool have_sequence_ = false;
  std::uint32_t last_v4l2_sequence_ = 0;
  std::uint64_t last_sequence_ = 0;
  hal::CameraStats stats_;
};

}  // namespace ale::linux_hal
