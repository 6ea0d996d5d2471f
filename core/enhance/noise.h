// A per-frame estimate of the sensor noise, for thresholds that should mean the same
// contrast-to-noise on a raw and on an enhanced frame (docs/features.md, "Noise-aware detection").
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "core/base/kernel_path.h"

namespace ale::enhance {

// The noise standard deviation of `image` in grey levels, by Immerkaer's Laplacian-difference
// operator (1996) N = [1 -2 1; -2 4 -2; 1 -2 1], which cancels intensity that is locally linear:
// for white noise of sigma s, N's response has sigma 6 s. The median of |N| (robust to the edges
// and texture that inflate the mean) over every `row_step`-th interior row, every second column,
// gives s = median / (0.6745 * 6). 0 for images smaller than 3x3. Integer histogram, no
// allocation.
double estimate_noise_sigma(GrayView image, int row_step = 4);

// The 3x3 binomial [1 2 1]^T [1 2 1] / 16, rounded half up, in place on the interior of `image`
// (its one-pixel border kept). For white noise of sigma s the result has sigma 0.375 s
// (kBinomial3NoiseGain = sqrt(sum of the squared weights)). `rows` and `sums` are scratch (two
// rows of bytes, one of sums), resized as needed. Images under 3x3 are left as they are. `path`
// picks the kernel (core/enhance/kernels.h): the reference or NEON, bit-exact with it.
void binomial3_in_place(MutableGrayView image, std::vector<std::uint8_t>& rows, std::vector<std::uint16_t>& sums,
                        KernelPath path = KernelPath::kAuto);
constexpr double kBinomial3NoiseGain = 0.375;

namespace internal {
// binomial3_in_place's kernels (noise.cpp, noise_neon.cpp); `rows` holds two rows of bytes and
// `sums` one row of 16-bit sums, both at least the image's width, the image at least 3x3. The
// NEON kernel runs the reference on images narrower than 16 pixels.
void binomial3_ref(MutableGrayView image, std::uint8_t* rows, std::uint16_t* sums);
void binomial3_neon(MutableGrayView image, std::uint8_t* rows, std::uint16_t* sums);
}  // namespace internal

}  // namespace ale::enhance
