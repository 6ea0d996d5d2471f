#include "app/tools/lib/render/materials.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "app/tools/lib/render/rng.h"
#include "app/tools/lib/render/texture.h"

namespace ale::render {

namespace {

constexpr float kTwoPi = 6.28318531f;

std::uint8_t to_texel(float albedo) {
  return static_cast<std::uint8_t>(std::clamp(albedo * 255.0f + 0.5f, 0.0f, 255.0f));
}

void set(GrayImage& img, int x, int y, float albedo) {
  img.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) + static_cast<std::size_t>(x)] =
      to_texel(albedo);
}

// Calls fn(x, y, u_m, v_m) for every texel whose centre lies in `r` (clipped to the canvas).
template <class Fn>
void for_texels(GrayImage& img, float texel_m, RectM r, Fn fn) {
  const int x0 = std::max(0, static_cast<int>(std::ceil(r.u0 / texel_m - 0.5f)));
  const int y0 = std::max(0, static_cast<int>(std::ceil(r.v0 / texel_m - 0.5f)));
  const int x1 = std::min(img.width, static_cast<int>(std::ceil((r.u0 + r.width) / texel_m - 0.5f)));
  const int y1 = std::min(img.height, static_cast<int>(std::ceil((r.v0 + r.height) / texel_m - 0.5f)));
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      fn(x, y, (static_cast<float>(x) + 0.5f) * texel_m, (static_cast<float>(y) + 0.5f) * texel_m);
}

RectM whole(const GrayImage& img, float texel_m) {
  return {0.0f, 0.0f, static_cast<float>(img.width) * texel_m, static_cast<float>(img.height) * texel_m};
}

float range(SplitMix64& g, float lo, float hi) { return lo + (hi - lo) * g.uniform(); }

}  // namespace

GrayImage make_canvas(float width_m, float height_m, float texel_m, float albedo) {
  const int w = std::max(1, static_cast<int>(std::ceil(width_m / texel_m)));
  const int h = std::max(1, static_cast<int>(std::ceil(height_m / texel_m)));
  return GrayImage(w, h, to_texel(albedo));
}

void paint_rect(GrayImage& img, float texel_m, RectM where, float albedo) {
  for_texels(img, texel_m, where, [&](int x, int y, float, float) { set(img, x, y, albedo); });
}

void paint_plaster(GrayImage& img, float texel_m, float albedo, float contrast, std::uint32_t seed) {
  for_texels(img, texel_m, whole(img, texel_m), [&](int x, int y, float u, float v) {
    const float coarse = fractal_noise(u * 1.5f, v * 1.5f, 4, seed) - 0.5f;
    const float grain = value_noise(u * 400.0f, v * 400.0f, seed + 101u) - 0.5f;
    set(img, x, y, albedo + contrast * coarse + 0.25f * contrast * grain);
  });
}

void paint_planks(GrayImage& img, float texel_m, std::uint32_t seed) {
  constexpr float kPlankWidth = 0.14f;
  constexpr float kGap = 0.0025f;
  const RectM all = whole(img, texel_m);
  const int rows = static_cast<int>(std::ceil(all.height / kPlankWidth)) + 1;
  // Plank ends per row, staggered; each plank has its own tone and grain phase.
  struct Plank {
    float end, tone, phase;
    bool knot;
    float knot_u, knot_v, knot_r;
  };
  std::vector<std::vector<Plank>> planks(static_cast<std::size_t>(rows));
  SplitMix64 g(seed);
  for (auto& row : planks) {
    float u = -range(g, 0.0f, 1.2f);
    while (u < all.width) {
      Plank p{};
      const float start = u;
      u += range(g, 0.7f, 1.6f);
      p.end = u;
      p.tone = range(g, 0.24f, 0.60f);
      p.phase = range(g, 0.0f, 100.0f);
      p.knot = g.uniform() < 0.45f;
      p.knot_u = range(g, start + 0.1f, u - 0.1f);
      p.knot_v = range(g, 0.03f, kPlankWidth - 0.03f);
      p.knot_r = range(g, 0.006f, 0.016f);
      row.push_back(p);
    }
  }
  for_texels(img, texel_m, all, [&](int x, int y, float u, float v) {
    const int r = std::min(rows - 1, static_cast<int>(v / kPlankWidth));
    const float vl = v - static_cast<float>(r) * kPlankWidth;
    const auto& row = planks[static_cast<std::size_t>(r)];
    std::size_t i = 0;
    while (i + 1 < row.size() && row[i].end <= u) ++i;
    const Plank& p = row[i];
    if (vl < kGap || p.end - u < kGap) {
      set(img, x, y, 0.05f);
      return;
    }
    const float warp = 2.0f * fractal_noise(u * 1.2f + p.phase, vl * 12.0f, 3, seed + 7u);
    const float grain = std::sin(kTwoPi * (vl / 0.009f + warp));
    float a = p.tone * (1.0f + 0.22f * grain) + 0.05f * (value_noise(u * 300.0f, v * 60.0f, seed + 9u) - 0.5f);
    if (p.knot) {
      const float du = (u - p.knot_u) / (2.2f * p.knot_r);
      const float dv = (vl - p.knot_v) / p.knot_r;
      const float d2 = du * du + dv * dv;
      if (d2 < 1.0f) a *= 0.35f + 0.4f * d2;
    }
    set(img, x, y, a);
  });
}

