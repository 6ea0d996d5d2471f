// The pyramid's downscale (ORB-SLAM resizes each level bilinearly from the one above), in fixed
// point: output pixel (dx, dy) samples the source at sx = (dx + 0.5) * sw / dw - 0.5 (likewise
// sy), rounded to 1/256 pixel: source pixels c0 and c1 = c0 + 1 with weights 256 - w and w
// (w = 0..255); a sample at or right of the last pixel takes the last pixel (c1 = c0, w = 0).
// Vertical pass first, kept at 16 bits: row[x] = r0[x] * (256 - wy) + r1[x] * wy, then the
// horizontal pass, rounded once: out = (row[c0] * (256 - wx) + row[c1] * wx + 32768) >> 16. This
// stays within a grey level or two of cv::resize (11-bit weights) on a few pixels (test); 7-bit
// weights and a rounding after each pass cost about 0.03 of the graf correct-match share. Scalar
// reference (pyramid_ref.cpp, the specification), NEON (pyramid_neon.cpp, gathers of 8 outputs
// from one 16-sample window) and SSE2 (pyramid_sse2.cpp), bit-exact; dispatch as FAST
// (ALE_FORCE_REF=1).
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "core/features/fast.h"

namespace ale::features {

// One source coordinate per output coordinate: c0 and c0 + 1 are read with weights 256 - w, w
// (c0 alone when w = 0).
struct ResizeAxis {
  std::vector<std::int32_t> c0;
  std::vector<std::uint8_t> w;
};

// 8 consecutive outputs whose samples lie in the 16 source pixels from `base`.
struct ResizeBlock {
  std::int32_t x = 0;     // first output
  std::int32_t base = 0;  // first source pixel of the window
  std::uint8_t bytes[16] = {};  // byte offsets in the window of 16-bit samples: c0 low, c0 high, ...
  std::uint16_t w[8] = {};
};

struct ResizePlan {
  int src_w = 0, src_h = 0, dst_w = 0, dst_h = 0;
  ResizeAxis xs, ys;
  // Empty when some 8 outputs span more than 16 source pixels (scale above about 2) or dst_w < 8:
  // the NEON path then runs the reference horizontal pass.
  std::vector<ResizeBlock> blocks;
};

// Sizes >= 1, dst no larger than src in either direction.
void plan_resize(int src_w, int src_h, int dst_w, int dst_h, ResizePlan& plan);

// dst (plan's size, distinct memory) from src (plan's size); `row` is scratch.
void resize_bilinear(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& row,
                     FastPath path = FastPath::kAuto);

namespace internal {
// out[x] for x < width from rows r0, r1 with weight wy (0..255) on r1.
void resize_vertical_ref(const std::uint8_t* r0, const std::uint8_t* r1, int width, int wy, std::uint16_t* out);
void resize_vertical_neon(const std::uint8_t* r0, const std::uint8_t* r1, int width, int wy, std::uint16_t* out);
// out[dx] for dx < plan.dst_w from a vertically resampled row (plan.src_w samples, readable up to
// src_w + 16).
void resize_horizontal_ref(const std::uint16_t* row, const ResizePlan& plan, std::uint8_t* out);
void resize_horizontal_neon(const std::uint16_t* row, const ResizePlan& plan, std::uint8_t* out);
void resize_vertical_sse2(const std::uint8_t* r0, const std::uint8_t* r1, int width, int wy, std::uint16_t* out);
void resize_horizontal_sse2(const std::uint16_t* row, const ResizePlan& plan, std::uint8_t* out);
}  // namespace internal

}  // namespace ale::features
