#include "hal/linux/v4l2_camera.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/mman.h>
#include <sys/sysmacros.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <utility>

#include "hal/linux/monotonic_clock.h"

// 64-bit time_t on 32-bit ARM changes the size of struct v4l2_buffer and with it the numbers of
// QUERYBUF/QBUF/DQBUF, which kernels before 5.6 reject.
#if defined(__arm__) && defined(_TIME_BITS) && _TIME_BITS == 64
#error "build the V4L2 backend without _TIME_BITS=64 (see docs/hardware.md)"
#endif

namespace ale::linux_hal {

namespace {

std::string errno_text(int err) { return std::strerror(err); }

std::string to_text(const __u8* chars, std::size_t size) {
  const char* p = reinterpret_cast<const char*>(chars);
  return std::string(p, strnlen(p, size));
}

bool is_multiplanar(std::uint32_t buf_type) { return buf_type == V4L2_BUF_TYPE_VIDEO_CAPTURE_MPLANE; }

// A v4l2_buffer for QUERYBUF/QBUF/DQBUF; multi-planar buffers point at `planes`.
v4l2_buffer make_buffer(std::uint32_t buf_type, std::uint32_t index, v4l2_plane* planes) {
  v4l2_buffer b{};
  b.type = buf_type;
  b.memory = V4L2_MEMORY_MMAP;
  b.index = index;
  if (is_multiplanar(buf_type)) {
    b.m.planes = planes;
    b.length = VIDEO_MAX_PLANES;
  }
  return b;
}

bool is_gone(int err) { return err == ENODEV || err == EIO || err == ENXIO; }

constexpr std::int64_t kNsPerMs = 1000000;
constexpr unsigned kVideoMajor = 81;  // every /dev/video*, /dev/v4l-subdev* node

}  // namespace

V4l2Camera::V4l2Camera(const V4l2CameraOptions& options, V4l2Io& io, int fd)
    : options_(options), io_(io), fd_(fd) {}

V4l2Camera::~V4l2Camera() {
  (void)stop();
  if (fd_ >= 0) io_.close(fd_);
}

Result<std::unique_ptr<V4l2Camera>> V4l2Camera::open(const V4l2CameraOptions& options, V4l2Io& io) {
  const std::string what = "camera " + options.device + ": ";
  if (options.width <= 0 || options.height <= 0)
    return invalid_argument(what + "size " + std::to_string(options.width) + "x" +
                            std::to_string(options.height) + " must be positive");
  if (options.fps < 0 || options.fps > 1000)
    return invalid_argument(what + "fps " + std::to_string(options.fps) + " outside [0, 1000]");
  if (options.buffers < 2 || options.buffers > 32)
    return invalid_argument(what + "buffers " + std::to_string(options.buffers) + " outside [2, 32]");
  if (options.exposure_us && *options.exposure_us <= 0)
    return invalid_argument(what + "exposure_us " + std::to_string(*options.exposure_us) + " must be positive");

  // Non-blocking: acquire() waits in poll() with its own timeout, never in DQBUF.
  const int fd = io.open(options.device.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    if (err == ENOENT || err == ENODEV || err == ENXIO)
      return not_found(what + "no such device (" + errno_text(err) + ")");
    if (err == EBUSY) return unavailable(what + "busy (used by another process?)");
    if (err == EACCES || err == EPERM)
      return io_error(what + "permission denied (is the user in the video group?)");
    return io_error(what + "cannot open: " + errno_text(err));
  }
  std::unique_ptr<V4l2Camera> camera(new V4l2Camera(options, io, fd));
  ALE_RETURN_IF_ERROR(camera->query_capabilities());
  ALE_RETURN_IF_ERROR(camera->negotiate_format());
  ALE_RETURN_IF_ERROR(camera->set_frame_rate());
  ALE_RETURN_IF_ERROR(camera->set_controls());
  return Result<std::unique_ptr<V4l2Camera>>(std::move(camera));
}

Status V4l2Camera::query_capabilities() {
  // Checked before any ioctl: qemu-user does not emulate the V4L2 ioctls, and an ioctl on a
  // stranger's device could do anything.
  struct stat st {};
  if (io_.fstat(fd_, &st) < 0) return io_error(name() + ": fstat failed: " + errno_text(errno));
  if (!S_ISCHR(st.st_mode)) return invalid_argument(name() + " is not a V4L2 device (not a character device)");
  if (major(st.st_rdev) != kVideoMajor)
    return invalid_argument(name() + " is not a V4L2 device (character device " + std::to_string(major(st.st_rdev)) +
                            ":" + std::to_string(minor(st.st_rdev)) + ", V4L2 devices have major " +
                            std::to_string(kVideoMajor) + ")");
  v4l2_capability cap{};
  if (io_.ioctl(fd_, VIDIOC_QUERYCAP, &cap) < 0) {
    const int err = errno;
    if (err == ENOTTY || err == EINVAL || err == ENOSYS)
      return invalid_argument(name() + " is not a V4L2 device (VIDIOC_QUERYCAP: " + errno_text(err) + ")");
    return io_error(name() + ": VIDIOC_QUERYCAP failed: " + errno_text(err));
  }
  driver_ = to_text(cap.driver, sizeof cap.driver);
  card_ = to_text(cap.card, sizeof cap.card);
  // device_caps describe this node; capabilities cover the whole physical device.
  const std::uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  if (caps & V4L2_CAP_VIDEO_CAPTURE) {
    buf_type_ = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  } else if (caps & V4L2_CAP_VIDEO_CAPTURE_MPLANE) {
    buf_type_ = V4L2_BUF_TYPE_VIDEO_CAPTURE_MPLANE;
  } else {
    return unsupported(name() + " (" + driver_ + ") is not a video capture device");
  }
  if (!(caps & V4L2_CAP_STREAMING))
    return unsupported(name() + " (" + driver_ + ") cannot stream (no V4L2_CAP_STREAMING)");
  return {};
}

Status V4l2Camera::negotiate_format() {
  std::vector<std::uint32_t> offered;
  for (std::uint32_t i = 0; i < 256; ++i) {
    v4l2_fmtdesc desc{};
    desc.index = i;
    desc.type = buf_type_;
    if (io_.ioctl(fd_, VIDIOC_ENUM_FMT, &desc) < 0) break;  // EINVAL ends the list
    offered.push_back(desc.pixelformat);
  }
  std::string offered_text;
  for (std::uint32_t f : offered) offered_text += (offered_text.empty() ? "" : " ") + fourcc_to_string(f);
  const std::vector<LumaFormat> usable = usable_formats(offered);
  if (usable.empty())
    return unsupported(name() + " offers no format with a grey or luma plane (offers: " +
                       (offered.empty() ? std::string("none") : offered_text) +
                       "; accepted: " + accepted_formats() + ")");

  // The best format that the driver delivers at exactly the asked size.
  const std::string asked = std::to_string(options_.width) + "x" + std::to_string(options_.height);
  std::string refusals;
  for (const LumaFormat& candidate : usable) {
    v4l2_format f{};
    f.type = buf_type_;
    if (is_multiplanar(buf_type_)) {
      f.fmt.pix_mp.width = static_cast<__u32>(options_.width);
      f.fmt.pix_mp.height = static_cast<__u32>(options_.height);
      f.fmt.pix_mp.pixelformat = candidate.fourcc;
      f.fmt.pix_mp.field = V4L2_FIELD_NONE;
    } else {
      f.fmt.pix.width = static_cast<__u32>(options_.width);
      f.fmt.pix.height = static_cast<__u32>(options_.height);
      f.fmt.pix.pixelformat = candidate.fourcc;
      f.fmt.pix.field = V4L2_FIELD_NONE;
    }
    const std::string label = fourcc_to_string(candidate.fourcc);
    if (io_.ioctl(fd_, VIDIOC_S_FMT, &f) < 0) {
      const int err = errno;
      if (err == EBUSY) return unavailable(name() + ": busy, cannot set the format (streaming elsewhere?)");
      refusals += "; " + label + ": VIDIOC_S_FMT " + errno_text(err);
      continue;
    }
    const bool mp = is_multiplanar(buf_type_);
    const std::uint32_t got_fourcc = mp ? f.fmt.pix_mp.pixelformat : f.fmt.pix.pixelformat;
    const int got_w = static_cast<int>(mp ? f.fmt.pix_mp.width : f.fmt.pix.width);
    const int got_h = static_cast<int>(mp ? f.fmt.pix_mp.height : f.fmt.pix.height);
    int bpl = static_cast<int>(mp ? f.fmt.pix_mp.plane_fmt[0].bytesperline : f.fmt.pix.bytesperline);
    if (got_fourcc != candidate.fourcc) {
      refusals += "; " + label + ": driver gave " + fourcc_to_string(got_fourcc);
      continue;
    }
    if (got_w != options_.width || got_h != options_.height) {
      refusals += "; " + label + ": driver gave " + std::to_string(got_w) + "x" + std::to_string(got_h);
      continue;
    }
    const int min_bpl = min_bytes_per_line(candidate, got_w);
    if (bpl == 0) bpl = min_bpl;  // some drivers leave it to the application
    if (bpl < min_bpl) {
      refusals += "; " + label + ": bytesperline " + std::to_string(bpl) + " < " + std::to_string(min_bpl);
      continue;
    }
    format_ = candidate;
    width_ = got_w;
    height_ = got_h;
    bytes_per_line_ = bpl;
    return {};
  }
  return unsupported(name() + ": no usable format at " + asked + " (offers: " + offered_text + refusals + ")");
}

Status V4l2Camera::set_frame_rate() {
  v4l2_streamparm parm{};
  parm.type = buf_type_;
  if (io_.ioctl(fd_, VIDIOC_G_PARM, &parm) < 0) return {};  // the driver keeps its rate to itself
  rate_settable_ = (parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME) != 0;
  if (rate_settable_ && options_.fps > 0) {
    parm.parm.capture.timeperframe.numerator = 1;
    parm.parm.capture.timeperframe.denominator = static_cast<__u32>(options_.fps);
    if (io_.ioctl(fd_, VIDIOC_S_PARM, &parm) < 0)
      return io_error(name() + ": VIDIOC_S_PARM " + std::to_string(options_.fps) + " fps failed: " +
                      errno_text(errno));
  }
  const v4l2_fract& t = parm.parm.capture.timeperframe;
  fps_ = t.numerator > 0 ? static_cast<double>(t.denominator) / t.numerator : 0.0;
  return {};
}

bool V4l2Camera::has_control(std::uint32_t id, bool need_read) {
  v4l2_queryctrl q{};
  q.id = id;
  if (io_.ioctl(fd_, VIDIOC_QUERYCTRL, &q) < 0) return false;
  if (q.flags & V4L2_CTRL_FLAG_DISABLED) return false;
  return !need_read || !(q.flags & V4L2_CTRL_FLAG_WRITE_ONLY);
}

Status V4l2Camera::set_control(std::uint32_t id, const char* control, int value, int scale, const char* option) {
  v4l2_queryctrl q{};
  q.id = id;
  if (io_.ioctl(fd_, VIDIOC_QUERYCTRL, &q) < 0 || (q.flags & V4L2_CTRL_FLAG_DISABLED))
    return unsupported(name() + " (" + driver_ + ") has no " + control + " control (option " + option + ")");
  if (q.flags & V4L2_CTRL_FLAG_READ_ONLY)
    return unsupported(name() + ": " + control + " is read-only (option " + option + ")");
  const int driver_value = static_cast<int>(std::lround(static_cast<double>(value) / scale));
  if (driver_value < q.minimum || driver_value > q.maximum)
    return invalid_argument(name() + ": " + option + " = " + std::to_string(value) + " outside the driver's range [" +
                            std::to_string(static_cast<long long>(q.minimum) * scale) + ", " +
                            std::to_string(static_cast<long long>(q.maximum) * scale) + "]");
  v4l2_control c{};
  c.id = id;
  c.value = driver_value;
  if (io_.ioctl(fd_, VIDIOC_S_CTRL, &c) < 0)
    return io_error(name() + ": setting " + control + " to " + std::to_string(driver_value) +
                    " failed: " + errno_text(errno));
  return {};
}

Status V4l2Camera::set_controls() {
  exposure_readable_ = has_control(V4L2_CID_EXPOSURE_ABSOLUTE, true);
  if (options_.exposure_us) {
    // Auto exposure must be off first, or the driver ignores (or refuses) the absolute value.
    if (has_control(V4L2_CID_EXPOSURE_AUTO, false))
      ALE_RETURN_IF_ERROR(set_control(V4L2_CID_EXPOSURE_AUTO, "exposure_auto", V4L2_EXPOSURE_MANUAL, 1, "exposure_us"));
    ALE_RETURN_IF_ERROR(
        set_control(V4L2_CID_EXPOSURE_ABSOLUTE, "exposure_absolute", *options_.exposure_us, 100, "exposure_us"));
  }
  if (options_.gain) {
    if (has_control(V4L2_CID_AUTOGAIN, false))
      ALE_RETURN_IF_ERROR(set_control(V4L2_CID_AUTOGAIN, "autogain", 0, 1, "gain"));
    ALE_RETURN_IF_ERROR(set_control(V4L2_CID_GAIN, "gain", *options_.gain, 1, "gain"));
  }
  return {};
}

Status V4l2Camera::request_buffers() {
  v4l2_requestbuffers req{};
  req.count = static_cast<__u32>(options_.buffers);
  req.type = buf_type_;
  req.memory = V4L2_MEMORY_MMAP;
  if (io_.ioctl(fd_, VIDIOC_REQBUFS, &req) < 0) {
    const int err = errno;
    if (err == EINVAL) return unsupported(name() + " (" + driver_ + ") does not support mmap streaming");
    if (err == EBUSY) return unavailable(name() + ": busy, cannot allocate buffers (streaming elsewhere?)");
    if (is_gone(err)) return vanish("VIDIOC_REQBUFS: " + errno_text(err));
    return io_error(name() + ": VIDIOC_REQBUFS failed: " + errno_text(err));
  }
  buffers_.resize(req.count);
  if (req.count < 2) {
    release_buffers();
    return out_of_memory(name() + ": the driver granted " + std::to_string(req.count) + " buffers, 2 are needed");
  }
  const std::size_t frame_bytes = static_cast<std::size_t>(bytes_per_line_) * static_cast<std::size_t>(height_);
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_plane planes[VIDEO_MAX_PLANES]{};
    v4l2_buffer b = make_buffer(buf_type_, i, planes);
    if (io_.ioctl(fd_, VIDIOC_QUERYBUF, &b) < 0) {
      const int err = errno;
      release_buffers();
      return io_error(name() + ": VIDIOC_QUERYBUF " + std::to_string(i) + " failed: " + errno_text(err));
    }
    const bool mp = is_multiplanar(buf_type_);
    const std::size_t length = mp ? planes[0].length : b.length;
    const auto offset = static_cast<off_t>(mp ? planes[0].m.mem_offset : b.m.offset);
    if (length < frame_bytes) {
      release_buffers();
      return unsupported(name() + ": buffer " + std::to_string(i) + " holds " + std::to_string(length) +
                         " bytes, a frame needs " + std::to_string(frame_bytes));
    }
    void* p = io_.mmap(length, fd_, offset);
    if (p == MAP_FAILED) {
      const int err = errno;
      release_buffers();
      return io_error(name() + ": mmap of buffer " + std::to_string(i) + " failed: " + errno_text(err));
    }
    buffers_[i].start = static_cast<std::uint8_t*>(p);
    buffers_[i].length = length;
  }
  return {};
}

