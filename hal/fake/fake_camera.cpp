#include "hal/fake/fake_camera.h"

#include <utility>

namespace ale::hal {

namespace {
std::size_t frame_bytes(const std::vector<GrayImage>& frames) {
  if (frames.empty()) return 0;
  return static_cast<std::size_t>(aligned_stride(frames[0].width)) * static_cast<std::size_t>(frames[0].height);
}
}  // namespace

FakeCamera::FakeCamera(std::vector<GrayImage> frames, Options options)
    : frames_(std::move(frames)),
      options_(options),
      pool_("fake camera frames", frame_bytes(frames_), static_cast<std::size_t>(options.buffers)),
      lent_(static_cast<std::size_t>(options.buffers)) {}

Status FakeCamera::start() {
  for (const GrayImage& f : frames_)
    if (f.width != frames_[0].width || f.height != frames_[0].height)
      return invalid_argument("fake camera: frames of different sizes");
  started_ = true;
  return {};
}

Status FakeCamera::stop() {
  started_ = false;
  return {};
}

Status FakeCamera::acquire(Frame& frame, int /*timeout_ms*/) {
  if (!started_) return invalid_argument("fake camera: acquire before start");
  if (options_.vanish_after >= 0 && next_ >= static_cast<std::size_t>(options_.vanish_after)) {
    ++stats_.errors;
    return unavailable("fake camera: device vanished");
  }
  if (next_ >= frames_.size()) return end_of_stream("fake camera: no more frames");
  std::size_t slot = 0;
  while (slot < lent_.size() && !lent_[slot].empty()) ++slot;
  if (slot == lent_.size()) return out_of_memory("fake camera: every buffer is lent out");
  const GrayImage& src = frames_[next_];
  Result<PooledImage> img = PooledImage::create(pool_, src.width, src.height);
  if (!img.ok()) return img.status();
  copy_pixels(src.view(), img->view());
  lent_[slot] = std::move(*img);
  frame.image = lent_[slot].view();
  frame.timestamp_ns = static_cast<std::int64_t>(next_) * options_.period_ns;
  frame.sequence = next_;
  frame.exposure_us.reset();
  frame.buffer_index = static_cast<int>(slot);
  ++next_;
  ++stats_.delivered;
  return {};
}

Status FakeCamera::release(const Frame& frame) {
  if (frame.buffer_index < 0 || static_cast<std::size_t>(frame.buffer_index) >= lent_.size() ||
      lent_[static_cast<std::size_t>(frame.buffer_index)].empty())
    return invalid_argument("fake camera: release of a frame that is not lent out");
  lent_[static_cast<std::size_t>(frame.buffer_index)].reset();
  return {};
}

}  // namespace ale::hal
