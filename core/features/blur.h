// The 7x7 Gaussian (sigma 2) the descriptors are computed on, in fixed point: a separable
// binomial-like kernel [18 34 48 56 48 34 18] / 256 (sigma 2 sampled and rounded so it sums to
// 256), vertical pass then horizontal pass, each rounded half up to 8 bits. Only the interior
// [3, w-3) x [3, h-3) is ever written: keypoints keep kEdgePx from the border and their rotated
// BRIEF samples stay within kPatchRadius of them, so the 3-pixel border is never read and needs no
// border rule.
//
// gaussian7_interior() blurs the whole interior; gaussian7_patches() only the pixels the
// descriptors of a list of keypoints read (about 63 % of the interior of a level for a normal
// frame at 1000 keypoints over 8 levels), in rectangles within runs of 16-pixel column blocks by
// 8-row groups, each trimmed to the columns needed.
//
// Scalar reference (blur_ref.cpp, the specification, written so compilers vectorise it: on x86
// GCC's -O3 vectorisation of it was as fast as a hand-written SSE2 version, so there is none) and
// NEON (blur_neon.cpp), bit-exact; dispatch through kernels.h.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "core/features/fast.h"

namespace ale::features {

constexpr int kBlurRadius = 3;
constexpr std::uint8_t kBlurTaps[2 * kBlurRadius + 1] = {18, 34, 48, 56, 48, 34, 18};
// gaussian7_patches()'s marking grid, anchored at the interior's corner (3, 3).
constexpr int kBlurBlockPx = 16;
constexpr int kBlurGroupRows = 8;

// dst (same size as src, distinct memory) gets the blurred interior; `scratch` is resized to two
// rows. Images narrower or shorter than 7 pixels leave dst untouched.
void gaussian7_interior(GrayView src, MutableGrayView dst, std::vector<std::uint8_t>& scratch,
                        KernelPath path = KernelPath::kAuto);

struct BlurScratch {
  std::vector<std::uint8_t> rows;   // two vertical-pass rows
  std::vector<std::uint16_t> marks;  // needed columns of each 16-pixel block of each 8-row group
};

// Like gaussian7_interior(), but dst is only guaranteed to hold the blurred value at the interior
// pixels within `radius` (Chebyshev distance) of a centre; other interior pixels may or may not be
// written (some of the 16 x 8 cells that hold such pixels are: each run of such cells along a row
// of cells, from its first needed column to its last), the border is not. Buffers
// grow on the first call for an image size and are reused after.
void gaussian7_patches(GrayView src, MutableGrayView dst, const std::vector<FastCorner>& centres, int radius,
                       BlurScratch& scratch, KernelPath path = KernelPath::kAuto);

namespace internal {
// dst over `rect` (inside the interior), reading src over `rect` grown by 3 on every side.
// `scratch` holds 2 * (width + 32) bytes.
void blur_rect_ref(GrayView src, MutableGrayView dst, PixelRect rect, std::uint8_t* scratch);
void blur_rect_neon(GrayView src, MutableGrayView dst, PixelRect rect, std::uint8_t* scratch);
}  // namespace internal

}  // namespace ale::features
