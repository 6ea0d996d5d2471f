// Procedural materials for the default room. Each painter works on an albedo canvas that covers
// a surface: texel (x, y) is the point (x + 0.5, y + 0.5) * texel_m metres in the surface's (u, v)
// coordinates (v is height above the floor on vertical surfaces). The patterns are chosen to give
// a feature detector what real rooms give it: plank ends and knots, grout-like lines, posters
// with high-contrast blobs, book spines, skirting boards and sockets near the floor; and large
// low-contrast areas (plaster, ceiling) where it should find little.
#pragma once

#include <cstdint>

#include "core/base/image.h"

namespace ale::render {

// A rectangle in surface metres: [u0, u0 + width) x [v0, v0 + height).
struct RectM {
  float u0 = 0, v0 = 0, width = 0, height = 0;
};

// A canvas of ceil(width_m / texel_m) x ceil(height_m / texel_m) texels of albedo `albedo`.
GrayImage make_canvas(float width_m, float height_m, float texel_m, float albedo);

// Painters. `seed` makes each instance different; the same seed paints the same texels.
void paint_plaster(GrayImage& img, float texel_m, float albedo, float contrast, std::uint32_t seed);
void paint_planks(GrayImage& img, float texel_m, std::uint32_t seed);
void paint_rug(GrayImage& img, float texel_m, RectM where, std::uint32_t seed);
void paint_poster(GrayImage& img, float texel_m, RectM where, std::uint32_t seed);
void paint_wood(GrayImage& img, float texel_m, float albedo, std::uint32_t seed);
void paint_fabric(GrayImage& img, float texel_m, float albedo, std::uint32_t seed);
// Shelves of books seen from the front; `shelf_pitch_m` apart, starting at v = 0.
void paint_books(GrayImage& img, float texel_m, float shelf_pitch_m, std::uint32_t seed);
// A framed panel (door, cabinet front): darker frame `frame_m` wide, a handle near one side.
void paint_panel(GrayImage& img, float texel_m, RectM where, float albedo, float frame_m, std::uint32_t seed);
// A wall socket: a light plate with two dark holes.
void paint_socket(GrayImage& img, float texel_m, float u_m, float v_m);
// A flat rectangle of one albedo (skirting boards, lines).
void paint_rect(GrayImage& img, float texel_m, RectM where, float albedo);

}  // namespace ale::render