void V4l2Camera::release_buffers() {
  for (Buffer& b : buffers_) {
    b.grey.reset();
    if (b.start != nullptr) io_.munmap(b.start, b.length);
  }
  if (!buffers_.empty() && !vanished_) {
    v4l2_requestbuffers req{};
    req.type = buf_type_;
    req.memory = V4L2_MEMORY_MMAP;
    (void)io_.ioctl(fd_, VIDIOC_REQBUFS, &req);  // count 0 frees the driver's buffers
  }
  buffers_.clear();
  grey_pool_.reset();
  queued_ = 0;
}

Status V4l2Camera::start() {
  if (vanished_) return unavailable(name() + " went away; open it again");
  if (streaming_) return {};
  ALE_RETURN_IF_ERROR(request_buffers());
  if (format_.layout == LumaLayout::kPacked422)
    grey_pool_ = std::make_unique<BlockPool>(
        "grey frames of " + options_.device,
        static_cast<std::size_t>(aligned_stride(width_)) * static_cast<std::size_t>(height_), buffers_.size());
  for (std::uint32_t i = 0; i < buffers_.size(); ++i) {
    Status s = queue(i);
    if (!s.ok()) {
      release_buffers();
      return s;
    }
  }
  int type = static_cast<int>(buf_type_);
  if (io_.ioctl(fd_, VIDIOC_STREAMON, &type) < 0) {
    const int err = errno;
    Status s = is_gone(err) ? vanish("VIDIOC_STREAMON: " + errno_text(err))
                            : io_error(name() + ": VIDIOC_STREAMON failed: " + errno_text(err));
    release_buffers();
    return s;
  }
  streaming_ = true;
  have_sequence_ = false;  // drivers restart their count at STREAMON
  return {};
}

