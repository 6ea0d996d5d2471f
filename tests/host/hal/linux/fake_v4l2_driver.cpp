#include "tests/host/hal/linux/fake_v4l2_driver.h"

#include <sys/mman.h>
#include <sys/sysmacros.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace ale::test {

int FakeV4l2Driver::fail(int err) {
  errno = err;
  return -1;
}

int FakeV4l2Driver::open(const char* file, int /*flags*/) {
  if (path != file || gone()) return fail(ENOENT);
  ++open_fds;
  return kFd;
}

int FakeV4l2Driver::close(int fd) {
  if (fd != kFd) return fail(EBADF);
  --open_fds;
  return 0;
}

int FakeV4l2Driver::fstat(int fd, struct stat* st) {
  if (fd != kFd) return fail(EBADF);
  *st = {};
  st->st_mode = S_IFCHR | 0660;
  st->st_rdev = makedev(device_major, 42);
  return 0;
}

void FakeV4l2Driver::replug() {
  vanish_after = -1;
  streaming = false;
  queued.clear();
  dequeued = 0;
}

std::size_t FakeV4l2Driver::bytes_per_line() const {
  const bool packed = format == V4L2_PIX_FMT_YUYV || format == V4L2_PIX_FMT_UYVY;
  return static_cast<std::size_t>((packed ? 2 : 1) * width + padding);
}

std::size_t FakeV4l2Driver::frame_bytes() const {
  const std::size_t luma = bytes_per_line() * static_cast<std::size_t>(height);
  const bool planar = format == V4L2_PIX_FMT_NV12 || format == V4L2_PIX_FMT_NV12M;
  return planar ? luma + luma / 2 : luma;
}

void FakeV4l2Driver::paint(std::vector<std::uint8_t>& buffer, const Shot& shot) const {
  std::fill(buffer.begin(), buffer.end(), std::uint8_t{128});  // chroma, padding
  const std::size_t bpl = bytes_per_line();
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      std::size_t at = bpl * static_cast<std::size_t>(y);
      if (format == V4L2_PIX_FMT_YUYV)
        at += 2 * static_cast<std::size_t>(x);
      else if (format == V4L2_PIX_FMT_UYVY)
        at += 2 * static_cast<std::size_t>(x) + 1;
      else
        at += static_cast<std::size_t>(x);
      buffer[at] = shot.luma && shot.luma->size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height)
                       ? (*shot.luma)[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)]
                       : pattern(x, y, shot.seed);
    }
  }
}

int FakeV4l2Driver::dequeue(v4l2_buffer& b) {
  if (gone()) return fail(ENODEV);
  if (!streaming || queued.empty() || shots.empty()) return fail(EAGAIN);
  const std::uint32_t index = queued.front();
  queued.erase(queued.begin());
  const Shot shot = shots.front();
  shots.pop_front();
  ++dequeued;
  paint(memory[index], shot);
  const std::uint32_t used =
      shot.bytes_used == ~0u ? static_cast<std::uint32_t>(frame_bytes()) : shot.bytes_used;
  b.index = index;
  b.sequence = shot.sequence;
  b.flags = (shot.error ? V4L2_BUF_FLAG_ERROR : 0u) |
            (monotonic ? V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC : V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN);
  b.timestamp.tv_sec = static_cast<decltype(b.timestamp.tv_sec)>(shot.timestamp_ns / 1000000000);
  b.timestamp.tv_usec = static_cast<decltype(b.timestamp.tv_usec)>((shot.timestamp_ns % 1000000000) / 1000);
  if (multiplanar()) {
    b.m.planes[0].bytesused = used;
    b.m.planes[0].data_offset = 0;
  } else {
    b.bytesused = used;
  }
  return 0;
}

