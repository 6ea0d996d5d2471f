// Textures for the renderer: 8-bit albedo maps with a mip chain, sampled trilinearly so that
// distant or grazing surfaces are low-pass filtered the way a lens and pixel would do it, instead
// of aliasing into noise; and the noise primitives the procedural materials are made of.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/image.h"

namespace ale::render {

// An albedo map laid on a surface: texel (0, 0) sits at surface coordinate (0, 0) metres, texel
// size `texel_m` in both directions. Grey 255 is albedo 1.
class Texture {
 public:
  Texture() = default;
  // Builds the mip chain (2x2 box filter, down to 1 texel). `repeat` tiles the map (photographs)
  // instead of clamping at its edges (procedural maps made to the surface's size).
  Texture(GrayImage level0, float texel_m, bool repeat);

  // Albedo in [0, 1] at surface coordinates (u_m, v_m) for a pixel whose footprint on the
  // surface is `footprint_m` wide.
  float sample(float u_m, float v_m, float footprint_m) const;

  int levels() const { return static_cast<int>(levels_.size()); }
  const GrayImage& level(int i) const { return levels_[static_cast<std::size_t>(i)]; }
  float texel_m() const { return texel_m_; }
  bool empty() const { return levels_.empty(); }

 private:
  float bilinear(int level, float x, float y) const;

  std::vector<GrayImage> levels_;
  float texel_m_ = 1.0f;
  float inv_texel_m_ = 1.0f;
  bool repeat_ = false;
};

// Value noise in [0, 1]: random values on the integer lattice, smoothly interpolated.
float value_noise(float x, float y, std::uint32_t seed);
// Sum of `octaves` value-noise layers, each twice the frequency and half the amplitude of the
// previous one, normalised to [0, 1]. x, y in units of the coarsest lattice.
float fractal_noise(float x, float y, int octaves, std::uint32_t seed);

}  // namespace ale::render