void paint_rug(GrayImage& img, float texel_m, RectM where, std::uint32_t seed) {
  constexpr float kBorder = 0.12f;
  constexpr float kCell = 0.24f;
  const float levels[4] = {0.12f, 0.62f, 0.30f, 0.82f};
  for_texels(img, texel_m, where, [&](int x, int y, float u, float v) {
    const float lu = u - where.u0;
    const float lv = v - where.v0;
    const float edge = std::min(std::min(lu, where.width - lu), std::min(lv, where.height - lv));
    const float fibre = 0.07f * (value_noise(u * 700.0f, v * 700.0f, seed) - 0.5f);
    float a;
    if (edge < kBorder) {
      a = (edge > 0.04f && edge < 0.07f) ? 0.75f : 0.18f;
    } else {
      // Concentric diamonds per cell: sharp-cornered, high-contrast rings.
      const float cu = lu / kCell - std::floor(lu / kCell) - 0.5f;
      const float cv = lv / kCell - std::floor(lv / kCell) - 0.5f;
      const float d = std::fabs(cu) + std::fabs(cv);
      const int ring = static_cast<int>(d * 6.0f);
      const int cell = static_cast<int>(std::floor(lu / kCell)) + 3 * static_cast<int>(std::floor(lv / kCell));
      a = levels[static_cast<std::size_t>((ring + cell) & 3)];
    }
    set(img, x, y, a + fibre);
  });
}

void paint_poster(GrayImage& img, float texel_m, RectM where, std::uint32_t seed) {
  SplitMix64 g(seed);
  struct Blob {
    float u, v, ru, rv, albedo;
  };
  std::vector<Blob> blobs;
  const int count = 10 + static_cast<int>(g.next() % 14);
  const float size = std::min(where.width, where.height);
  for (int i = 0; i < count; ++i) {
    Blob b{};
    b.u = range(g, 0.1f, 0.9f) * where.width;
    b.v = range(g, 0.1f, 0.9f) * where.height;
    b.ru = range(g, 0.03f, 0.16f) * size;
    b.rv = b.ru * range(g, 0.5f, 1.8f);
    b.albedo = (g.uniform() < 0.7f) ? range(g, 0.03f, 0.2f) : range(g, 0.45f, 0.7f);
    blobs.push_back(b);
  }
  const float frame = 0.012f;
  const float bg = range(g, 0.78f, 0.92f);
  for_texels(img, texel_m, where, [&](int x, int y, float u, float v) {
    const float lu = u - where.u0;
    const float lv = v - where.v0;
    const float edge = std::min(std::min(lu, where.width - lu), std::min(lv, where.height - lv));
    if (edge < frame) {
      set(img, x, y, 0.05f);
      return;
    }
    float a = bg;
    for (const Blob& b : blobs) {
      const float du = (lu - b.u) / b.ru;
      const float dv = (lv - b.v) / b.rv;
      const float d2 = du * du + dv * dv;
      if (d2 < 1.0f) a = b.albedo;
    }
    set(img, x, y, a);
  });
}

