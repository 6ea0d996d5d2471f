// Frame statistics and brightness grading (spec section 1) with hysteresis.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

#include "core/base/frame_state.h"
#include "core/base/image.h"
#include "core/enhance/params.h"

namespace ale::enhance {

struct FrameStats {
  std::array<std::uint32_t, 256> histogram{};
  std::uint64_t pixels = 0;
  double mean = 0.0;
  double sigma = 0.0;  // population standard deviation
  int median = 0;      // smallest grey whose CDF reaches one half
};

// One pass over the pixels; the rest comes from the histogram.
void compute_stats(GrayView image, FrameStats& out);
// pixels, mean, sigma and median from out.histogram (what compute_stats() does after counting).
void stats_from_histogram(FrameStats& out);

// Only the pixel count, mean, sigma (the same values compute_stats() gives, from the same integer
// sums) and minimum, without a histogram: what grading and the feature cells' retry bound need,
// at a fraction of the cost (NEON sums).
struct Moments {
  std::uint64_t pixels = 0;
  double mean = 0.0;
  double sigma = 0.0;
  int min = 0;  // smallest grey (0 for an empty image)
};
Moments compute_moments(GrayView image);
// Mean and sigma from the pixel count and the sums of grey values and their squares: the one place
// they are computed, so that every routine with the same sums gives identical doubles. Sums that
// fit 32 bits may come as std::uint32_t (the same doubles; on ARM a 64-bit conversion to double is
// a library call).
template <typename Sum>
Moments moments_from_sums(Sum n, Sum sum, Sum sum_sq) {
  Moments m;
  m.pixels = n;
  if (n == 0) return m;
  const double dn = static_cast<double>(n);
  m.mean = static_cast<double>(sum) / dn;
  m.sigma = std::sqrt(std::max(0.0, static_cast<double>(sum_sq) / dn - m.mean * m.mean));
  return m;
}

namespace internal {
// compute_moments()'s kernels (grading_ref.cpp, grading_neon.cpp), and the NEON kernel for images
// of at most 66,051 pixels (the feature cells), whose sums fit 32 bits.
Moments moments_ref(GrayView image);
Moments moments_neon(GrayView image);
Moments small_moments_neon(GrayView image);
// moments_from_sums() with the minimum (0 for an empty image).
template <typename Sum>
Moments moments_with_min(Sum n, Sum sum, Sum sum_sq, std::uint8_t low) {
  Moments m = moments_from_sums(n, sum, sum_sq);
  m.min = n == 0 ? 0 : low;
  return m;
}
}  // namespace internal

using Lut = std::array<std::uint8_t, 256>;

// Stats of lut[image] derived from the stats of image, without touching pixels.
void remap_stats(const FrameStats& stats, const Lut& lut, FrameStats& out);

// The class of a mean by the thresholds alone (no memory).
BrightnessClass classify(double mean, const GradingParams& p);

// Grades a stream of frames: the first frame by classify(), later ones keep the held class until
// the mean passes a threshold by `hysteresis` grey levels, so a mean wobbling around a threshold
// does not switch the treatment (and the look descriptors are matched on) every frame.
class BrightnessGrader {
 public:
  explicit BrightnessGrader(const GradingParams& p = {}) : params_(p) {}
  BrightnessClass update(double mean);
  void reset() { held_.reset(); }
  // New thresholds from the next frame on; the held class stays (a reload is not a new sequence).
  void set_params(const GradingParams& p) { params_ = p; }
  std::optional<BrightnessClass> held() const { return held_; }

 private:
  GradingParams params_;
  std::optional<BrightnessClass> held_;
};

}  // namespace ale::enhance
