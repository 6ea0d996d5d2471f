// Scalar 7x7 Gaussian: the specification blur_neon.cpp reproduces (definition in blur.h).
#include "core/features/blur.h"

namespace ale::features {

namespace internal {

void blur_vertical_ref(GrayView src, int y, std::uint8_t* vrow) {
  const std::uint8_t* r[7];
  for (int k = 0; k < 7; ++k) r[k] = src.row(y + k - kBlurRadius);
  for (int x = 0; x < src.width; ++x) {
    unsigned s = 128;
    for (int k = 0; k < 7; ++k) s += static_cast<unsigned>(kBlurTaps[k]) * r[k][x];
    vrow[x] = static_cast<std::uint8_t>(s >> 8);
  }
}

void blur_horizontal_ref(const std::uint8_t* vrow, int width, std::uint8_t* out) {
  for (int x = kBlurRadius; x < width - kBlurRadius; ++x) {
    unsigned s = 128;
    for (int k = 0; k < 7; ++k) s += static_cast<unsigned>(kBlurTaps[k]) * vrow[x + k - kBlurRadius];
    out[x] = static_cast<std::uint8_t>(s >> 8);
  }
}

}  // namespace internal

void gaussian7_interior(GrayView src, MutableGrayView dst, std::vector<std::uint8_t>& scratch, FastPath path) {
  if (src.width < 2 * kBlurRadius + 1 || src.height < 2 * kBlurRadius + 1) return;
  if (scratch.size() < static_cast<std::size_t>(src.width)) scratch.resize(static_cast<std::size_t>(src.width));
  if (path == FastPath::kAuto) path = fast_auto_path();
  const bool neon = path == FastPath::kNeon && fast_neon_compiled();
  for (int y = kBlurRadius; y < src.height - kBlurRadius; ++y) {
    if (neon) {
      internal::blur_vertical_neon(src, y, scratch.data());
      internal::blur_horizontal_neon(scratch.data(), src.width, dst.row(y));
    } else {
      internal::blur_vertical_ref(src, y, scratch.data());
      internal::blur_horizontal_ref(scratch.data(), src.width, dst.row(y));
    }
  }
}

}  // namespace ale::features
