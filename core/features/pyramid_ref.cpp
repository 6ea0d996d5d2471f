// Scalar bilinear downscale: the specification pyramid_neon.cpp reproduces (definition in pyramid.h).
#include "core/features/pyramid.h"

#include <algorithm>

#include "core/features/kernels.h"

namespace ale::features {

namespace {

// Integer arithmetic only, so host and ARM builds plan the same samples.
void plan_axis(int src, int dst, ResizeAxis& axis) {
  axis.c0.resize(static_cast<std::size_t>(dst));
  axis.w.resize(static_cast<std::size_t>(dst));
  for (int d = 0; d < dst; ++d) {
    // 256 * sx = 128 * ((2d + 1) src - dst) / dst, rounded half up; >= 0 because src >= dst.
    const std::int64_t num = 128 * (static_cast<std::int64_t>(2 * d + 1) * src - dst);
    const std::int64_t pos = (2 * num + dst) / (2 * static_cast<std::int64_t>(dst));
    int c0 = static_cast<int>(pos >> 8);
    int w = static_cast<int>(pos & 255);
    if (c0 >= src - 1) {
      c0 = src - 1;
      w = 0;
    }
    axis.c0[static_cast<std::size_t>(d)] = c0;
    axis.w[static_cast<std::size_t>(d)] = static_cast<std::uint8_t>(w);
  }
}

}  // namespace

void plan_resize(int src_w, int src_h, int dst_w, int dst_h, ResizePlan& plan) {
  plan.src_w = src_w;
  plan.src_h = src_h;
  plan.dst_w = dst_w;
  plan.dst_h = dst_h;
  plan_axis(src_w, dst_w, plan.xs);
  plan_axis(src_h, dst_h, plan.ys);
  plan.blocks.clear();
  if (dst_w < 16 || src_w < 32) return;
  // vld4 puts window byte k in d-register k % 4, lane k / 4: vtbl4 table byte (k % 4) * 8 + k / 4.
  const auto table_byte = [](int k) { return static_cast<std::uint8_t>((k % 4) * 8 + k / 4); };
  for (int x = 0;; x += 16) {
    if (x > dst_w - 16) x = dst_w - 16;
    ResizeBlock b;
    b.x = x;
    b.base = std::min(plan.xs.c0[static_cast<std::size_t>(x)], src_w - 32);
    for (int i = 0; i < 16; ++i) {
      const int c0 = plan.xs.c0[static_cast<std::size_t>(x + i)];
      const int w = plan.xs.w[static_cast<std::size_t>(x + i)];
      const int rel1 = (w == 0 ? c0 : c0 + 1) - b.base;
      if (rel1 > 31) {
        plan.blocks.clear();
        return;
      }
      // Even outputs in d0 (c0) and d2 (c1), odd ones in d1 and d3.
      const int lane = 4 * (i / 2) + i % 2;
      b.idx[lane] = table_byte(c0 - b.base);
      b.idx[lane + 2] = table_byte(rel1);
      b.wts[lane] = static_cast<std::uint8_t>(w);
      b.wts[lane + 2] = static_cast<std::uint8_t>(255 - w);
    }
    if (!plan.blocks.empty()) plan.blocks.back().step = b.base - plan.blocks.back().base;
    plan.blocks.push_back(b);
    if (x == dst_w - 16) break;
  }
}

namespace internal {

void resize_vertical_ref(const std::uint8_t* r0, const std::uint8_t* r1, int width, int wy, std::uint16_t* out) {
  for (int x = 0; x < width; ++x) out[x] = static_cast<std::uint16_t>(r0[x] * (256 - wy) + r1[x] * wy);
}

void resize_horizontal_ref(const std::uint16_t* row, const ResizePlan& plan, std::uint8_t* out) {
  for (int d = 0; d < plan.dst_w; ++d) {
    const int c = plan.xs.c0[static_cast<std::size_t>(d)];
    const int w = plan.xs.w[static_cast<std::size_t>(d)];
    const int c1 = w == 0 ? c : c + 1;
    out[d] = static_cast<std::uint8_t>((row[c] * (256 - w) + row[c1] * w + 32768) >> 16);
  }
}

void resize_rows(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& row,
                 VerticalPass vertical, HorizontalPass horizontal) {
  if (row.size() < static_cast<std::size_t>(plan.src_w) + 16) row.resize(static_cast<std::size_t>(plan.src_w) + 16);
  for (int d = 0; d < plan.dst_h; ++d) {
    const int c = plan.ys.c0[static_cast<std::size_t>(d)];
    const int wy = plan.ys.w[static_cast<std::size_t>(d)];
    const int c1 = wy == 0 ? c : c + 1;
    vertical(src.row(c), src.row(c1), plan.src_w, wy, row.data());
    horizontal(row.data(), plan, dst.row(d));
  }
}

void resize_ref(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& row) {
  resize_rows(src, dst, plan, row, &resize_vertical_ref, &resize_horizontal_ref);
}

}  // namespace internal

void resize_bilinear(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& row,
                     KernelPath path) {
  kernels(path).resize(src, dst, plan, row);
}

}  // namespace ale::features