Status V4l2Camera::stop() {
  Status status;
  if (streaming_) {
    int type = static_cast<int>(buf_type_);
    if (io_.ioctl(fd_, VIDIOC_STREAMOFF, &type) < 0 && !vanished_ && !is_gone(errno))
      status = io_error(name() + ": VIDIOC_STREAMOFF failed: " + errno_text(errno));
    streaming_ = false;
  }
  release_buffers();
  return status;
}

Status V4l2Camera::queue(std::uint32_t index) {
  v4l2_plane planes[VIDEO_MAX_PLANES]{};
  v4l2_buffer b = make_buffer(buf_type_, index, planes);
  if (io_.ioctl(fd_, VIDIOC_QBUF, &b) < 0) return device_error("VIDIOC_QBUF", errno);
  ++queued_;
  return {};
}

Status V4l2Camera::vanish(const std::string& why) {
  vanished_ = true;
  ++stats_.errors;
  return unavailable(name() + " went away (" + why + ")");
}

Status V4l2Camera::device_error(const char* what, int err) {
  if (is_gone(err)) return vanish(std::string(what) + ": " + errno_text(err));
  ++stats_.errors;
  return io_error(name() + ": " + what + " failed: " + errno_text(err));
}

std::uint64_t V4l2Camera::next_sequence(std::uint32_t v4l2_sequence) {
  if (!have_sequence_) {
    have_sequence_ = true;
    last_v4l2_sequence_ = v4l2_sequence;
    if (stats_.delivered + stats_.dropped > 0) ++last_sequence_;  // a restart after stop()/start()
    return last_sequence_;
  }
  // Unsigned difference: survives the 32-bit counter wrapping.
  std::uint32_t step = v4l2_sequence - last_v4l2_sequence_;
  // A driver that does not count (always 0) or jumps backwards: assume the next frame.
  if (step == 0 || step > 0x80000000u) step = 1;
  stats_.dropped += step - 1;
  last_v4l2_sequence_ = v4l2_sequence;
  last_sequence_ += step;
  return last_sequence_;
}

