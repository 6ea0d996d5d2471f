#include "core/features/describer.h"

#include "core/features/kernels.h"
#include "core/features/orientation.h"

namespace ale::features {

Describer::Describer() : pattern_(make_brief_pattern()) {}

void Describer::plan(const FramePyramid& pyramid) {
  if (width_ == pyramid.width() && height_ == pyramid.height()) return;
  width_ = pyramid.width();
  height_ = pyramid.height();
  blurred_.assign(pyramid.size(), 0);
  rotated_.build(pattern_, pyramid.stride());
}

void Describer::describe_level(const FramePyramid& pyramid, int level, const std::vector<FastCorner>& corners,
                               std::vector<Keypoint>& keypoints, std::vector<Descriptor>& descriptors) {
  if (corners.empty()) return;
  const GrayView plain = pyramid.plain(level);
  std::uint8_t* const level_blurred = blurred_.data() + pyramid.offset(level);
  // Only around the kept corners: descriptors read nothing else (their rotated samples stay
  // within kPatchRadius), and most of a level is not near one.
  gaussian7_patches(plain, MutableGrayView{level_blurred, plain.width, plain.height, pyramid.stride()}, corners,
                    kPatchRadius, blur_scratch_);
  // Read-only from here: one view for every describe() call, not a conversion per corner.
  const GrayView smoothed{level_blurred, plain.width, plain.height, pyramid.stride()};
  const float scale = static_cast<float>(pyramid.scale(level));
  const auto describe_kernel = kernels().describe;  // describe() without its per-call wrapper
  for (const FastCorner& c : corners) {
    Keypoint kp;
    kp.lx = c.x;
    kp.ly = c.y;
    kp.x = static_cast<float>(c.x) * scale;
    kp.y = static_cast<float>(c.y) * scale;
    kp.level = level;
    kp.score = c.score;
    kp.size = 31.0f * scale;
    kp.angle_deg = ic_angle_deg(plain, c.x, c.y);
    keypoints.push_back(kp);
    descriptors.emplace_back();
    describe_kernel(smoothed, c.x, c.y, rotated_, angle_bin(kp.angle_deg), descriptors.back());
  }
}

}  // namespace ale::features
