// A per-frame estimate of the sensor noise, for thresholds that should mean the same
// contrast-to-noise on a raw and on an enhanced frame (docs/features.md, "Noise-aware detection").
#pragma once

#include "core/base/image.h"

namespace ale::enhance {

// The noise standard deviation of `image` in grey levels, by Immerkaer's Laplacian-difference
// operator (1996) N = [1 -2 1; -2 4 -2; 1 -2 1], which cancels intensity that is locally linear:
// for white noise of sigma s, N's response has sigma 6 s. The median of |N| (robust to the edges
// and texture that inflate the mean) over every `row_step`-th interior row, every second column,
// gives s = median / (0.6745 * 6). 0 for images smaller than 3x3. Integer histogram, no
// allocation.
double estimate_noise_sigma(GrayView image, int row_step = 4);

}  // namespace ale::enhance