Status V4l2Camera::acquire(hal::Frame& frame, int timeout_ms) {
  if (vanished_) return unavailable(name() + " went away; open it again");
  if (!streaming_) return invalid_argument(name() + ": acquire before start");
  if (queued_ == 0) return out_of_memory(name() + ": every buffer is lent out (release frames first)");

  MonotonicClock clock;
  const std::int64_t deadline_ns = clock.now_ns() + static_cast<std::int64_t>(timeout_ms) * kNsPerMs;
  for (;;) {
    int wait_ms = -1;
    if (timeout_ms >= 0) {
      const std::int64_t left_ns = deadline_ns - clock.now_ns();
      wait_ms = left_ns > 0 ? static_cast<int>((left_ns + kNsPerMs - 1) / kNsPerMs) : 0;
    }
    pollfd p{};
    p.fd = fd_;
    p.events = POLLIN;
    const int ready = io_.poll(&p, 1, wait_ms);
    if (ready < 0) {
      if (errno == EINTR) continue;
      return device_error("poll", errno);
    }
    if (ready == 0)
      return Status(StatusCode::kTimeout, name() + ": no frame within " + std::to_string(timeout_ms) + " ms");

    v4l2_plane planes[VIDEO_MAX_PLANES]{};
    v4l2_buffer b = make_buffer(buf_type_, 0, planes);
    if (io_.ioctl(fd_, VIDIOC_DQBUF, &b) < 0) {
      const int err = errno;
      if (err != EAGAIN) return device_error("VIDIOC_DQBUF", err);
      // Streaming with buffers queued, an error flag can only mean the device is gone.
      if (p.revents & (POLLERR | POLLHUP | POLLNVAL)) return vanish("poll reported an error");
      continue;  // woken without a frame
    }
    --queued_;
    if (b.index >= buffers_.size()) {
      ++stats_.errors;
      return io_error(name() + ": the driver dequeued buffer " + std::to_string(b.index) + " of " +
                      std::to_string(buffers_.size()));
    }
    const bool mp = is_multiplanar(buf_type_);
    const std::size_t used = mp ? planes[0].bytesused : b.bytesused;
    const std::size_t offset = mp ? planes[0].data_offset : 0;
    const std::size_t needed = static_cast<std::size_t>(bytes_per_line_) * static_cast<std::size_t>(height_);
    // bytesused 0: a driver that does not fill it in; the whole buffer is then the frame.
    const std::size_t available = used == 0 ? buffers_[b.index].length : used;
    const std::uint64_t sequence = next_sequence(b.sequence);
    if ((b.flags & V4L2_BUF_FLAG_ERROR) || offset > available || available - offset < needed) {
      ++stats_.dropped;  // a torn or short frame: give it straight back
      ALE_RETURN_IF_ERROR(queue(b.index));
      continue;
    }

    if ((b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC) {
      frame.timestamp_ns = static_cast<std::int64_t>(b.timestamp.tv_sec) * 1000000000 +
                           static_cast<std::int64_t>(b.timestamp.tv_usec) * 1000;
    } else {
      // Old drivers stamp with the wall clock, which jumps: the dequeue time is closer to the truth.
      monotonic_timestamps_ = false;
      frame.timestamp_ns = clock.now_ns();
    }
    frame.sequence = sequence;
    return deliver(b.index, offset, frame);
  }
}

Status V4l2Camera::deliver(std::uint32_t index, std::size_t luma_offset, hal::Frame& frame) {
  Buffer& buf = buffers_[index];
  const std::uint8_t* luma = buf.start + luma_offset;
  if (format_.layout == LumaLayout::kPacked422) {
    Result<PooledImage> grey = PooledImage::create(*grey_pool_, width_, height_);
    if (!grey.ok()) {
      ++stats_.errors;
      ALE_RETURN_IF_ERROR(queue(index));
      return grey.status();
    }
    packed422_to_gray(luma, bytes_per_line_, format_.luma_offset, grey->view());
    buf.grey = std::move(*grey);
    frame.image = buf.grey.view();
  } else {
    frame.image = GrayView{luma, width_, height_, bytes_per_line_};
  }
  frame.exposure_us.reset();
  if (exposure_readable_) {
    // The control's current value: drivers do not report the exposure of each frame.
    v4l2_control c{};
    c.id = V4L2_CID_EXPOSURE_ABSOLUTE;
    if (io_.ioctl(fd_, VIDIOC_G_CTRL, &c) == 0)
      frame.exposure_us = c.value * 100;
    else
      exposure_readable_ = false;
  }
  frame.buffer_index = static_cast<int>(index);
  buf.lent = true;
  ++stats_.delivered;
  stats_.buffers = buffers_.size();
  stats_.buffers_high_water =
      std::max<std::uint64_t>(stats_.buffers_high_water, static_cast<std::uint64_t>(std::count_if(
                                                             buffers_.begin(), buffers_.end(),
                                                             [](const Buffer& b) { return b.lent; })));
  return {};
}

Status V4l2Camera::release(const hal::Frame& frame) {
  if (frame.buffer_index < 0 || static_cast<std::size_t>(frame.buffer_index) >= buffers_.size() ||
      !buffers_[static_cast<std::size_t>(frame.buffer_index)].lent)
    return invalid_argument(name() + ": release of buffer " + std::to_string(frame.buffer_index) +
                            ", which is not lent out");
  Buffer& buf = buffers_[static_cast<std::size_t>(frame.buffer_index)];
  buf.lent = false;
  buf.grey.reset();
  if (vanished_) return {};  // nothing to give back to
  return queue(static_cast<std::uint32_t>(frame.buffer_index));
}

std::string V4l2Camera::describe() const {
  std::string s = name() + " (" + driver_ + (card_.empty() ? "" : ", " + card_) + "): " + std::to_string(width_) +
                  "x" + std::to_string(height_) + " " + describe_luma(format_);
  if (fps_ > 0) {
    s += ", " + std::to_string(static_cast<int>(std::lround(fps_))) + " fps";
  } else {
    s += ", the driver's frame rate";
  }
  if (!rate_settable_ && options_.fps > 0) s += " (the driver cannot set " + std::to_string(options_.fps) + " fps)";
  if (is_multiplanar(buf_type_)) s += ", multi-planar API";
  if (!buffers_.empty()) s += ", " + std::to_string(buffers_.size()) + " mmap buffers";
  if (!monotonic_timestamps_) s += ", timestamps taken at dequeue (the driver's are not CLOCK_MONOTONIC)";
  if (exposure_readable_) s += ", exposure read from V4L2_CID_EXPOSURE_ABSOLUTE";
  if (vanished_) s += ", GONE";
  return s;
}

}  // namespace ale::linux_hal
