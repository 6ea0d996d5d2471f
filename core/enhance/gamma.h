// CDF-driven gamma (spec section 2) as a 256-entry LUT, and applying any 256-entry LUT.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>

#include "core/base/image.h"
#include "core/enhance/grading.h"

namespace ale::enhance {

// gamma = alpha / cdf(cdf_point) clamped to [gamma_min, 1]: a darker frame has a larger CDF at
// the same grey, hence a smaller gamma and a stronger lift. 1 for an empty histogram. With
// p.target_mean > 0: log(target / 255) / log(mean / 255), 1 at or above the target (params.h);
// with p.noise_max > 0 and noise_sigma > 0 (the frame's, before any LUT) the target is lowered
// until noise_sigma * gamma * target / mean <= p.noise_max.
double cdf_gamma(const FrameStats& stats, const GammaParams& p, double noise_sigma = 0.0);

// lut[i] = round(255 * (i / 255)^gamma): monotonic, lut[0] = 0, lut[255] = 255.
void gamma_lut(double gamma, Lut& lut);

// Global histogram equalisation (the article's "HE" comparison; OpenCV's equalizeHist rule in
// integers): lut[i] = round(255 * (cdf(i) - cdf(lo)) / (pixels - cdf(lo))), lo the darkest grey
// present; the identity for an empty or single-grey histogram. Monotonic.
void equalisation_lut(const FrameStats& stats, Lut& lut);

// dst(x, y) = lut[src(x, y)]; dst may be src. Sizes must match.
Status apply_lut(GrayView src, MutableGrayView dst, const Lut& lut);

namespace internal {
// dst = lut[src] (dst may be src; sizes equal, no checks): apply_lut's kernels (gamma_ref.cpp,
// gamma_neon.cpp), also the feature cells' single-tile CLAHE's.
void apply_lut_ref(GrayView src, MutableGrayView dst, const std::uint8_t* lut);
void apply_lut_neon(GrayView src, MutableGrayView dst, const std::uint8_t* lut);

// out[i] = lut[in[i]] for i in [x, width), four pixels per word load and store (about half the
// instructions of a byte loop): the reference, and the NEON kernel's row tail (fewer than 32
// pixels); out may be in.
inline void lut_row_words(const std::uint8_t* in, std::uint8_t* out, int x, int width, const std::uint8_t* lut) {
  for (; x + 4 <= width; x += 4) {
    std::uint32_t q;
    std::memcpy(&q, in + x, 4);
    const std::uint32_t r = std::uint32_t{lut[q & 0xFFu]} | std::uint32_t{lut[(q >> 8) & 0xFFu]} << 8 |
                            std::uint32_t{lut[(q >> 16) & 0xFFu]} << 16 | std::uint32_t{lut[q >> 24]} << 24;
    std::memcpy(out + x, &r, 4);
  }
  for (; x < width; ++x) out[x] = lut[in[x]];
}
}  // namespace internal

}  // namespace ale::enhance
