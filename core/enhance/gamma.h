// CDF-driven gamma (spec section 2) as a 256-entry LUT, and applying any 256-entry LUT.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>

#include "core/base/image.h"
#include "core/enhance/grading.h"

namespace ale::enhance {

// gamma = alpha / cdf(cdf_point) clamped to [gamma_min, 1]: a darker frame has a larger CDF at
// the same grey, hence a smaller gamma and a stronger lift. 1 for an empty histogram.
double cdf_gamma(const FrameStats& stats, const GammaParams& p);

// lut[i] = round(255 * (i / 255)^gamma): monotonic, lut[0] = 0, lut[255] = 255.
void gamma_lut(double gamma, Lut& lut);

// dst(x, y) = lut[src(x, y)]; dst may be src. Sizes must match.
Status apply_lut(GrayView src, MutableGrayView dst, const Lut& lut);

// out[x] = lut[in[x]] for x < width (out may be in). Shared by apply_lut and the feature cells'
// CLAHE. With NEON, 32 pixels a step through eight 32-byte table look-ups (vtbl/vtbx): about 2.1
// ARM instructions a pixel against 3.75 for the scalar word-wise loop, which does the last
// pixels (and everything without NEON).
void lut_row(const std::uint8_t* in, std::uint8_t* out, int width, const std::uint8_t* lut);

}  // namespace ale::enhance
