// Scalar bilinear downscale: the specification pyramid_neon.cpp reproduces (definition in pyramid.h).
#include "core/features/pyramid.h"

#include <algorithm>

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
  if (dst_w < 8 || src_w < 2) return;
  for (int x = 0;; x += 8) {
    if (x > dst_w - 8) x = dst_w - 8;
    ResizeBlock b;
    b.x = x;
    b.base = plan.xs.c0[static_cast<std::size_t>(x)];
    for (int i = 0; i < 8; ++i) {
      const int rel = plan.xs.c0[static_cast<std::size_t>(x + i)] - b.base;
      if (rel + 1 > 15) {
        plan.blocks.clear();
        return;
      }
      b.bytes[2 * i] = static_cast<std::uint8_t>(2 * rel);
      b.bytes[2 * i + 1] = static_cast<std::uint8_t>(2 * rel + 1);
      b.w[i] = plan.xs.w[static_cast<std::size_t>(x + i)];
    }
    plan.blocks.push_back(b);
    if (x == dst_w - 8) break;
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

}  // namespace internal

void resize_bilinear(GrayView src, MutableGrayView dst, const ResizePlan& plan, std::vector<std::uint16_t>& row,
                     FastPath path) {
  if (row.size() < static_cast<std::size_t>(plan.src_w) + 16) row.resize(static_cast<std::size_t>(plan.src_w) + 16);
  if (path == FastPath::kAuto) path = fast_auto_path();
  const bool neon = path == FastPath::kNeon && fast_neon_compiled();
  const bool sse2 = path == FastPath::kSse2 && fast_sse2_compiled();
  for (int d = 0; d < plan.dst_h; ++d) {
    const int c = plan.ys.c0[static_cast<std::size_t>(d)];
    const int wy = plan.ys.w[static_cast<std::size_t>(d)];
    const int c1 = wy == 0 ? c : c + 1;
    if (neon) {
      internal::resize_vertical_neon(src.row(c), src.row(c1), plan.src_w, wy, row.data());
      internal::resize_horizontal_neon(row.data(), plan, dst.row(d));
    } else if (sse2) {
      internal::resize_vertical_sse2(src.row(c), src.row(c1), plan.src_w, wy, row.data());
      internal::resize_horizontal_sse2(row.data(), plan, dst.row(d));
    } else {
      internal::resize_vertical_ref(src.row(c), src.row(c1), plan.src_w, wy, row.data());
      internal::resize_horizontal_ref(row.data(), plan, dst.row(d));
    }
  }
}

}  // namespace ale::features
