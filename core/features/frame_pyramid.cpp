#include "core/features/frame_pyramid.h"

#include <cmath>

namespace ale::features {

void FramePyramid::configure(int levels, double scale_factor, bool with_enhanced) {
  levels_ = levels;
  with_enhanced_ = with_enhanced;
  scales_[0] = 1.0;
  for (int l = 1; l < levels; ++l)
    scales_[static_cast<std::size_t>(l)] = scales_[static_cast<std::size_t>(l - 1)] * scale_factor;
  width_ = height_ = 0;
}

void FramePyramid::plan(int width, int height) {
  if (width == width_ && height == height_) return;
  stride_ = aligned_stride(width);
  std::size_t offset = 0;
  for (int l = 0; l < levels_; ++l) {
    const std::size_t i = static_cast<std::size_t>(l);
    const int w = static_cast<int>(std::lround(width / scales_[i]));
    const int h = static_cast<int>(std::lround(height / scales_[i]));
    level_w_[i] = w;
    level_h_[i] = h;
    offsets_[i] = offset;
    offset += static_cast<std::size_t>(h) * static_cast<std::size_t>(stride_);
    if (l > 0) plan_resize(level_w_[i - 1], level_h_[i - 1], w, h, resize_plans_[i]);
  }
  pixels_.assign(offset, 0);
  enhanced_.assign(with_enhanced_ ? offset : 0, 0);
  width_ = width;
  height_ = height;
}

void FramePyramid::load(GrayView image) {
  copy_pixels(image, MutableGrayView{pixels_.data(), width_, height_, stride_});
  has_enhanced_.fill(false);
}

void FramePyramid::build() {
  for (int l = 1; l < levels_; ++l)
    resize_bilinear(plain(l - 1), plain(l), resize_plans_[static_cast<std::size_t>(l)], resize_row_);
}

}  // namespace ale::features
