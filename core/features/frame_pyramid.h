// The pyramid stage of the frame path: ORB-SLAM's image pyramid (each level resized bilinearly
// from the one above) in one buffer whose levels share a stride, so one table of rotated
// descriptor offsets serves them all; beside it the levels after the per-level CLAHE, which the
// enhancement stage fills where it runs. Buffers are planned for a frame size once; nothing is
// allocated for later frames of that size.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"
#include "core/features/pyramid.h"

namespace ale::features {

constexpr int kMaxLevels = 16;

class FramePyramid {
 public:
  // levels 1..kMaxLevels, scale_factor > 1; with_enhanced: keep a second set of levels for the
  // per-level CLAHE. Forgets the planned size.
  void configure(int levels, double scale_factor, bool with_enhanced);
  // Plans the buffers for width x height unless they already are.
  void plan(int width, int height);
  // Level 0 := image (of the planned size); every level counts as not enhanced again.
  void load(GrayView image);
  // Levels 1.. from level 0 as it is now.
  void build();

  int levels() const { return levels_; }
  int width() const { return width_; }
  int height() const { return height_; }
  int stride() const { return stride_; }
  double scale(int level) const { return scales_[static_cast<std::size_t>(level)]; }
  std::size_t offset(int level) const { return offsets_[static_cast<std::size_t>(level)]; }
  std::size_t size() const { return pixels_.size(); }  // bytes of one set of levels

  // The level before the per-level CLAHE (globally mapped only). Inline: the cell detector asks
  // for levels per cell.
  GrayView plain(int level) const {
    const std::size_t l = static_cast<std::size_t>(level);
    return {pixels_.data() + offsets_[l], level_w_[l], level_h_[l], stride_};
  }
  MutableGrayView plain(int level) {
    const std::size_t l = static_cast<std::size_t>(level);
    return {pixels_.data() + offsets_[l], level_w_[l], level_h_[l], stride_};
  }
  // The level CLAHE's output buffer of `level` (with_enhanced only); mark it used with set_enhanced().
  MutableGrayView enhanced(int level) {
    const std::size_t l = static_cast<std::size_t>(level);
    return {enhanced_.data() + offsets_[l], level_w_[l], level_h_[l], stride_};
  }
  void set_enhanced(int level) { has_enhanced_[static_cast<std::size_t>(level)] = true; }
  bool has_enhanced(int level) const { return has_enhanced_[static_cast<std::size_t>(level)]; }
  // The image FAST runs on: the enhanced level where the level CLAHE ran, else the plain one.
  GrayView image(int level) const {
    const std::size_t l = static_cast<std::size_t>(level);
    if (!has_enhanced_[l]) return plain(level);
    return {enhanced_.data() + offsets_[l], level_w_[l], level_h_[l], stride_};
  }

 private:
  int levels_ = 0;
  bool with_enhanced_ = false;
  std::array<double, kMaxLevels> scales_{};
  int width_ = 0;
  int height_ = 0;
  int stride_ = 0;
  std::array<int, kMaxLevels> level_w_{}, level_h_{};
  std::array<std::size_t, kMaxLevels> offsets_{};
  std::vector<std::uint8_t> pixels_;
  std::vector<std::uint8_t> enhanced_;
  std::array<bool, kMaxLevels> has_enhanced_{};
  std::array<ResizePlan, kMaxLevels> resize_plans_;  // level l from level l - 1 (l >= 1)
  std::vector<std::uint16_t> resize_row_;
};

}  // namespace ale::features
