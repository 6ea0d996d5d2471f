// The pyramid's downscale (ORB-SLAM resizes each level bilinearly from the one above), in fixed
// point: output pixel (dx, dy) samples the source at sx = (dx + 0.5) * sw / dw - 0.5 (likewise
// sy), rounded to 1/256 pixel: source pixels c0 and c1 = c0 + 1 with weights 256 - w and w
// (w = 0..255); a sample at or right of the last pixel takes the last pixel (c1 = c0, w = 0).
// Specification (pyramid_ref.cpp): vertical pass first, kept at 16 bits:
// row[x] = r0[x] * (256 - wy) + r1[x] * wy, then the horizontal pass, rounded once:
// out = (row[c0] * (256 - wx) + row[c1] * wx + 32768) >> 16. The first pass is exact, so the
// passes commute: the NEON path (pyramid_neon.cpp) runs the horizontal pass first on the 8-bit
// source (vtbl gathers 16 outputs from a 32-pixel window) into 16-bit rows that carry the rounding
// term (+128, times 256 after the vertical weights), keeps the latest such row for the next output
// row (about 1.2 source rows per output row at scale 1.2), and finishes with the vertical pass in
// 32 bits whose byte 2 is the output. This stays within a grey level or two of cv::resize
// (11-bit weights) on a few pixels (test); 7-bit weights and a rounding after each pass cost about
// 0.03 of the graf correct-match share. NEON and SSE2 (pyramid_sse2.cpp) are bit-exact with the
// reference; dispatch through kernels.h.
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

// 16 consecutive outputs from `x` whose samples lie in the 32 source pixels from `base` (a
// window inside the source row). Laid out for vld4 (lane j of d-register r at byte 4 j + r):
// `idx` holds d0, d1 = window byte of c0 for the even, odd outputs and d2, d3 = the same for c1
// (c0 when w = 0), each permuted as vld4 permutes the window (window byte k is table byte
// (k % 4) * 8 + k / 4); `wts` holds w (d0, d1) and 255 - w (d2, d3).
struct ResizeBlock {
  std::uint8_t idx[32] = {};
  std::uint8_t wts[32] = {};
  std::int32_t base = 0;
  std::int32_t step = 0;  // next block's base - base (0 for the last)
  std::int32_t x = 0;
};

struct ResizePlan {
  int src_w = 0, src_h = 0, dst_w = 0, dst_h = 0;
  ResizeAxis xs, ys;
  // Empty when dst_w < 16, src_w < 32 or some 16 outputs span more than 32 source pixels (scale
  // above about 2): the NEON path then runs the reference.
  std::vector<ResizeBlock> blocks;
};

// Sizes >= 1, dst no larger than src in either direction.
void plan_resize(int src_w, int src_h, int dst_w, int dst_h, ResizePlan& plan);

// dst (plan's size, distinct memory) from src (plan's size); `row` is scratch (grown on first use).
void resize_bilinear(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& row,
                     KernelPath path = KernelPath::kAuto);

namespace internal {
// out[x] for x < width from rows r0, r1 with weight wy (0..255) on r1.
void resize_vertical_ref(const std::uint8_t* r0, const std::uint8_t* r1, int width, int wy, std::uint16_t* out);
// out[dx] for dx < plan.dst_w from a vertically resampled row (plan.src_w samples, readable up to
// src_w + 16).
void resize_horizontal_ref(const std::uint16_t* row, const ResizePlan& plan, std::uint8_t* out);
// resize_bilinear()'s kernels: the reference and SSE2 run the two passes per output row
// (resize_rows); NEON the whole image, horizontal pass first (plan.blocks non-empty; else the
// reference), `rows` then being scratch for one 16-bit row of 16 * plan.blocks.size() samples.
using VerticalPass = void (*)(const std::uint8_t*, const std::uint8_t*, int, int, std::uint16_t*);
using HorizontalPass = void (*)(const std::uint16_t*, const ResizePlan&, std::uint8_t*);
void resize_rows(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& row,
                 VerticalPass vertical, HorizontalPass horizontal);
void resize_ref(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& row);
void resize_neon(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& rows);
void resize_sse2(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& row);
void resize_vertical_sse2(const std::uint8_t* r0, const std::uint8_t* r1, int width, int wy, std::uint16_t* out);
void resize_horizontal_sse2(const std::uint16_t* row, const ResizePlan& plan, std::uint8_t* out);
}  // namespace internal

}  // namespace ale::features