int FakeV4l2Driver::ioctl(int fd, unsigned long request, void* arg) {
  if (fd != kFd) return fail(EBADF);
  const std::uint32_t buf_type = multiplanar() ? V4L2_BUF_TYPE_VIDEO_CAPTURE_MPLANE : V4L2_BUF_TYPE_VIDEO_CAPTURE;
  switch (request) {
    case VIDIOC_QUERYCAP: {
      auto* cap = static_cast<v4l2_capability*>(arg);
      std::memset(cap, 0, sizeof *cap);
      std::memcpy(cap->driver, "fake", 5);
      std::memcpy(cap->card, "fake sensor", 12);
      cap->capabilities = caps | V4L2_CAP_DEVICE_CAPS;
      cap->device_caps = caps;
      return 0;
    }
    case VIDIOC_ENUM_FMT: {
      auto* d = static_cast<v4l2_fmtdesc*>(arg);
      if (d->type != buf_type || d->index >= formats.size()) return fail(EINVAL);
      d->pixelformat = formats[d->index];
      return 0;
    }
    case VIDIOC_S_FMT: {
      auto* f = static_cast<v4l2_format*>(arg);
      if (f->type != buf_type) return fail(EINVAL);
      if (streaming) return fail(EBUSY);
      const bool mp = multiplanar();
      std::uint32_t fourcc = mp ? f->fmt.pix_mp.pixelformat : f->fmt.pix.pixelformat;
      // Drivers substitute a format they have for one they do not.
      if (std::find(formats.begin(), formats.end(), fourcc) == formats.end()) fourcc = formats.front();
      format = fourcc;
      width = std::min(static_cast<int>(mp ? f->fmt.pix_mp.width : f->fmt.pix.width), max_width);
      height = std::min(static_cast<int>(mp ? f->fmt.pix_mp.height : f->fmt.pix.height), max_height);
      if (mp) {
        f->fmt.pix_mp.pixelformat = format;
        f->fmt.pix_mp.width = static_cast<__u32>(width);
        f->fmt.pix_mp.height = static_cast<__u32>(height);
        f->fmt.pix_mp.num_planes = 1;
        f->fmt.pix_mp.plane_fmt[0].bytesperline = static_cast<__u32>(bytes_per_line());
        f->fmt.pix_mp.plane_fmt[0].sizeimage = static_cast<__u32>(frame_bytes());
      } else {
        f->fmt.pix.pixelformat = format;
        f->fmt.pix.width = static_cast<__u32>(width);
        f->fmt.pix.height = static_cast<__u32>(height);
        f->fmt.pix.bytesperline = static_cast<__u32>(bytes_per_line());
        f->fmt.pix.sizeimage = static_cast<__u32>(frame_bytes());
      }
      return 0;
    }
    case VIDIOC_G_PARM:
    case VIDIOC_S_PARM: {
      auto* p = static_cast<v4l2_streamparm*>(arg);
      if (p->type != buf_type) return fail(EINVAL);
      if (request == VIDIOC_S_PARM && timeperframe) fps_denominator = p->parm.capture.timeperframe.denominator;
      std::memset(&p->parm, 0, sizeof p->parm);
      p->parm.capture.capability = timeperframe ? V4L2_CAP_TIMEPERFRAME : 0;
      p->parm.capture.timeperframe = {1, fps_denominator == 0 ? 25u : fps_denominator};
      return 0;
    }
    case VIDIOC_QUERYCTRL: {
      auto* q = static_cast<v4l2_queryctrl*>(arg);
      if (!has_exposure || (q->id != V4L2_CID_EXPOSURE_ABSOLUTE && q->id != V4L2_CID_EXPOSURE_AUTO))
        return fail(EINVAL);
      q->minimum = q->id == V4L2_CID_EXPOSURE_AUTO ? 0 : 1;
      q->maximum = q->id == V4L2_CID_EXPOSURE_AUTO ? 3 : 5000;
      q->flags = 0;
      return 0;
    }
    case VIDIOC_G_CTRL:
    case VIDIOC_S_CTRL: {
      auto* c = static_cast<v4l2_control*>(arg);
      if (!has_exposure || (c->id != V4L2_CID_EXPOSURE_ABSOLUTE && c->id != V4L2_CID_EXPOSURE_AUTO))
        return fail(EINVAL);
      if (gone()) return fail(ENODEV);
      if (c->id == V4L2_CID_EXPOSURE_ABSOLUTE) {
        if (request == VIDIOC_S_CTRL) exposure = c->value;
        c->value = exposure;
      }
      return 0;
    }
    case VIDIOC_REQBUFS: {
      auto* r = static_cast<v4l2_requestbuffers*>(arg);
      if (r->type != buf_type || r->memory != V4L2_MEMORY_MMAP) return fail(EINVAL);
      if (streaming || mapped > 0) return fail(EBUSY);
      r->count = r->count == 0 ? 0 : (grant_buffers != 0 ? grant_buffers : r->count);
      memory.assign(r->count, std::vector<std::uint8_t>(frame_bytes()));
      queued.clear();
      return 0;
    }
    case VIDIOC_QUERYBUF:
    case VIDIOC_QBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (b->type != buf_type || b->index >= memory.size()) return fail(EINVAL);
      if (gone()) return fail(ENODEV);
      if (request == VIDIOC_QBUF) {
        if (std::find(queued.begin(), queued.end(), b->index) != queued.end()) return fail(EINVAL);
        queued.push_back(b->index);
        return 0;
      }
      // The mmap offset of buffer i is i * 4096 (any cookie would do).
      const auto offset = static_cast<std::uint32_t>(b->index * 4096u);
      const auto length = static_cast<std::uint32_t>(memory[b->index].size());
      if (multiplanar()) {
        if (b->length < 1) return fail(EINVAL);
        b->length = 1;
        b->m.planes[0].length = length;
        b->m.planes[0].m.mem_offset = offset;
      } else {
        b->length = length;
        b->m.offset = offset;
      }
      return 0;
    }
    case VIDIOC_DQBUF: return dequeue(*static_cast<v4l2_buffer*>(arg));
    case VIDIOC_STREAMON:
    case VIDIOC_STREAMOFF: {
      if (*static_cast<int*>(arg) != static_cast<int>(buf_type)) return fail(EINVAL);
      if (gone()) return fail(ENODEV);
      streaming = request == VIDIOC_STREAMON;
      if (!streaming) queued.clear();
      return 0;
    }
    default: return fail(ENOTTY);
  }
}

void* FakeV4l2Driver::mmap(std::size_t length, int fd, off_t offset) {
  const auto index = static_cast<std::size_t>(offset / 4096);
  if (fd != kFd || offset % 4096 != 0 || index >= memory.size() || length > memory[index].size()) {
    errno = EINVAL;
    return MAP_FAILED;
  }
  ++mapped;
  return memory[index].data();
}

int FakeV4l2Driver::munmap(void* /*addr*/, std::size_t /*length*/) {
  --mapped;
  return 0;
}

int FakeV4l2Driver::poll(pollfd* fds, nfds_t count, int /*timeout_ms*/) {
  if (count != 1 || fds[0].fd != kFd) return fail(EINVAL);
  fds[0].revents = 0;
  if (gone() || poll_error || !streaming || queued.empty()) {
    fds[0].revents = POLLERR;  // what videobuf2 reports in all three cases
    return 1;
  }
  if (shots.empty()) return 0;  // a timeout, without waiting for it
  fds[0].revents = POLLIN;
  return 1;
}

}  // namespace ale::test
