// The 7x7 Gaussian (sigma 2) the descriptors are computed on, in fixed point: a separable
// binomial-like kernel [18 34 48 56 48 34 18] / 256 (sigma 2 sampled and rounded so it sums to
// 256), vertical pass then horizontal pass, each rounded half up to 8 bits. Only the interior
// [3, w-3) x [3, h-3) is written: keypoints keep kEdgePx from the border and their rotated BRIEF
// samples stay within kPatchRadius + 1 of them, so the 3-pixel border is never read and needs no
// border rule. Scalar reference (blur_ref.cpp, the specification, written so compilers vectorise
// it: on x86 GCC's -O3 vectorisation of it was as fast as a hand-written SSE2 version, so there
// is none) and NEON (blur_neon.cpp), bit-exact; dispatch as FAST (ALE_FORCE_REF=1 forces the
// reference).
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "core/features/fast.h"

namespace ale::features {

constexpr int kBlurRadius = 3;
constexpr std::uint8_t kBlurTaps[2 * kBlurRadius + 1] = {18, 34, 48, 56, 48, 34, 18};

// dst (same size as src, distinct memory) gets the blurred interior; `scratch` is resized to one
// row. Images narrower or shorter than 7 pixels leave dst untouched.
void gaussian7_interior(GrayView src, MutableGrayView dst, std::vector<std::uint8_t>& scratch,
                        FastPath path = FastPath::kAuto);

namespace internal {
// Row y of dst (3 <= y < h-3) from the vertical pass already in `vrow` (full width).
void blur_vertical_ref(GrayView src, int y, std::uint8_t* vrow);
void blur_horizontal_ref(const std::uint8_t* vrow, int width, std::uint8_t* out);
void blur_vertical_neon(GrayView src, int y, std::uint8_t* vrow);
void blur_horizontal_neon(const std::uint8_t* vrow, int width, std::uint8_t* out);
}  // namespace internal

}  // namespace ale::features