void paint_wood(GrayImage& img, float texel_m, float albedo, std::uint32_t seed) {
  for_texels(img, texel_m, whole(img, texel_m), [&](int x, int y, float u, float v) {
    const float warp = 1.5f * fractal_noise(u * 2.0f, v * 10.0f, 3, seed);
    const float grain = std::sin(kTwoPi * (v / 0.012f + warp));
    set(img, x, y, albedo * (1.0f + 0.15f * grain) + 0.03f * (value_noise(u * 250.0f, v * 80.0f, seed + 3u) - 0.5f));
  });
}

void paint_fabric(GrayImage& img, float texel_m, float albedo, std::uint32_t seed) {
  for_texels(img, texel_m, whole(img, texel_m), [&](int x, int y, float u, float v) {
    const float weave = (((x / 2) + (y / 2)) & 1) ? 0.02f : -0.02f;
    const float blotch = 0.14f * (fractal_noise(u * 4.0f, v * 4.0f, 4, seed) - 0.5f);
    // Seams between cushions.
    const float seam = std::fabs(u / 0.65f - std::round(u / 0.65f)) * 0.65f < 0.004f ? -0.12f : 0.0f;
    set(img, x, y, albedo + weave + blotch + seam);
  });
}

void paint_books(GrayImage& img, float texel_m, float shelf_pitch_m, std::uint32_t seed) {
  const RectM all = whole(img, texel_m);
  SplitMix64 g(seed);
  constexpr float kBoard = 0.025f;
  for (float base = 0.0f; base < all.height; base += shelf_pitch_m) {
    paint_rect(img, texel_m, {0.0f, base, all.width, kBoard}, 0.45f);
    // The shelf's dark interior, then the books standing on the board.
    const float interior = std::min(shelf_pitch_m - kBoard, all.height - base - kBoard);
    paint_rect(img, texel_m, {0.0f, base + kBoard, all.width, interior}, 0.06f);
    float u = range(g, 0.0f, 0.05f);
    while (u < all.width - 0.03f) {
      const float w = range(g, 0.018f, 0.055f);
      if (g.uniform() < 0.12f) {  // a gap in the row
        u += w;
        continue;
      }
      const float h = range(g, 0.55f, 0.9f) * interior;
      const float a = range(g, 0.08f, 0.85f);
      paint_rect(img, texel_m, {u, base + kBoard, std::min(w, all.width - u), h}, a);
      // A label band on some spines.
      if (g.uniform() < 0.5f)
        paint_rect(img, texel_m, {u + 0.15f * w, base + kBoard + 0.6f * h, 0.7f * w, 0.08f * h}, 1.0f - a);
      u += w + 0.002f;
    }
  }
}

void paint_panel(GrayImage& img, float texel_m, RectM where, float albedo, float frame_m, std::uint32_t seed) {
  for_texels(img, texel_m, where, [&](int x, int y, float u, float v) {
    const float lu = u - where.u0;
    const float lv = v - where.v0;
    const float edge = std::min(std::min(lu, where.width - lu), std::min(lv, where.height - lv));
    const float grain = 0.04f * (fractal_noise(u * 3.0f, v * 25.0f, 3, seed) - 0.5f);
    float a = albedo + grain;
    if (edge < frame_m) a = 0.8f * albedo + grain;
    if (edge > frame_m && edge < frame_m + 0.006f) a = 0.35f * albedo;  // the groove
    set(img, x, y, a);
  });
  // Handle: a small dark bar near the right edge at hand height (or mid-height for low panels).
  const float hv = where.v0 + std::min(0.95f, 0.5f * where.height);
  paint_rect(img, texel_m, {where.u0 + where.width - frame_m - 0.05f, hv - 0.06f, 0.018f, 0.12f}, 0.05f);
}

void paint_socket(GrayImage& img, float texel_m, float u_m, float v_m) {
  paint_rect(img, texel_m, {u_m - 0.04f, v_m - 0.04f, 0.08f, 0.08f}, 0.88f);
  paint_rect(img, texel_m, {u_m - 0.04f, v_m - 0.04f, 0.08f, 0.004f}, 0.45f);  // the plate's shadow
  paint_rect(img, texel_m, {u_m - 0.016f, v_m - 0.004f, 0.008f, 0.008f}, 0.05f);
  paint_rect(img, texel_m, {u_m + 0.008f, v_m - 0.004f, 0.008f, 0.008f}, 0.05f);
}

}  // namespace ale::render
